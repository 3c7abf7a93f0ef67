// Two-pass photon mapping (Jensen 1996; Jensen 2001, chapter 9). Each pass traces `photons`
// photon paths (beginPass) into a global map of every stored photon and a caustic map of the
// caustic ones; then camera paths follow specular surfaces to the first diffuse hit x, where
// L = Le + direct light (one light sample) + caustics (caustic map) + indirect light: from the
// global map's indirect photons at x, or, with final gathering, from `final_gather` BSDF-sampled
// rays whose first diffuse hits y look up every photon of the global map. Each part of the light
// is counted once: direct L D, caustic L S+ D, indirect paths with a diffuse vertex before x.
// With `causticPhotons`, the caustic map comes from its own, cheaper tracing (paths end at their
// first diffuse hit), so that caustics can have many more photons than the global map.
//
// `ppm` is the same estimator with the memoryless progressive radius of Knaus & Zwicker (2011):
// pass i (0-based) uses the fixed radius r_i with r_i^2 = r_0^2 prod_{j=1..i} (j - 1 + alpha) / j,
// so that each pass is an independent estimate whose bias shrinks while its variance grows slowly
// enough that the average of the passes converges to the right image. The radius depends only on
// the pass index: passes can run on different workers.
#pragma once

#include <memory>

#include "integrators/integrator.h"
#include "photons/photon_map.h"
#include "photons/photon_pass.h"

namespace caustic {

class PhotonIntegrator final : public Integrator {
public:
    /// Its own settings (render/settings_table.cpp declares their names, ranges and docs); it
    /// also reads TraceSettings (max_depth; seed and threads for photon tracing).
    struct Settings {
        uint64_t photons = 200000;    ///< Photon paths traced per pass.
        uint64_t causticPhotons = 0;  ///< Paths for the caustic map; 0 takes those of `photons`.
        PhotonLookup lookup = PhotonLookup::KdTree;
        int k = 50;         ///< Photons per density estimate, when radius is 0.
        double radius = 0;  ///< Fixed search radius, 0 for the k nearest; ppm: the first pass's.
        PhotonKernel kernel = PhotonKernel::Cone;
        int finalGather = 0;  ///< Gather rays per camera path; 0 looks up the global map at x.
        /// Surfaces whose Material::lobeRoughness is below this are followed as mirrors are, by
        /// camera paths and photons alike, instead of estimated from the maps: a density
        /// estimate there sees the lobe through the photons' scattered directions and is noisy
        /// where the lobe is narrow (docs/integrators.md, "Glossy surfaces", measures where).
        double followRoughness = 0.3;
        double alpha = 2.0 / 3.0;  ///< ppm: the radius reduction per pass.
    };

    /// `progressive` makes it ppm: the radius shrinks per pass (from 1/500 of the scene's
    /// diagonal when settings.radius is 0), and final gathering is off.
    PhotonIntegrator(const Scene& scene, const Accelerator& accel, const TraceSettings& trace,
                     const Settings& settings, bool progressive = false);

    uint64_t beginPass(uint32_t pass) override;
    Color Li(const Ray& ray, SampleContext& ctx) const override;
    /// Every estimate it makes is a density estimate: it tracks their bias.
    bool estimatesBias() const override { return true; }
    size_t memoryBytes() const override;
    void checkMemory(size_t budgetBytes) const override;

    /// Peak bytes of one pass's photon tracing and maps, from a pilot tracing of at most
    /// kPilotPhotonPaths paths of each kind.
    size_t estimatedPeakBytes() const;

private:
    PhotonTracingOptions tracingOptions(uint32_t pass, bool causticOnly) const {
        PhotonTracingOptions o =
            photonTracingOptions(trace_, causticOnly ? settings_.causticPhotons : settings_.photons,
                                 pass, causticOnly, interrupt_);
        o.followedRoughness = float(settings_.followRoughness);
        return o;
    }
    /// Follows specular and followed (Settings::followRoughness) surfaces from `ray`, one BSDF
    /// sample per hit, to the first other hit; nullopt when the path escapes (`escaped`) or ends.
    /// `beta` accumulates the samples' weights; `ray` becomes the ray that reached the hit, after
    /// `bounces` followed bounces.
    std::optional<SurfaceInteraction> firstDiffuseHit(Ray& ray, Color& beta, bool& escaped,
                                                      SampleContext& ctx,
                                                      int* bounces = nullptr) const;
    /// The final gather's estimate at x; `bias` becomes its bias (with ctx.trackBias).
    Color gather(const SurfaceInteraction& x, const Vec3& wo, const Material& m, SampleContext& ctx,
                 std::vector<Neighbor>& scratch, Color& bias) const;

    TraceSettings trace_;
    Settings settings_;
    bool progressive_;
    PhotonEstimate estimate_;      // k, kernel and the first pass's radius
    PhotonEstimate passEstimate_;  // this pass's estimate settings (the radius changes for ppm)
    std::unique_ptr<PhotonMap> global_;
    std::unique_ptr<PhotonMap> caustic_;
};

}  // namespace caustic
