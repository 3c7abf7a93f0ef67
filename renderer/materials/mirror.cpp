#include "materials/mirror.h"

#include "materials/fresnel.h"

namespace caustic {

std::optional<BsdfSample> Mirror::sample(const Vec3& wo, const Vec3& n, float, Vec2,
                                         TransportMode) const {
    BsdfSample s;
    s.wi = reflect(wo, n);
    float cosI = std::abs(glm::dot(s.wi, n));
    if (cosI == 0.0f) return std::nullopt;
    s.f = reflectance_ / cosI;
    s.pdf = 1.0f;
    s.weight = reflectance_;
    s.specular = true;
    return s;
}

int Mirror::specularLobes(const Vec3& wo, const Vec3& n, TransportMode, SpecularLobe out[2]) const {
    out[0] = SpecularLobe{reflect(wo, n), reflectance_};
    return 1;
}

}  // namespace caustic
