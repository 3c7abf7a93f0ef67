// Exact agreement of two accelerators that share every primitive test (the kd-tree and brute
// force): the same hit or miss, the same distance to the bit, the same primitive unless another
// one ties at that distance, and the same occlusion answers. For tests and the scene fuzzer
// (tests/fuzz/scene_fuzzer.cpp), so it reports instead of asserting.
#pragma once

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

/// The first ray on which `tested` and `reference` disagree, described; nullopt when they agree on
/// every ray.
inline std::optional<std::string> firstDisagreement(const Accelerator& tested,
                                                    const Accelerator& reference,
                                                    const std::vector<Ray>& rays) {
    for (const Ray& ray : rays) {
        std::optional<Hit> a = tested.intersect(ray, kInfinity);
        std::optional<Hit> b = reference.intersect(ray, kInfinity);
        // A different primitive is a tie only at the same distance, which `t` compares.
        bool same = a.has_value() == b.has_value() && (!a || a->t == b->t);
        // Occlusion before the hit, at it (exclusive) and past it; anywhere for a miss.
        float tHit = b ? b->t : kInfinity;
        for (float tMax : {0.5f * tHit, tHit, std::nextafter(tHit, kInfinity), kInfinity})
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
