#include "lights/area_light.h"

namespace caustic {

std::optional<LightSample> AreaLight::sampleLi(const Vec3& ref, Vec2 u) const {
    SurfaceSample at = geometry_.sample(prim_, u);
    Vec3 d = at.p - ref;
    float dist2 = glm::dot(d, d);
    if (dist2 == 0.0f) return std::nullopt;
    Vec3 wi = d / std::sqrt(dist2);
    // Emission leaves the front side only.
    float cosLight = -glm::dot(wi, at.n);
    if (cosLight <= 0.0f) return std::nullopt;
    LightSample s;
    s.wi = wi;
    s.Li = Le_;
    s.pdf = at.pdfArea * dist2 / cosLight;  // dA -> d omega (pbrt-v4 eq. 4.9)
    s.at = at;
    if (!std::isfinite(s.pdf) || s.pdf <= 0.0f) return std::nullopt;
    return s;
}

}  // namespace caustic
