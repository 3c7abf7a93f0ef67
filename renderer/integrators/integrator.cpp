#include "integrators/integrator.h"

#include "core/sampling.h"
#include "materials/surface_bsdf.h"

namespace caustic {

bool Integrator::unoccluded(const SurfaceInteraction& si, const LightSample& ls,
                            SampleContext& ctx) const {
    Vec3 from = rayOrigin(si, ls.wi);
    // Offset the far end too, off the emitter's surface towards the receiver.
    Vec3 to = glm::dot(ls.at.n, ls.at.n) > 0.0f
                  ? offsetRayOrigin(ls.at.p, ls.at.pError, ls.at.n, from - ls.at.p)
                  : ls.at.p;
    Vec3 d = to - from;
    float dist = glm::length(d);
    if (!(dist > 0.0f)) return true;
    ++ctx.rays;
    return !occludedVisible(scene_, accel_, Ray{from, d / dist}, dist * (1.0f - kShadowEpsilon),
                            ctx.rays);
}

Color Integrator::sampleDirectLight(const SurfaceInteraction& si, const Vec3& wo, const Material& m,
                                    SampleContext& ctx, bool mis) const {
    if (m.isSpecular()) return Color(0.0f);
    std::optional<SampledLight> chosen = scene_.directLights.sample(si, ctx.sampler.uniform());
    Vec2 u = ctx.sampler.uniform2();
    if (!chosen) return Color(0.0f);
    // With MIS, BSDF sampling finds the environment's dim directions: its light samples may
    // leave them out (MIS compensation).
    std::optional<LightSample> ls = mis && chosen->light == scene_.environment
                                        ? scene_.environment->sampleLiCompensated(si, u)
                                        : chosen->light->sampleLi(si, u);
    if (!ls || isBlack(ls->Li)) return Color(0.0f);
    const SurfaceBsdf bsdf(m, si);
    Color f = bsdf.f(wo, ls->wi);
    if (isBlack(f) || !unoccluded(si, *ls, ctx)) return Color(0.0f);
    float lightPdf = ls->pdf * chosen->pmf;
    float weight = 1.0f;
    if (mis && !chosen->light->isDelta()) weight = powerHeuristic(lightPdf, bsdf.pdf(wo, ls->wi));
    return f * ls->Li * (bsdf.absCos(ls->wi) * weight / lightPdf);
}

}  // namespace caustic
