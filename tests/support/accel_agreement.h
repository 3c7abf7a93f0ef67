// Agreement of two accelerators that share every primitive test (the kd-tree and brute force): the
// same hit or miss, the same distance up to rounding, the same primitive unless another one ties
// at that distance, and the same occlusion answers. For tests and the fuzz targets
// (tests/fuzz/fuzz_support.h), so it reports instead of asserting.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "accel/accelerator.h"

namespace caustic::testing {

/// "t=... prim=..." or "miss", for messages.
inline std::string describeHit(const std::optional<Hit>& h) {
    if (!h) return "miss";
    char buf[64];
    std::snprintf(buf, sizeof buf, "t=%.9g prim=%u", h->t, h->prim);
    return buf;
}

/// Where a ray crosses a quad's diagonal both of its triangles are hit, a few ulps apart: brute
/// force meets the quad once and keeps the first, the kd-tree may meet it again in another leaf
/// and keep the closer. Distances agree to this fraction of the ray's scale (its distance and
/// origin); measured differences are about 1e-7.
inline constexpr float kDistanceTolerance = 1e-6f;

/// The first ray on which `tested` and `reference` disagree, described; nullopt when they agree on
/// every ray.
inline std::optional<std::string> firstDisagreement(const Accelerator& tested,
                                                    const Accelerator& reference,
                                                    const std::vector<Ray>& rays) {
    for (const Ray& ray : rays) {
        std::optional<Hit> a = tested.intersect(ray, kInfinity);
        std::optional<Hit> b = reference.intersect(ray, kInfinity);
        bool same = a.has_value() == b.has_value();
        // A different primitive at the same distance is a tie.
        if (same && a) {
            float scale = std::max({a->t, b->t, maxComponent(glm::abs(ray.o))});
            same = std::abs(a->t - b->t) <= kDistanceTolerance * scale;
        }
        // Occlusion halfway to the hit and past it; anywhere for a miss.
        std::vector<float> tMaxes{kInfinity};
        if (b) tMaxes.insert(tMaxes.end(), {0.5f * b->t, 2.0f * b->t});
        for (float tMax : tMaxes)
            same = same && tested.occluded(ray, tMax) == reference.occluded(ray, tMax);
        if (same) continue;
        char buf[160];
        std::snprintf(buf, sizeof buf, "o=(%.9g, %.9g, %.9g) d=(%.9g, %.9g, %.9g): ", ray.o.x,
                      ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z);
        return buf + describeHit(a) + " vs " + describeHit(b);
    }
    return std::nullopt;
}

}  // namespace caustic::testing
