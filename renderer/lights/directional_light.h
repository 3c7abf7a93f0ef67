// A directional light (the sun seen as a point at infinity): irradiance E (W/m^2 per channel) on a
// surface facing it, arriving along one direction everywhere.
#pragma once

#include "core/bounds.h"
#include "lights/light.h"

namespace caustic {

class DirectionalLight final : public Light {
public:
    /// `direction`: the way the light travels (any length > 0).
    DirectionalLight(const Vec3& direction, const Color& irradiance, const Bounds3& sceneBounds);

    std::optional<LightSample> sampleLi(const LightSampleContext& ref, Vec2 u) const override;
    float pdfLi(const LightSampleContext&, const SurfaceInteraction&) const override { return 0; }
    /// A point on the disk of the scene's bounding radius that faces the light, outside the
    /// scene (pbrt-v4 12.4.2).
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    /// E pi R^2: the flux through the scene's bounding disk.
    Color power() const override { return irradiance_ * (kPi * radius_ * radius_); }
    bool isDelta() const override { return true; }
    /// The luminance of the irradiance at ref: E |cos|, the cosine floored (importanceCosine).
    float importance(const LightSampleContext& ref) const override {
        return luminance(irradiance_) * importanceCosine(direction_, ref);
    }

private:
    Vec3 direction_;
    Color irradiance_;
    Vec3 center_{0.0f};
    float radius_ = 1.0f;
};

}  // namespace caustic
