// What a scene built because it uses it (an environment's sampling density, the texture system,
// tangent frames, the light tables), with what each cost: the render's stats list them, so that a
// user sees what a feature costs and that a scene without it pays nothing.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace caustic {

struct BuiltPart {
    std::string part;
    double seconds = 0;
    size_t bytes = 0;
    int count = 0;  ///< How many were built (images, meshes).
};

class BuiltParts {
public:
    /// Adds `seconds`, `bytes` and one to `part`'s entry (made, in first-built order, if new).
    void add(const std::string& part, double seconds, size_t bytes) {
        for (BuiltPart& p : parts_)
            if (p.part == part) {
                p.seconds += seconds;
                p.bytes += bytes;
                ++p.count;
                return;
            }
        parts_.push_back(BuiltPart{part, seconds, bytes, 1});
    }
    const std::vector<BuiltPart>& parts() const { return parts_; }

private:
    std::vector<BuiltPart> parts_;
};

}  // namespace caustic
