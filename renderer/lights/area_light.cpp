#include "lights/area_light.h"

#include "core/sampling.h"
#include "materials/material_scratch.h"

namespace caustic {

Color AreaLight::LeAt(const SurfaceSample& at) const {
    if (!textured_) return Le_;
    SurfaceInteraction si;
    si.p = si.pShading = at.p;
    si.pError = at.pError;
    si.n = si.ns = at.n;
    si.uv = at.uv;
    si.prim = prim_;
    TexturePoint point;
    point.frame = geometry_.textureFrame(si);
    point.query.st = point.frame.st;
    point.n = at.n;
    return textured_->emissionAt(point);
}

std::optional<LightSample> AreaLight::sampleLi(const LightSampleContext& ref, Vec2 u) const {
    const Sphere* s = sphere();
    float conePdf = 0.0f;
    std::optional<SurfaceSample> cone =
        s ? s->sampleCone(coneApex(*s, ref), u, conePdf) : std::nullopt;
    SurfaceSample at = cone ? *cone : geometry_.sample(prim_, u);
    Vec3 d = at.p - ref.p;
    float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return std::nullopt;
    Vec3 wi = d / std::sqrt(dist2);
    // Emission leaves the front side only.
    float cosLight = -glm::dot(wi, at.n);
    if (!(cosLight > 0.0f)) return std::nullopt;
    LightSample ls;
    ls.wi = wi;
    ls.Li = LeAt(at);
    // Area density to solid angle: p(w) = p(A) d^2 / cos (pbrt-v4 eq. 4.9).
    ls.pdf = cone ? conePdf : at.pdfArea * dist2 / cosLight;
    ls.at = at;
    if (!std::isfinite(ls.pdf) || !(ls.pdf > 0.0f)) return std::nullopt;
    return ls;
}

float AreaLight::importance(const LightSampleContext& ref) const {
    const Bounds3 b = geometry_.bounds(prim_);
    const Vec3 d = b.center() - ref.p;
    const float radius2 = 0.25f * glm::dot(b.diagonal(), b.diagonal());
    return luminance(power()) / std::max(glm::dot(d, d), radius2);
}

std::optional<LightLeSample> AreaLight::sampleLe(Vec2 uPosition, Vec2 uDirection) const {
    SurfaceSample at = geometry_.sample(prim_, uPosition);
    Vec3 local = sampleCosineHemisphere(uDirection);
    if (!(local.z > 0.0f)) return std::nullopt;
    Vec3 w = fromLocal(local, at.n);
    const Color flux = textured_ ? LeAt(at) * geometry_.area(prim_) * kPi : power();
    return LightLeSample{Ray{offsetRayOrigin(at.p, at.pError, at.n, w), w}, flux};
}

float AreaLight::pdfLi(const LightSampleContext& ref, const SurfaceInteraction& at) const {
    if (const Sphere* s = sphere()) {
        float conePdf = s->coneSolidAnglePdf(coneApex(*s, ref));
        if (conePdf > 0.0f) return conePdf;
    }
    Vec3 d = at.p - ref.p;
    float dist2 = glm::dot(d, d);
    float cosLight = std::abs(glm::dot(d, at.n)) / std::sqrt(dist2);
    float pdf = dist2 / (cosLight * geometry_.area(prim_));
    return std::isfinite(pdf) ? pdf : 0.0f;
}

}  // namespace caustic
