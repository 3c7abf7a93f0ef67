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

namespace caustic {

class PhotonIntegrator final : public Integrator {
public:
    struct Options {
        uint64_t photons = 200000;
        uint64_t causticPhotons = 0;  ///< Paths for the caustic map; 0 takes those of `photons`.
        PhotonLookup lookup = PhotonLookup::KdTree;
        PhotonEstimate estimate;
        int finalGather = 0;  ///< Gather rays per camera path; 0 looks up the global map at x.
        int maxDepth = 16;
        uint64_t seed = 0;
        int threads = 0;
        bool progressive = false;  ///< ppm: radius per pass from estimate.radius and alpha.
        float alpha = 2.0f / 3.0f;
    };

    /// The radius of pass `pass` for initial radius r0 (Knaus & Zwicker 2011, eq. 20).
    static float progressiveRadius(float r0, float alpha, uint32_t pass);

    PhotonIntegrator(const Scene& scene, const Accelerator& accel, const Options& options)
        : Integrator(scene, accel), options_(options) {}

    uint64_t beginPass(uint32_t pass) override;
    Color Li(const Ray& ray, SampleContext& ctx) const override;
    size_t memoryBytes() const override;
    void checkMemory(size_t budgetBytes) const override;

    /// Peak bytes of one pass's photon tracing and maps, from a pilot tracing of at most
    /// kPilotPaths paths of each kind (a few milliseconds).
    size_t estimatedPeakBytes() const;
    static constexpr uint64_t kPilotPaths = 8192;
    /// Peak bytes of one pass that stores `storedPhotons` photons (global and caustic maps).
    static size_t peakBytes(double storedPhotons);

private:
    PhotonTracingOptions tracingOptions(uint32_t pass, bool causticOnly) const;
    /// Follows specular lobes from `ray` (one sampled lobe per hit) to the first non-specular hit;
    /// nullopt when the path escapes (`escaped`) or ends. `beta` accumulates the specular weights;
    /// `ray` becomes the ray that reached the hit.
    std::optional<SurfaceInteraction> firstDiffuseHit(Ray& ray, Color& beta, bool& escaped,
                                                      SampleContext& ctx) const;
    Color gather(const SurfaceInteraction& x, const Vec3& wo, const Material& m, SampleContext& ctx,
                 std::vector<Neighbor>& scratch) const;

    Options options_;
    PhotonEstimate passEstimate_;  // this pass's estimate settings (the radius changes for ppm)
    std::unique_ptr<PhotonMap> global_;
    std::unique_ptr<PhotonMap> caustic_;
};

}  // namespace caustic
