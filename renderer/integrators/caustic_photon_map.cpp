#include "integrators/caustic_photon_map.h"

#include <algorithm>

namespace caustic {

CausticPhotonMap::CausticPhotonMap(const Scene& scene, const Accelerator& accel,
                                   const TraceSettings& trace,
                                   const PhotonIntegrator::Settings& settings)
    : scene_(scene),
      accel_(accel),
      trace_(trace),
      settings_(settings),
      firstPass_{settings.k, PhotonIntegrator::firstRadius(settings.radius, accel),
                 settings.kernel},
      pass_(firstPass_) {}

uint64_t CausticPhotonMap::beginPass(uint32_t pass, const Interrupt* interrupt) {
    pass_ = firstPass_;
    pass_.radius =
        PhotonIntegrator::progressiveRadius(firstPass_.radius, float(settings_.alpha), pass);
    map_.reset();  // the previous pass's first: peak memory is one pass's
    PhotonTracing traced = tracePhotons(scene_, accel_, tracingOptions(pass, interrupt));
    if (traced.interrupted) return traced.rays;
    map_ = std::make_unique<PhotonMap>(std::move(traced.photons), settings_.lookup);
    return traced.rays;
}

Color CausticPhotonMap::reflected(const SurfaceInteraction& si, const Vec3& wo, const Material& m,
                                  int maxBounces) const {
    thread_local std::vector<Neighbor> scratch;
    PhotonEstimate estimate = pass_;
    estimate.maxBounces = std::min(maxBounces, 255);
    return map_->reflected(si, wo, m, estimate, kAllPhotonPaths, scratch);
}

void CausticPhotonMap::checkMemory(size_t budgetBytes, const Interrupt* interrupt) const {
    PhotonTracingOptions o = tracingOptions(0, interrupt);
    o.photons = std::min<uint64_t>(o.photons, PhotonIntegrator::kPilotPaths);
    PhotonTracing pilot = tracePhotons(scene_, accel_, o);
    const double perPath = double(pilot.photons.size()) / std::max(1.0, double(o.photons));
    PhotonIntegrator::checkPeak(PhotonIntegrator::peakBytes(double(settings_.photons) * perPath),
                                budgetBytes, "/settings/photons");
}

}  // namespace caustic
