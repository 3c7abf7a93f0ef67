#include "integrators/path.h"

#include "core/sampling.h"

namespace caustic {

float PathIntegrator::emissionWeight(const LightSampleContext& from, float bsdfPdf,
                                     const SurfaceInteraction& at) const {
    // Without light sampling only the BSDF finds emitters.
    if (!settings_.lightSampling) return 1.0f;
    // Light sampling alone accounts for emitters seen from non-specular vertices.
    if (!settings_.mis) return 0.0f;
    std::optional<SampledLight> light = scene_.areaLightOf(at.prim);
    if (!light) return 1.0f;
    return powerHeuristic(bsdfPdf, light->pmf * light->light->pdfLi(from, at));
}

Color PathIntegrator::Li(const Ray& cameraRay, SampleContext& ctx) const {
    Color L(0.0f), beta(1.0f);
    // The product of eta^2 over the path's refractions: beta * etaScale is the throughput without
    // the radiance scaling of refraction, which Russian roulette must not see (pbrt-v4 13.4.3).
    float etaScale = 1.0f;
    Ray ray = cameraRay;
    // The previous vertex: whether it scattered specularly, its BSDF density and position.
    bool specularBounce = true;
    float bsdfPdf = 0.0f;
    LightSampleContext from(cameraRay.o);

    for (int depth = 0;; ++depth) {
        if (ctx.interrupted()) break;
        std::optional<Hit> hit = intersect(ray, ctx);
        if (!hit) {
            // The background is not sampled as a light: BSDF sampling finds it with weight 1.
            L += beta * scene_.background;
            break;
        }
        SurfaceInteraction si = scene_.geometry.interaction(ray, *hit);
        const Material& m = *scene_.materials[si.material];
        Vec3 wo = -ray.d;

        if (m.isEmissive()) {
            Color Le = m.Le(wo, si.n);
            if (!isBlack(Le)) {
                float w = specularBounce ? 1.0f : emissionWeight(from, bsdfPdf, si);
                L += beta * Le * w;
            }
        }
        if (depth >= maxDepth_) break;

        if (settings_.lightSampling) L += beta * sampleDirectLight(si, wo, m, ctx, settings_.mis);

        float uc = ctx.sampler.uniform();
        Vec2 u = ctx.sampler.uniform2();
        std::optional<BsdfSample> bs = m.sample(wo, si.n, uc, u, TransportMode::Radiance);
        if (!bs || isBlack(bs->weight)) break;
        beta *= bs->weight;
        etaScale *= sqr(bs->eta);
        specularBounce = bs->specular;
        bsdfPdf = bs->pdf;
        from = si;
        ray = spawnRay(si, bs->wi);

        // Russian roulette: continue with the probability of the throughput, then divide it out,
        // so that a path's weight stays near 1 (pbrt-v4 13.4.3).
        if (depth + 1 >= settings_.rrDepth) {
            float q = maxComponent(beta) * etaScale;
            if (q < 1.0f) {
                if (ctx.sampler.uniform() >= q) break;
                beta /= q;
            }
        }
    }
    return L;
}

}  // namespace caustic
