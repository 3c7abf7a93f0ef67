// The general render settings that integrators and photon tracing read.
#pragma once

#include <cstdint>

namespace caustic {

/// The general render settings that integrators read, as Tungsten's TraceSettings: path length,
/// and the seed and threads of an integrator's own per-pass work (photon tracing). RenderSettings
/// derives from it, so each is stored once; integrators take it beside their own Settings.
struct TraceSettings {
    int maxDepth = 16;  ///< Most scattering events on a path (1: direct light only).
    uint64_t seed = 0;  ///< Same scene, settings and seed: the same image.
    int threads = 0;    ///< Worker threads; 0 uses every core.
};

}  // namespace caustic
