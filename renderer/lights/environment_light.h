// Light from infinitely far away in every direction: a constant radiance, or an equirectangular
// image (latitude-longitude, Mitsuba 3's `envmap` convention) importance-sampled by a
// piecewise-constant density over its texels (pbrt-v4 12.5.2).
#pragma once

#include "core/bounds.h"
#include "core/distribution.h"
#include "film/image_io.h"
#include "lights/light.h"

namespace caustic {

class EnvironmentLight final : public Light {
public:
    /// A constant radiance from every direction; sampled uniformly over the sphere.
    EnvironmentLight(const Color& radiance, const Bounds3& sceneBounds);
    /// An equirectangular RGB image of radiance (W/(m^2 sr) per channel) times `strength`, turned
    /// by `rotationDegrees` about +y. Row 0 is the zenith (+y); the image's left edge faces -z and
    /// its centre +z. Texels must be finite and >= 0.
    EnvironmentLight(RgbImage image, float rotationDegrees, float strength,
                     const Bounds3& sceneBounds);

    /// The radiance arriving from direction w (unit, pointing away from the scene).
    Color Le(const Vec3& w) const;
    /// The solid-angle density with which sampleLi returns direction w; with `compensated`, that
    /// of sampleLiCompensated.
    float pdfDirection(const Vec3& w, bool compensated = false) const;

    std::optional<LightSample> sampleLi(const LightSampleContext& ref, Vec2 u) const override;
    /// A light sample for multiple importance sampling with BSDF sampling: from the density less
    /// its average, clamped at zero (Karlik et al. 2019, "MIS Compensation: Optimizing Sampling
    /// Techniques in Multiple Importance Sampling"; pbrt-v4 12.5.2). It never returns the dim
    /// directions, which BSDF sampling finds; the bright ones get more samples. Only an integrator
    /// that adds the BSDF-sampled share with MIS weights may use it.
    std::optional<LightSample> sampleLiCompensated(const LightSampleContext& ref, Vec2 u) const;
    /// Zero: a ray reaches an environment by leaving the scene, not by hitting a surface; the
    /// integrators ask pdfDirection.
    float pdfLi(const LightSampleContext&, const SurfaceInteraction&) const override { return 0; }
    /// A direction by importance, then a point on the disk that faces it, just outside the scene's
    /// bounding sphere (pbrt-v4 12.5.2): the light enters the scene as parallel rays per direction.
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    /// pi R^2 times the radiance integrated over the sphere: the flux through the disk of the
    /// scene's bounding radius R.
    Color power() const override { return power_; }
    bool isDelta() const override { return false; }

    /// Bytes held by the image and its sampling density.
    size_t memoryBytes() const;
    /// What memoryBytes() is for a width x height image, from its size alone (admission).
    static size_t bytesFor(int width, int height) {
        // RGB float texels; two densities (plain and compensated), each a value and a double CDF
        // entry per texel and a few per row.
        const size_t texels = size_t(width) * size_t(height);
        return texels * (3 * sizeof(float) + 2 * (sizeof(float) + sizeof(double))) +
               size_t(height) * 128;
    }

private:
    Vec3 toLocal(const Vec3& w) const;
    Vec3 toWorld(const Vec3& local) const;
    /// Direction (world) and density per steradian for a sample u.
    Vec3 sampleDirection(Vec2 u, float& pdf, bool compensated) const;
    std::optional<LightSample> sample(const LightSampleContext& ref, Vec2 u,
                                      bool compensated) const;
    Color texel(int x, int y) const;

    Color constant_{0.0f};
    RgbImage image_;  // empty for a constant environment
    Distribution2D distribution_, compensated_;
    float strength_ = 1.0f;
    float cosRotation_ = 1.0f, sinRotation_ = 0.0f;
    Vec3 center_{0.0f};
    float radius_ = 1.0f;
    Color power_{0.0f};
};

}  // namespace caustic
