#include "integrators/raycast.h"

namespace caustic {

Color RayCastIntegrator::Li(const Ray& ray, SampleContext& ctx) const {
    std::optional<Hit> hit = intersect(ray, ctx);
    if (!hit) return scene_.escapedRadiance(ray.d);
    SurfaceInteraction si = scene_.geometry.interaction(ray, *hit);
    const Material& m = shade(si, ctx);
    Vec3 wo = -ray.d;
    Color L = sampleDirectLight(si, wo, m, ctx);
    return ctx.cameraEmission ? L + m.Le(wo, si.n) : L;
}

}  // namespace caustic
