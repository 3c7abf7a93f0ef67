// Paging of the stores' lists (jobs, assets): newest first, by a seq cursor.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace caustic::server {

/// Ends a page of rows read newest first with LIMIT limit + 1: the extra row only tells that there
/// is a next page, whose cursor is the seq of the last row kept. Nothing on the last page.
template <class Row>
std::optional<int64_t> trimPage(std::vector<Row>& rows, int limit) {
    if (rows.size() <= size_t(limit)) return std::nullopt;
    rows.pop_back();
    return rows.back().seq;
}

}  // namespace caustic::server
