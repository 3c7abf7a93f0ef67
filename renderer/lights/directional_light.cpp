#include "lights/directional_light.h"

#include "core/sampling.h"

namespace caustic {

DirectionalLight::DirectionalLight(const Vec3& direction, const Color& irradiance,
                                   const Bounds3& sceneBounds)
    : direction_(glm::normalize(direction)), irradiance_(irradiance) {
    sceneBoundingSphere(sceneBounds, center_, radius_);
}

std::optional<LightSample> DirectionalLight::sampleLi(const LightSampleContext& ref, Vec2) const {
    LightSample s;
    s.wi = -direction_;
    s.Li = irradiance_;
    s.pdf = 1.0f;
    // A point past the bounding sphere, for the shadow ray.
    const float far = 2.0f * radius_ + glm::length(ref.p - center_);
    s.at = SurfaceSample{ref.p + far * s.wi, Vec3(0.0f), Vec3(0.0f), 1.0f};
    return s;
}

std::optional<LightLeSample> DirectionalLight::sampleLe(Vec2 uPosition, Vec2) const {
    Vec3 t, b;
    coordinateSystem(direction_, t, b);
    const Vec2 d = sampleConcentricDisk(uPosition);
    const Vec3 origin = center_ + radius_ * (-direction_ + d.x * t + d.y * b);
    return LightLeSample{Ray{origin, direction_}, power()};
}

}  // namespace caustic
