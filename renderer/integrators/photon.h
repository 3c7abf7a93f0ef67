// Two-pass photon mapping (Jensen 1996; Jensen 2001, chapter 9). Each pass traces `photons`
// photon paths (beginPass) into a global map of every stored photon and a caustic map of the
// caustic ones; then camera paths follow specular surfaces to the first diffuse hit x, where
// L = Le + direct light (one light sample) + caustics (caustic map) + indirect light: from the
// global map's indirect photons at x, or, with final gathering, from `final_gather` BSDF-sampled
// rays whose first diffuse hits y look up every photon of the global map. Each part of the light
// is counted once: direct L D, caustic L S+ D, indirect paths with a diffuse vertex before x.
#pragma once

#include <memory>

#include "integrators/integrator.h"
#include "photons/photon_map.h"

namespace caustic {

class PhotonIntegrator final : public Integrator {
public:
    struct Options {
        uint64_t photons = 200000;
        PhotonEstimate estimate;
        int finalGather = 0;  ///< Gather rays per camera path; 0 looks up the global map at x.
        int maxDepth = 16;
        uint64_t seed = 0;
    };

    PhotonIntegrator(const Scene& scene, const Accelerator& accel, const Options& options)
        : Integrator(scene, accel), options_(options) {}

    void beginPass(uint32_t pass) override;
    Color Li(const Ray& ray, SampleContext& ctx) const override;
    size_t memoryBytes() const override;

private:
    /// Follows specular lobes from `ray` (one sampled lobe per hit) to the first non-specular hit;
    /// nullopt when the path escapes (`escaped`) or ends. `beta` accumulates the specular weights;
    /// `ray` becomes the ray that reached the hit.
    std::optional<SurfaceInteraction> firstDiffuseHit(Ray& ray, Color& beta, bool& escaped,
                                                      SampleContext& ctx) const;
    Color gather(const SurfaceInteraction& x, const Vec3& wo, const Material& m, SampleContext& ctx,
                 std::vector<Neighbor>& scratch) const;

    Options options_;
    std::unique_ptr<PhotonMap> global_;
    std::unique_ptr<PhotonMap> caustic_;
};

}  // namespace caustic
