// Unidirectional path tracing (Kajiya 1986) with next-event estimation and multiple importance
// sampling (Veach 1997, chapter 9; pbrt-v4 13.4): at every non-specular vertex one light is
// sampled by power and the BSDF is sampled to continue the path; emission found by either strategy
// is weighted by the power heuristic. Russian roulette ends paths in proportion to their
// throughput. With light sampling off it is the naive path tracer; with MIS off, light sampling
// alone accounts for direct light at non-specular vertices (the seed's two variants).
#pragma once

#include "integrators/integrator.h"

namespace caustic {

class PathIntegrator final : public Integrator {
public:
    struct Options {
        int maxDepth = 16;  ///< Most scattering events on a path; 1 is direct lighting only.
        int rrDepth = 3;    ///< Bounces before Russian roulette may end a path.
        bool lightSampling = true;
        bool mis = true;
    };

    PathIntegrator(const Scene& scene, const Accelerator& accel, const Options& options)
        : Integrator(scene, accel), options_(options) {}
    Color Li(const Ray& ray, SampleContext& ctx) const override;

private:
    /// The weight of emission Le found by a BSDF-sampled ray from `from` (density bsdfPdf) that
    /// hit emitter `at`.
    float emissionWeight(const LightSampleContext& from, float bsdfPdf,
                         const SurfaceInteraction& at) const;

    Options options_;
};

}  // namespace caustic
