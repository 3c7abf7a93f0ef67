// What a material scatters from one direction: the mean of its samples' weights (f |cos| / pdf),
// the directional albedo, and the part of it reflected (wi on wo's side). Normal +z.
#pragma once

#include <cstdint>

#include "core/rng.h"
#include "materials/material.h"

namespace caustic::testing {

struct ScatteredEnergy {
    DVec3 total{0.0}, reflected{0.0};
};

inline ScatteredEnergy scatteredEnergy(const Material& m, const Vec3& wo, int samples,
                                       TransportMode mode, uint64_t seed) {
    const Vec3 n(0.0f, 0.0f, 1.0f);
    Rng rng(seed);
    ScatteredEnergy e;
    for (int i = 0; i < samples; ++i) {
        const Vec2 u(rng.uniform(), rng.uniform());
        const std::optional<BsdfSample> s = m.sample(wo, n, rng.uniform(), u, mode);
        if (!s) continue;
        e.total += DVec3(s->weight);
        if (s->wi.z * wo.z > 0.0f) e.reflected += DVec3(s->weight);
    }
    e.total /= double(samples);
    e.reflected /= double(samples);
    return e;
}

}  // namespace caustic::testing
