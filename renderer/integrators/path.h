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
    /// Its own settings (render/settings_table.cpp declares their names, ranges and docs); it
    /// also reads TraceSettings::maxDepth.
    struct Settings {
        int rrDepth = 3;            ///< Bounces before Russian roulette may end a path.
        bool lightSampling = true;  ///< Next-event estimation at non-specular vertices.
        bool mis = true;            ///< Power-heuristic weights for light and BSDF samples.
    };

    PathIntegrator(const Scene& scene, const Accelerator& accel, const TraceSettings& trace,
                   const Settings& settings)
        : Integrator(scene, accel), maxDepth_(trace.maxDepth), settings_(settings) {}
    Color Li(const Ray& ray, SampleContext& ctx) const override;

private:
    /// The weight of emission Le found by a BSDF-sampled ray from `from` (density bsdfPdf) that
    /// hit emitter `at`.
    float emissionWeight(const LightSampleContext& from, float bsdfPdf,
                         const SurfaceInteraction& at) const;

    int maxDepth_;
    Settings settings_;
};

}  // namespace caustic
