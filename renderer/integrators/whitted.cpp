#include "integrators/whitted.h"

namespace caustic {

Color WhittedIntegrator::trace(const Ray& ray, int depth, SampleContext& ctx) const {
    std::optional<Hit> hit = intersect(ray, ctx);
    if (!hit) return scene_.background;
    SurfaceInteraction si = scene_.geometry.interaction(ray, *hit);
    const Material& m = *scene_.materials[si.material];
    Vec3 wo = -ray.d;
    Color L = m.Le(wo, si.n);

    // Diffuse surfaces end the path with direct light.
    if (!m.isSpecular()) return L + sampleDirectLight(si, wo, m, ctx);

    // Follow every specular branch.
    if (depth >= maxDepth_) return L;
    SpecularLobe lobes[2];
    int count = m.specularLobes(wo, si.n, TransportMode::Radiance, lobes);
    for (int i = 0; i < count; ++i)
        if (!isBlack(lobes[i].weight))
            L += lobes[i].weight * trace(spawnRay(si, lobes[i].wi), depth + 1, ctx);
    return L;
}

}  // namespace caustic
