// Photon-mapped caustics for the path tracer: in each pass, `photons` caustic-only photon paths
// (each ends at its first non-specular hit, stored there when every bounce before it was specular:
// the L S+ D paths) fill a map read with that pass's radius, which shrinks with the pass index as
// in progressive photon mapping (Knaus & Zwicker 2011). The path tracer reads the map at every
// non-specular vertex and leaves out the emission it would find from there through specular
// bounces only: the fireflies of a small light seen through glass are replaced by a density
// estimate, whose bias falls pass by pass while the mean of the passes converges (consistent, as
// ppm is). The radius depends only on the pass index, so passes can run on different workers.
#pragma once

#include <memory>
#include <vector>

#include "integrators/photon.h"

namespace caustic {

class CausticPhotonMap {
public:
    /// Reads trace (max_depth, seed, threads) and, of the photon settings, photons, radius (0:
    /// 1/500 of the scene's diagonal), alpha, kernel and lookup.
    CausticPhotonMap(const Scene& scene, const Accelerator& accel, const TraceSettings& trace,
                     const PhotonIntegrator::Settings& settings);

    /// Traces pass `pass`'s photons and builds its map; returns the rays traced. When `interrupt`
    /// asks to stop it returns early, and the pass must be abandoned.
    uint64_t beginPass(uint32_t pass, const Interrupt* interrupt);
    /// Radiance reflected towards wo at si by material m from the caustic photons that landed
    /// after at most `maxBounces` scattering events.
    Color reflected(const SurfaceInteraction& si, const Vec3& wo, const Material& m,
                    int maxBounces) const;

    size_t memoryBytes() const { return map_ ? map_->memoryBytes() : 0; }
    /// Throws InputError at /settings/photons when a pass's map would not fit in `budgetBytes`,
    /// estimated from a pilot tracing of at most PhotonIntegrator::kPilotPaths paths.
    void checkMemory(size_t budgetBytes, const Interrupt* interrupt) const;

private:
    PhotonTracingOptions tracingOptions(uint32_t pass, const Interrupt* interrupt) const {
        return PhotonIntegrator::tracingOptions(trace_, settings_.photons, pass,
                                                /*causticOnly=*/true, interrupt);
    }

    const Scene& scene_;
    const Accelerator& accel_;
    TraceSettings trace_;
    PhotonIntegrator::Settings settings_;
    PhotonEstimate firstPass_;  // the radius of pass 0
    PhotonEstimate pass_;       // this pass's
    std::unique_ptr<PhotonMap> map_;
};

}  // namespace caustic
