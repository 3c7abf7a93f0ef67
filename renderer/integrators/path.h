// Unidirectional path tracing (Kajiya 1986) with next-event estimation and multiple importance
// sampling (Veach 1997, chapter 9; pbrt-v4 13.4): at every non-specular vertex one light is
// sampled by power and the BSDF is sampled to continue the path; emission found by either strategy
// is weighted by the power heuristic. Russian roulette ends paths in proportion to their
// throughput. With light sampling off it is the naive path tracer; with MIS off, light sampling
// alone accounts for direct light at non-specular vertices (the seed's two variants). With
// photon-mapped caustics the L S+ D part of the light comes from a progressive caustic photon map
// at every non-specular vertex instead; with photon-mapped indirect light the path ends at its
// second non-specular vertex, where a light sample and a progressive map of the photons that
// scattered before they landed give the light leaving it (photons/progressive_photon_map.h).
#pragma once

#include <memory>

#include "integrators/integrator.h"
#include "integrators/photon.h"
#include "photons/progressive_photon_map.h"

namespace caustic {

/// Where the path tracer takes a part of the light from: caustics (light reaching a non-specular
/// vertex through specular bounces only), or the light leaving its second non-specular vertex
/// other than emission and direct light.
enum class PathSource { Paths, PhotonMap };

class PathIntegrator final : public Integrator {
public:
    /// Its own settings (render/settings_table.cpp declares their names, ranges and docs); it
    /// also reads TraceSettings::maxDepth.
    struct Settings {
        int rrDepth = 3;            ///< Bounces before Russian roulette may end a path.
        bool lightSampling = true;  ///< Next-event estimation at non-specular vertices.
        bool mis = true;            ///< Power-heuristic weights for light and BSDF samples.
        PathSource caustics = PathSource::Paths;
        PathSource indirect = PathSource::Paths;
        uint64_t indirectPhotons = 30000;  ///< The indirect map's photon paths per pass.
        double indirectRadius = 0;  ///< Its first pass's radius; 0: 1/62.5 of the scene's diagonal.

        /// Whether a photon map gives a part of the light: the estimate is then consistent, not
        /// unbiased, and the error estimate excludes the bias.
        bool photonMapped() const {
            return caustics == PathSource::PhotonMap || indirect == PathSource::PhotonMap;
        }
    };

    /// `photon` is read only with caustics from a photon map (photons, radius, alpha, kernel and
    /// lookup); the indirect map reads its alpha, kernel and lookup.
    PathIntegrator(const Scene& scene, const Accelerator& accel, const TraceSettings& trace,
                   const Settings& settings, const PhotonIntegrator::Settings& photon);

    uint64_t beginPass(uint32_t pass) override;
    Color Li(const Ray& ray, SampleContext& ctx) const override;
    size_t memoryBytes() const override {
        return (caustics_ ? caustics_->memoryBytes() : 0) +
               (indirect_ ? indirect_->memoryBytes() : 0);
    }
    void checkMemory(size_t budgetBytes) const override;
    bool estimatesBias() const override { return caustics_ || indirect_; }

private:
    /// beta times a map's reading at si; with ctx.trackBias, beta times its bias is added to
    /// ctx.bias.
    Color mapped(const ProgressivePhotonMap& map, const SurfaceInteraction& si, const Vec3& wo,
                 const Material& m, int maxBounces, const Color& beta, SampleContext& ctx) const;
    /// The weight of emission Le found by a BSDF-sampled ray from `from` (density bsdfPdf) that
    /// hit emitter `at`.
    float emissionWeight(const LightSampleContext& from, float bsdfPdf,
                         const SurfaceInteraction& at) const;
    /// The same for the environment's radiance found by a ray that left the scene along d.
    float environmentWeight(const LightSampleContext& from, float bsdfPdf, const Vec3& d) const;

    int maxDepth_;
    Settings settings_;
    std::unique_ptr<ProgressivePhotonMap> caustics_;  // null when caustics are path traced
    std::unique_ptr<ProgressivePhotonMap> indirect_;  // null when indirect light is path traced
};

}  // namespace caustic
