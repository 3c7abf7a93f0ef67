// A progressive photon map for the path tracer: in each pass, `photons` photon paths fill a map
// read with that pass's radius, which shrinks with the pass index as in progressive photon mapping
// (Knaus & Zwicker 2011), so that the bias of the density estimate falls pass by pass while the
// mean of the passes converges (consistent, as ppm is). The radius depends only on the pass index,
// so passes can run on different workers. It holds one of two parts of the light:
//
// - Caustics (L S+ D): caustic-only photon paths, each ending at its first non-specular hit and
//   stored there when every bounce before it was specular. The path tracer reads the map at every
//   non-specular vertex and leaves out the emission it would find from there through specular
//   bounces only: the fireflies of a small light seen through glass become a density estimate.
// - Indirect light (every photon that scattered at least once before it landed): the path tracer
//   reads the map at its second non-specular vertex, beside a light sample there, and ends the
//   path; the first vertex's BSDF sample is a final-gather ray (Jensen 2001, 9.3.3), so the
//   estimate's blur is averaged over the gather's hemisphere.
#pragma once

#include <memory>
#include <vector>

#include "accel/accelerator.h"
#include "core/trace_settings.h"
#include "photons/photon_map.h"
#include "photons/photon_pass.h"
#include "scene/scene.h"

namespace caustic {

/// The part of the light a ProgressivePhotonMap holds: caustics; every photon that scattered
/// before it landed; or every photon, direct ones too (for a path tracer that samples no light).
enum class MappedLight { Caustics, Indirect, All };

class ProgressivePhotonMap {
public:
    struct Settings {
        MappedLight light = MappedLight::Caustics;
        uint64_t photons = 100000;  ///< Photon paths per pass.
        float firstRadius = 0.0f;   ///< Pass 0's radius.
        double alpha = 2.0 / 3.0;
        PhotonKernel kernel = PhotonKernel::Cone;
        PhotonLookup lookup = PhotonLookup::KdTree;
    };

    /// Reads trace's max_depth, seed and threads.
    ProgressivePhotonMap(const Scene& scene, const Accelerator& accel, const TraceSettings& trace,
                         const Settings& settings);

    /// Traces pass `pass`'s photons and builds its map; returns the rays traced. When `interrupt`
    /// asks to stop it returns early, and the pass must be abandoned.
    uint64_t beginPass(uint32_t pass, const Interrupt* interrupt);
    /// Radiance reflected towards wo at si by material m from the map's photons that landed after
    /// at most `maxBounces` scattering events; with `bias`, the estimate's bias too
    /// (PhotonMap::reflected).
    Color reflected(const SurfaceInteraction& si, const Vec3& wo, const Material& m, int maxBounces,
                    Color* bias = nullptr) const;

    size_t memoryBytes() const { return map_ ? map_->memoryBytes() : 0; }
    /// Peak bytes of a pass's tracing and map, estimated from a pilot tracing of at most
    /// kPilotPhotonPaths paths.
    size_t peakBytes(const Interrupt* interrupt) const;

private:
    PhotonTracingOptions tracingOptions(uint32_t pass, const Interrupt* interrupt) const;
    /// The photons a map keeps of a tracing.
    std::vector<Photon> kept(std::vector<Photon> traced) const;

    const Scene& scene_;
    const Accelerator& accel_;
    TraceSettings trace_;
    Settings settings_;
    PhotonEstimate pass_;  // this pass's radius and kernel
    std::unique_ptr<PhotonMap> map_;
};

}  // namespace caustic
