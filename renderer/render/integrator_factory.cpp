#include "render/integrator_factory.h"

#include "core/error.h"
#include "integrators/path.h"
#include "integrators/photon.h"
#include "integrators/raycast.h"
#include "integrators/whitted.h"
#include "render/settings.h"

namespace caustic {

const std::vector<IntegratorTraits>& integratorTraits() {
    static const std::vector<IntegratorTraits> traits{
        // name, ownsPhotonMaps, photonMapsBySetting, progressive
        {"raycast", false, false, false}, {"whitted", false, false, false},
        {"path", false, true, false},     {"photon", true, false, false},
        {"ppm", true, false, true},
    };
    return traits;
}

const IntegratorTraits* findIntegrator(const std::string& name) {
    for (const IntegratorTraits& t : integratorTraits())
        if (name == t.name) return &t;
    return nullptr;
}

const std::vector<std::string>& integratorNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const IntegratorTraits& t : integratorTraits()) out.emplace_back(t.name);
        return out;
    }();
    return names;
}

std::unique_ptr<Integrator> createIntegrator(const Scene& scene, const Accelerator& accel,
                                             const RenderSettings& settings) {
    const std::string& name = settings.integrator;
    // The one place that maps names to classes.
    if (name == "raycast") return std::make_unique<RayCastIntegrator>(scene, accel);
    if (name == "whitted") return std::make_unique<WhittedIntegrator>(scene, accel, settings);
    if (name == "path")
        return std::make_unique<PathIntegrator>(scene, accel, settings, settings.path,
                                                settings.photon);
    if (const IntegratorTraits* t = findIntegrator(name); t && t->ownsPhotonMaps)
        return std::make_unique<PhotonIntegrator>(scene, accel, settings, settings.photon,
                                                  t->progressive);
    std::string valid;
    for (const std::string& n : integratorNames()) valid += (valid.empty() ? "" : ", ") + n;
    throw InputError("/settings/integrator",
                     "unknown integrator \"" + name + "\"; valid: " + valid);
}

}  // namespace caustic
