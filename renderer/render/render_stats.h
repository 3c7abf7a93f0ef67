// What a render cost and how accurate it is: time per phase, rays, passes, the error estimate, why
// it stopped, and the memory each part held.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/built_parts.h"
#include "render/stopping.h"

namespace caustic {

/// Bytes held by each part of a render, at its end. A part the scene and integrator do not need
/// is never built and shows zero.
struct MemoryStats {
    size_t geometry = 0;     ///< Primitive tables, spheres and quads.
    size_t meshes = 0;       ///< Triangle vertex and index arrays.
    size_t accelerator = 0;  ///< The intersection structure (Embree: the buffers we hand it).
    size_t film = 0;         ///< Pass accumulators and the pass buffer.
    size_t lightTables = 0;  ///< Light selection by power and the emitter index.
    size_t photonMaps = 0;   ///< Photon maps, for the photon-mapping integrators.
    /// Image textures' tiles held in the texture cache at the end (at most its bound, which a
    /// worker's renders share).
    size_t textures = 0;
    size_t total() const {
        return geometry + meshes + accelerator + film + lightTables + photonMaps + textures;
    }
    nlohmann::json toJson() const;
};

/// What a render cost and how accurate it is.
struct RenderStats {
    double setupSeconds = 0;        ///< acceleratorSeconds + integratorSeconds.
    double acceleratorSeconds = 0;  ///< Building the intersection structure.
    double integratorSeconds = 0;   ///< Preparing the integrator (photon tracing, for example).
    double renderSeconds = 0;       ///< The passes, pass setup included.
    double passSetupSeconds = 0;    ///< Of renderSeconds, preparing passes (photon tracing).
    double totalSeconds = 0;
    uint64_t rays = 0;         ///< Every ray traced: camera, bounce and shadow.
    uint64_t samples = 0;      ///< Camera samples taken (pixels x spp reached).
    double raysPerSecond = 0;  ///< rays / renderSeconds.
    int passes = 0;
    int sppReached = 0;
    double relativeError = 0;  ///< Film::relativeError(); NaN with fewer than 2 passes.
    /// Its parts (Film::relativeNoise, relativeBias): the bias is 0 for an unbiased integrator.
    double relativeNoise = 0, relativeBias = 0;
    uint64_t droppedSamples = 0;  ///< NaN or infinite samples left out.
    uint64_t clampedValues = 0;   ///< Pass values beyond the film's range (Film::clampedValues).
    int threads = 0;
    StopReason stopReason = StopReason::Spp;
    MemoryStats memory;
    /// What the scene built because it uses it (environment distribution, texture system,
    /// tangent frames, light tables), with its time and bytes, when it was loaded.
    std::vector<BuiltPart> built;
    nlohmann::json toJson() const;
    nlohmann::json builtJson() const;
};

}  // namespace caustic
