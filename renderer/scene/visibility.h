// Ray queries that pass through cut-out surfaces (a material's alpha: Material::cutOut). Without
// an alpha material in the scene they are the accelerator's own queries; with one, each hit on
// an alpha material is tested and, where cut out, the ray goes on from just past it. A blended
// surface is hit with probability alpha, from a number hashed from the ray (pbrt-v4's
// HashFloat(ray.o, ray.d)), so that a ray and its shadow rays agree from pass to pass.
#pragma once

#include <optional>

#include "accel/accelerator.h"
#include "scene/scene.h"

namespace caustic {

/// The most cut-out surfaces a ray passes through; the next one counts as hit.
inline constexpr int kMaxCutOutLayers = 64;

/// The closest hit in (0, tMax) that is not cut out; t is along `ray`. Adds the rays traced past
/// cut-out surfaces to `rays`.
std::optional<Hit> intersectSolid(const Scene& scene, const Accelerator& accel, const Ray& ray,
                                  float tMax, uint64_t& rays);
inline std::optional<Hit> intersectVisible(const Scene& scene, const Accelerator& accel,
                                           const Ray& ray, float tMax, uint64_t& rays) {
    return scene.hasAlpha ? intersectSolid(scene, accel, ray, tMax, rays)
                          : accel.intersect(ray, tMax);
}

/// Whether a surface that is not cut out lies along the ray in (0, tMax).
inline bool occludedVisible(const Scene& scene, const Accelerator& accel, const Ray& ray,
                            float tMax, uint64_t& rays) {
    return scene.hasAlpha ? intersectSolid(scene, accel, ray, tMax, rays).has_value()
                          : accel.occluded(ray, tMax);
}

}  // namespace caustic
