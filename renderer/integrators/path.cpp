#include "integrators/path.h"

#include "core/sampling.h"
#include "materials/surface_bsdf.h"

namespace caustic {

PathIntegrator::PathIntegrator(const Scene& scene, const Accelerator& accel,
                               const TraceSettings& trace, const Settings& settings,
                               const PhotonIntegrator::Settings& photon)
    : Integrator(scene, accel), maxDepth_(trace.maxDepth), settings_(settings) {
    ProgressivePhotonMap::Settings map{
        .alpha = photon.alpha, .kernel = photon.kernel, .lookup = photon.lookup};
    if (settings_.caustics == PathSource::PhotonMap) {
        map.light = MappedLight::Caustics;
        map.photons = photon.photons;
        map.firstRadius = firstProgressiveRadius(photon.radius, accel.bounds());
        caustics_ = std::make_unique<ProgressivePhotonMap>(scene, accel, trace, map);
    }
    if (settings_.indirect == PathSource::PhotonMap) {
        // Without light sampling nothing else gives the direct light where the map is read.
        map.light = settings_.lightSampling ? MappedLight::Indirect : MappedLight::All;
        map.photons = settings_.indirectPhotons;
        // Read after a gather ray, the estimate's blur is averaged over a hemisphere: a radius
        // eight times the caustic map's default costs little bias and much less noise (measured on
        // the bunny, bench/README.md "Photon-mapped indirect light").
        map.firstRadius = settings_.indirectRadius > 0
                              ? float(settings_.indirectRadius)
                              : 8.0f * firstProgressiveRadius(0.0, accel.bounds());
        indirect_ = std::make_unique<ProgressivePhotonMap>(scene, accel, trace, map);
    }
}

uint64_t PathIntegrator::beginPass(uint32_t pass) {
    uint64_t rays = caustics_ ? caustics_->beginPass(pass, interrupt_) : 0;
    return rays + (indirect_ ? indirect_->beginPass(pass, interrupt_) : 0);
}

void PathIntegrator::checkMemory(size_t budgetBytes) const {
    // Both maps live through a pass: the indirect map is checked against what the caustic map
    // leaves.
    size_t caustics = caustics_ ? caustics_->peakBytes(interrupt_) : 0;
    if (caustics_) checkPhotonPeak(caustics, budgetBytes, "/settings/photons");
    if (indirect_)
        checkPhotonPeak(indirect_->peakBytes(interrupt_), budgetBytes - caustics,
                        "/settings/indirect_photons");
}

float PathIntegrator::emissionWeight(const LightSampleContext& from, float bsdfPdf,
                                     const SurfaceInteraction& at) const {
    // Without light sampling only the BSDF finds emitters.
    if (!settings_.lightSampling) return 1.0f;
    // Light sampling alone accounts for emitters seen from non-specular vertices.
    if (!settings_.mis) return 0.0f;
    std::optional<size_t> light = scene_.areaLightOf(at.prim);
    if (!light) return 1.0f;
    return powerHeuristic(
        bsdfPdf, scene_.directLights.pmf(from, *light) * scene_.lights[*light]->pdfLi(from, at));
}

float PathIntegrator::environmentWeight(const LightSampleContext& from, float bsdfPdf,
                                        const Vec3& d) const {
    if (!settings_.lightSampling) return 1.0f;
    if (!settings_.mis) return 0.0f;
    return powerHeuristic(bsdfPdf, scene_.directLights.pmf(from, scene_.environmentIndex) *
                                       scene_.environment->pdfDirection(d, /*compensated=*/true));
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
    // With photon-mapped caustics: whether the path has passed a non-specular vertex. The map gave
    // that vertex the light of every L S+ D path, so emission the path goes on to find through
    // specular bounces alone is that light again, and is left out.
    bool mappedCaustics = false;
    // Whether the path has passed a non-specular vertex (the next one ends it, with an indirect
    // map).
    bool pastDiffuse = false;

    for (int depth = 0;; ++depth) {
        if (ctx.interrupted()) break;
        std::optional<Hit> hit = intersect(ray, ctx);
        if (!hit) {
            // The background is not sampled as a light: BSDF sampling finds it with weight 1.
            L += beta * scene_.background;
            if (scene_.environment && !(specularBounce && mappedCaustics)) {
                float w = specularBounce ? 1.0f : environmentWeight(from, bsdfPdf, ray.d);
                L += beta * scene_.environment->Le(ray.d) * w;
            }
            break;
        }
        SurfaceInteraction si = scene_.geometry.interaction(ray, *hit);
        const Material& m = shade(si, ctx);
        Vec3 wo = -ray.d;

        if (m.isEmissive() && (depth > 0 || ctx.cameraEmission)) {
            Color Le = m.Le(wo, si.n);
            if (!isBlack(Le) && !(specularBounce && mappedCaustics)) {
                float w = specularBounce ? 1.0f : emissionWeight(from, bsdfPdf, si);
                L += beta * Le * w;
            }
        }
        if (depth >= maxDepth_) break;

        if (indirect_ && pastDiffuse && !m.isSpecular()) {
            // The path ends here: light sampling alone gives the direct light (no BSDF sample is
            // taken to weigh it against), the map the rest.
            if (settings_.lightSampling) L += beta * sampleDirectLight(si, wo, m, ctx, false);
            if (depth + 2 <= maxDepth_)
                L += mapped(*indirect_, si, wo, m, maxDepth_ - depth - 1, beta, ctx);
            break;
        }
        if (settings_.lightSampling) L += beta * sampleDirectLight(si, wo, m, ctx, settings_.mis);
        if (caustics_ && !m.isSpecular()) {
            // A photon that landed after j >= 1 bounces makes a path of depth + 1 + j scattering
            // events, at most max_depth.
            if (depth + 2 <= maxDepth_)
                L += mapped(*caustics_, si, wo, m, maxDepth_ - depth - 1, beta, ctx);
            mappedCaustics = true;
        }
        pastDiffuse = pastDiffuse || !m.isSpecular();

        float uc = ctx.sampler.uniform();
        Vec2 u = ctx.sampler.uniform2();
        std::optional<BsdfSample> bs =
            SurfaceBsdf(m, si).sample(wo, uc, u, TransportMode::Radiance);
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

Color PathIntegrator::mapped(const ProgressivePhotonMap& map, const SurfaceInteraction& si,
                             const Vec3& wo, const Material& m, int maxBounces, const Color& beta,
                             SampleContext& ctx) const {
    Color bias(0.0f);
    const Color L = map.reflected(si, wo, m, maxBounces, ctx.trackBias ? &bias : nullptr);
    ctx.bias += beta * bias;
    return beta * L;
}

}  // namespace caustic
