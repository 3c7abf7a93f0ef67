// A spot light: a point that emits intensity I (W/sr) inside a cone, with the smooth falloff of
// glTF's KHR_lights_punctual between the inner and outer cone angles (its spec's implementation
// note: the squared linear ramp in cos(theta)).
#pragma once

#include "lights/light.h"

namespace caustic {

class SpotLight final : public Light {
public:
    /// `direction`: where the cone points (any length > 0). Half-angles in degrees,
    /// 0 <= inner <= outer <= 90; inner == outer gives a hard-edged cone.
    SpotLight(const Vec3& position, const Vec3& direction, const Color& intensity,
              float innerDegrees, float outerDegrees);

    /// The falloff in [0, 1] of a unit direction leaving the light.
    float falloff(const Vec3& w) const;

    std::optional<LightSample> sampleLi(const LightSampleContext& ref, Vec2 u) const override;
    float pdfLi(const LightSampleContext&, const SurfaceInteraction&) const override { return 0; }
    /// A direction uniform in the outer cone.
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    /// I 2 pi ((1 - cos inner) + (cos inner - cos outer) / 3): the falloff integrated over the
    /// sphere.
    Color power() const override;
    bool isDelta() const override { return true; }
    /// The luminance of the irradiance at ref: I falloff |cos| / d^2.
    float importance(const LightSampleContext& ref) const override;

private:
    Vec3 position_, axis_;
    Color intensity_;
    float cosInner_, cosOuter_;
};

}  // namespace caustic
