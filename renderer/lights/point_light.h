// An isotropic point light of radiant intensity I (W/sr): irradiance I cos(theta) / d^2.
#pragma once

#include "core/sampling.h"
#include "lights/light.h"

namespace caustic {

class PointLight final : public Light {
public:
    PointLight(const Vec3& position, const Color& intensity)
        : position_(position), intensity_(intensity) {}

    std::optional<LightSample> sampleLi(const LightSampleContext& ref, Vec2) const override {
        Vec3 d = position_ - ref.p;
        float dist2 = glm::dot(d, d);
        if (dist2 == 0.0f) return std::nullopt;
        LightSample s;
        s.wi = d / std::sqrt(dist2);
        s.Li = intensity_ / dist2;
        s.pdf = 1.0f;
        s.at = SurfaceSample{position_, Vec3(0.0f), Vec3(0.0f), 1.0f};
        return s;
    }
    float pdfLi(const LightSampleContext&, const SurfaceInteraction&) const override {
        return 0.0f;
    }
    /// Uniform over the sphere of directions: the flux of a sample is 4 pi I.
    std::optional<LightLeSample> sampleLe(Vec2, Vec2 uDirection) const override {
        return LightLeSample{Ray{position_, sampleUniformSphere(uDirection)}, power()};
    }
    Color power() const override { return 4.0f * kPi * intensity_; }
    /// The luminance of the irradiance at ref: I |cos| / d^2 (|cos| 1 for a point in space).
    float importance(const LightSampleContext& ref) const override {
        return luminance(intensity_) * pointLightFactor(position_, ref);
    }
    bool isDelta() const override { return true; }
    const Vec3& position() const { return position_; }

private:
    Vec3 position_;
    Color intensity_;
};

}  // namespace caustic
