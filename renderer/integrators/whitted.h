// Whitted ray tracing (Whitted 1980; pbrt-v3 src/integrators/whitted.cpp): direct light at diffuse
// hits, and recursion along every specular branch (mirror reflection; dielectric reflection and
// refraction weighted by Fresnel) up to max_depth bounces. The branches are followed from an
// explicit stack, not by recursion, so that a large max_depth cannot overflow a thread's stack.
#pragma once

#include "integrators/integrator.h"

namespace caustic {

class WhittedIntegrator final : public Integrator {
public:
    /// Whitted reads no settings of its own: only TraceSettings::maxDepth, its recursion depth.
    WhittedIntegrator(const Scene& scene, const Accelerator& accel, const TraceSettings& settings)
        : Integrator(scene, accel), maxDepth_(settings.maxDepth) {}
    Color Li(const Ray& ray, SampleContext& ctx) const override;

private:
    int maxDepth_;
};

}  // namespace caustic
