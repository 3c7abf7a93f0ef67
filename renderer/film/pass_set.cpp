#include "film/pass_set.h"

#include <algorithm>
#include <stdexcept>

namespace caustic {

bool PassSet::overlaps(int first, int last) const {
    for (const Range& r : ranges_)
        if (r.first < last && first < r.second) return true;
    return false;
}

void PassSet::insert(int first, int last) {
    if (first >= last) return;
    if (first < 0) throw std::invalid_argument("negative pass index " + std::to_string(first));
    if (overlaps(first, last))
        throw std::invalid_argument("passes " + std::to_string(first) + "-" +
                                    std::to_string(last - 1) + " overlap the passes held (" +
                                    toString() + ")");
    auto at = std::lower_bound(ranges_.begin(), ranges_.end(), Range{first, last});
    at = ranges_.insert(at, Range{first, last});
    // Join with the neighbours it touches.
    if (at + 1 != ranges_.end() && at->second == (at + 1)->first) {
        at->second = (at + 1)->second;
        ranges_.erase(at + 1);
    }
    if (at != ranges_.begin() && (at - 1)->second == at->first) {
        (at - 1)->second = at->second;
        ranges_.erase(at);
    }
}

void PassSet::insert(const PassSet& other) {
    for (const Range& r : other.ranges_)
        if (overlaps(r.first, r.second))
            throw std::invalid_argument("passes " + other.toString() +
                                        " overlap the passes held (" + toString() + ")");
    for (const Range& r : other.ranges_) insert(r.first, r.second);
}

int PassSet::count() const {
    int n = 0;
    for (const Range& r : ranges_) n += r.second - r.first;
    return n;
}

std::string PassSet::toString() const {
    if (ranges_.empty()) return "none";
    std::string s;
    for (const Range& r : ranges_) {
        // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "-" + std::string.
        if (!s.empty()) s += ',';
        s += std::to_string(r.first);
        if (r.second - r.first > 1) {
            s += '-';
            s += std::to_string(r.second - 1);
        }
    }
    return s;
}

}  // namespace caustic
