// A render's peak memory estimated from counts alone (primitives, mesh vertex and triangle counts,
// resolution, photon budget), without building an accelerator, tracing a photon or loading a
// mesh: what a service checks when it admits a job (DESIGN.md, "Service"). render() checks the
// same limit again from what it has built; the two refuse with the same JSON path.
#pragma once

#include <cstddef>

#include "render/settings.h"
#include "scene/scene.h"

namespace caustic {

/// Bytes by part, as MemoryStats splits them (render/renderer.h).
struct MemoryEstimate {
    size_t geometry = 0;     ///< Primitive tables and mesh arrays: exact from the counts.
    size_t accelerator = 0;  ///< Per-primitive figures measured on the example meshes, see .cpp.
    size_t film = 0;         ///< Exact.
    size_t lightTables = 0;  ///< A bound.
    size_t photonMaps = 0;   ///< A bound on one pass's peak (photon and ppm only), see .cpp.
    size_t textures = 0;     ///< The texture cache's bound, for a scene with image textures.
    /// What is built before the first pass: everything but the photon maps.
    size_t beforePasses() const { return geometry + accelerator + film + lightTables + textures; }
    size_t total() const { return beforePasses() + photonMaps; }
};

/// Bytes of a width x height film as render() counts them before its first pass: per pixel, the
/// sum and sum of squares of the pass estimates in double and the pass buffer in float; with
/// adaptive sampling also the sample map and the film of the pilot, which a range that starts past
/// the pilot renders again (render/sample_map.h). With `bias` (an integrator that estimates its
/// bias), the films' bias layer and the pass buffer's bias half.
size_t filmBytes(int width, int height, bool adaptive = false, bool bias = false);

/// Most photons one photon path stores, in expectation, in a scene (see .cpp for the argument):
/// min(max_depth, 1 / (1 - rho)) with rho the largest scattering weight of a non-specular material;
/// 0 when nothing emits or nothing stores photons.
double storedPhotonsPerPathBound(const Scene& scene, int maxDepth);

/// Estimates the render of `scene` with `settings`. The scene may have been loaded with
/// SceneOptions::countMeshesOnly (its counted meshes are included). Thread-safe.
MemoryEstimate estimateMemory(const Scene& scene, const RenderSettings& settings);

/// Throws InputError naming the setting at fault when the estimate exceeds
/// settings.memory_limit: /settings/memory_limit when the scene, accelerator and film do,
/// /settings/photons or /settings/caustic_photons when the photon maps do.
void checkMemoryEstimate(const Scene& scene, const RenderSettings& settings);

}  // namespace caustic
