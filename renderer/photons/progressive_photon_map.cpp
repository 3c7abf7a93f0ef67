#include "photons/progressive_photon_map.h"

#include <algorithm>

namespace caustic {

ProgressivePhotonMap::ProgressivePhotonMap(const Scene& scene, const Accelerator& accel,
                                           const TraceSettings& trace, const Settings& settings)
    : scene_(scene),
      accel_(accel),
      trace_(trace),
      settings_(settings),
      pass_{.radius = settings.firstRadius, .kernel = settings.kernel} {}

PhotonTracingOptions ProgressivePhotonMap::tracingOptions(uint32_t pass,
                                                          const Interrupt* interrupt) const {
    return photonTracingOptions(trace_, settings_.photons, pass,
                                settings_.light == MappedLight::Caustics, interrupt);
}

std::vector<Photon> ProgressivePhotonMap::kept(std::vector<Photon> traced) const {
    // Light sampling accounts for direct light where the indirect map is read.
    if (settings_.light == MappedLight::Indirect)
        std::erase_if(traced, [](const Photon& p) { return p.path == PhotonPath::Direct; });
    return traced;
}

uint64_t ProgressivePhotonMap::beginPass(uint32_t pass, const Interrupt* interrupt) {
    pass_.radius = progressiveRadius(settings_.firstRadius, float(settings_.alpha), pass);
    map_.reset();  // the previous pass's first: peak memory is one pass's
    PhotonTracing traced = tracePhotons(scene_, accel_, tracingOptions(pass, interrupt));
    if (traced.interrupted) return traced.rays;
    map_ = std::make_unique<PhotonMap>(kept(std::move(traced.photons)), settings_.lookup);
    return traced.rays;
}

Color ProgressivePhotonMap::reflected(const SurfaceInteraction& si, const Vec3& wo,
                                      const Material& m, int maxBounces, Color* bias) const {
    thread_local std::vector<Neighbor> scratch;
    PhotonEstimate estimate = pass_;
    estimate.maxBounces = std::min(maxBounces, 255);
    return map_->reflected(si, wo, m, estimate, kAllPhotonPaths, scratch, bias);
}

size_t ProgressivePhotonMap::peakBytes(const Interrupt* interrupt) const {
    PhotonTracingOptions o = tracingOptions(0, interrupt);
    o.photons = std::min<uint64_t>(o.photons, kPilotPhotonPaths);
    PhotonTracing pilot = tracePhotons(scene_, accel_, o);
    const double perPath = double(pilot.photons.size()) / std::max(1.0, double(o.photons));
    return photonPassPeakBytes(double(settings_.photons) * perPath);
}

}  // namespace caustic
