#include "materials/mirror.h"

#include "materials/fresnel.h"

namespace caustic {

std::optional<BsdfSample> Mirror::sample(const Vec3& wo, const Vec3& n, float, Vec2,
                                         TransportMode) const {
    return specularSample(SpecularLobe{reflect(wo, n), reflectance_}, n);
}

int Mirror::specularLobes(const Vec3& wo, const Vec3& n, TransportMode, SpecularLobe out[2]) const {
    out[0] = SpecularLobe{reflect(wo, n), reflectance_};
    return 1;
}

}  // namespace caustic
