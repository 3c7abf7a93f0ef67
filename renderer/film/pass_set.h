// The passes a film holds: disjoint half-open ranges of pass indices, so that films rendered
// anywhere merge into the film of their union and no pass is ever counted twice.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace caustic {

class PassSet {
public:
    using Range = std::pair<int, int>;  ///< [first, last)

    /// Whether any pass of [first, last) is held.
    bool overlaps(int first, int last) const;
    /// Adds [first, last); throws std::invalid_argument if a pass of it is held already.
    void insert(int first, int last);
    /// Adds every range of `other`; throws std::invalid_argument (adding nothing) on overlap.
    void insert(const PassSet& other);

    /// Passes held.
    int count() const;
    /// One past the highest pass held; 0 when empty.
    int end() const { return ranges_.empty() ? 0 : ranges_.back().second; }
    /// Whether the set is exactly [0, count()): every pass from the first on, none missing.
    bool isPrefix() const {
        return ranges_.empty() || (ranges_.size() == 1 && ranges_[0].first == 0);
    }
    /// The ranges, sorted, disjoint and not adjacent (adjacent ones are joined).
    const std::vector<Range>& ranges() const { return ranges_; }
    /// "0-39,48-63" (inclusive), or "none".
    std::string toString() const;

    bool operator==(const PassSet&) const = default;

private:
    std::vector<Range> ranges_;
};

}  // namespace caustic
