// The integrators by name: the one place that knows every integrator and the settings each takes,
// so that integrators/ never reads the render settings (render/ builds integrators, not the
// reverse).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "integrators/integrator.h"

namespace caustic {

struct RenderSettings;

/// The integrator names `createIntegrator` accepts.
const std::vector<std::string>& integratorNames();

/// Whether the error estimated from the pass variance misses part of the integrator's error: the
/// photon mappers' bias, which every pass shares (photon) or which shrinks pass by pass (ppm, and
/// path with photon-mapped caustics or indirect light); docs/study/README.md measures it.
inline bool errorExcludesBias(const std::string& integrator, bool pathPhotonMaps) {
    return integrator == "photon" || integrator == "ppm" ||
           (integrator == "path" && pathPhotonMaps);
}

/// Creates the integrator `settings.integrator`, with its own settings, for a scene and
/// accelerator that outlive it. Throws InputError (path "/settings/integrator") for an unknown
/// name, listing the valid ones.
std::unique_ptr<Integrator> createIntegrator(const Scene& scene, const Accelerator& accel,
                                             const RenderSettings& settings);

}  // namespace caustic
