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

/// What the code that must treat integrators apart needs to know of one, so that it asks this
/// instead of comparing names.
struct IntegratorTraits {
    const char* name;
    /// Keeps photon maps of its own in every render (photon, ppm: `photons`, `caustic_photons`).
    bool ownsPhotonMaps;
    /// May keep photon maps for parts of the light, as its settings say (path: `caustics` and
    /// `indirect` set to `photon_map`).
    bool photonMapsBySetting;
    /// Its photon maps' radius shrinks pass by pass (ppm), so their bias falls as it renders.
    bool progressive;
};

/// Every integrator, in the order `integratorNames` lists them.
const std::vector<IntegratorTraits>& integratorTraits();
/// The traits of integrator `name`; null for a name that is none.
const IntegratorTraits* findIntegrator(const std::string& name);

/// The integrator names `createIntegrator` accepts.
const std::vector<std::string>& integratorNames();

/// Whether the integrator estimates the bias of its photon maps (Integrator::estimatesBias): the
/// photon mappers, whose bias every pass shares (photon) or shrinks pass by pass (ppm), and path
/// with photon-mapped caustics or indirect light. Their films have the bias layer and their error
/// estimate adds the bias to the noise (film/film.h).
inline bool estimatesBias(const std::string& integrator, bool pathPhotonMaps) {
    const IntegratorTraits* t = findIntegrator(integrator);
    return t && (t->ownsPhotonMaps || (t->photonMapsBySetting && pathPhotonMaps));
}

/// Creates the integrator `settings.integrator`, with its own settings, for a scene and
/// accelerator that outlive it. Throws InputError (path "/settings/integrator") for an unknown
/// name, listing the valid ones.
std::unique_ptr<Integrator> createIntegrator(const Scene& scene, const Accelerator& accel,
                                             const RenderSettings& settings);

}  // namespace caustic
