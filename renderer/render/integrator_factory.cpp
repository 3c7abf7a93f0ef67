#include "render/integrator_factory.h"

#include "core/error.h"
#include "integrators/path.h"
#include "integrators/photon.h"
#include "integrators/raycast.h"
#include "integrators/whitted.h"
#include "render/settings.h"

namespace caustic {

const std::vector<std::string>& integratorNames() {
    static const std::vector<std::string> names{"raycast", "whitted", "path", "photon", "ppm"};
    return names;
}

std::unique_ptr<Integrator> createIntegrator(const Scene& scene, const Accelerator& accel,
                                             const RenderSettings& settings) {
    const std::string& name = settings.integrator;
    if (name == "raycast") return std::make_unique<RayCastIntegrator>(scene, accel);
    if (name == "whitted") return std::make_unique<WhittedIntegrator>(scene, accel, settings);
    if (name == "path")
        return std::make_unique<PathIntegrator>(scene, accel, settings, settings.path,
                                                settings.photon);
    if (name == "photon" || name == "ppm")
        return std::make_unique<PhotonIntegrator>(scene, accel, settings, settings.photon,
                                                  /*progressive=*/name == "ppm");
    std::string valid;
    for (const std::string& n : integratorNames()) valid += (valid.empty() ? "" : ", ") + n;
    throw InputError("/settings/integrator",
                     "unknown integrator \"" + name + "\"; valid: " + valid);
}

}  // namespace caustic
