#include "lights/spot_light.h"

#include <algorithm>

#include "core/sampling.h"

namespace caustic {

SpotLight::SpotLight(const Vec3& position, const Vec3& direction, const Color& intensity,
                     float innerDegrees, float outerDegrees)
    : position_(position),
      axis_(glm::normalize(direction)),
      intensity_(intensity),
      cosInner_(std::cos(radians(innerDegrees))),
      cosOuter_(std::cos(radians(outerDegrees))) {}

float SpotLight::falloff(const Vec3& w) const {
    const float cosTheta = glm::dot(w, axis_);
    if (cosTheta < cosOuter_) return 0.0f;
    if (cosTheta >= cosInner_) return 1.0f;
    const float t = (cosTheta - cosOuter_) / (cosInner_ - cosOuter_);
    return t * t;
}

std::optional<LightSample> SpotLight::sampleLi(const LightSampleContext& ref, Vec2) const {
    const Vec3 d = position_ - ref.p;
    const float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return std::nullopt;
    LightSample s;
    s.wi = d / std::sqrt(dist2);
    const float f = falloff(-s.wi);
    if (f == 0.0f) return std::nullopt;
    s.Li = intensity_ * (f / dist2);
    s.pdf = 1.0f;
    s.at = SurfaceSample{position_, Vec3(0.0f), Vec3(0.0f), 1.0f};
    return s;
}

std::optional<LightLeSample> SpotLight::sampleLe(Vec2, Vec2 u) const {
    // Uniform in the cone cos(theta) in [cos outer, 1]: density 1 / (2 pi (1 - cos outer)).
    const float cosTheta = 1.0f - u.x * (1.0f - cosOuter_);
    const float sinTheta = safeSqrt(1.0f - cosTheta * cosTheta);
    const float phi = 2.0f * kPi * u.y;
    const Vec3 w =
        fromLocal(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta), axis_);
    const float f = falloff(w);
    if (f == 0.0f) return std::nullopt;
    return LightLeSample{Ray{position_, w}, intensity_ * (f * 2.0f * kPi * (1.0f - cosOuter_))};
}

float SpotLight::importance(const LightSampleContext& ref) const {
    const Vec3 d = ref.p - position_;
    const float length = glm::length(d);
    if (!(length > 0.0f)) return 0.0f;
    return luminance(intensity_) * falloff(d / length) * pointLightFactor(position_, ref);
}

Color SpotLight::power() const {
    return intensity_ * (2.0f * kPi * ((1.0f - cosInner_) + (cosInner_ - cosOuter_) / 3.0f));
}

}  // namespace caustic
