#include "integrators/whitted.h"

#include <vector>

#include "materials/surface_bsdf.h"

namespace caustic {

Color WhittedIntegrator::Li(const Ray& cameraRay, SampleContext& ctx) const {
    // A specular branch still to follow: its ray, the product of the lobe weights that led to
    // it, and its depth. A dielectric splits a branch in two, so the stack holds at most
    // 2 * max_depth branches while the work grows with the branches followed: the interrupt is
    // polled per branch.
    struct Branch {
        Ray ray;
        Color weight;
        int depth;
    };
    thread_local std::vector<Branch> stack;
    stack.clear();
    stack.push_back({cameraRay, Color(1.0f), 0});
    Color L(0.0f);
    while (!stack.empty()) {
        Branch b = stack.back();
        stack.pop_back();
        if (ctx.interrupted()) break;
        std::optional<Hit> hit = intersect(b.ray, ctx);
        if (!hit) {
            L += b.weight * scene_.escapedRadiance(b.ray.d);
            continue;
        }
        SurfaceInteraction si = scene_.geometry.interaction(b.ray, *hit);
        const Material& m = shade(si, ctx);
        Vec3 wo = -b.ray.d;
        if (b.depth > 0 || ctx.cameraEmission) L += b.weight * m.Le(wo, si.n);

        // Diffuse surfaces end the branch with direct light.
        if (!m.isSpecular()) {
            L += b.weight * sampleDirectLight(si, wo, m, ctx);
            continue;
        }
        // Follow every specular lobe.
        if (b.depth >= maxDepth_) continue;
        SpecularLobe lobes[2];
        int count = SurfaceBsdf(m, si).specularLobes(wo, TransportMode::Radiance, lobes);
        // Pushed in reverse, so the first lobe is followed first, as a recursive trace would.
        for (int i = count - 1; i >= 0; --i)
            if (!isBlack(lobes[i].weight))
                stack.push_back(
                    {spawnRay(si, lobes[i].wi), b.weight * lobes[i].weight, b.depth + 1});
    }
    return L;
}

}  // namespace caustic
