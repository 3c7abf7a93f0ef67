// A primitive with an emissive material: radiance Le from its front side, uniform, or from an
// emissive texture (a textured material's emissionAt).
#pragma once

#include "geometry/geometry.h"
#include "lights/light.h"
#include "materials/material.h"

namespace caustic {

class AreaLight final : public Light {
public:
    /// Le: the radiance, or for a textured material (`textured`, which outlives the light) its
    /// average, which the light's power uses.
    AreaLight(const Geometry& geometry, uint32_t prim, const Color& Le,
              const Material* textured = nullptr)
        : geometry_(geometry), prim_(prim), Le_(Le), textured_(textured) {}

    /// Samples a sphere seen from outside uniformly in the cone of directions it subtends; any
    /// other primitive (and a sphere from inside) uniformly by area, converted to solid angle.
    std::optional<LightSample> sampleLi(const LightSampleContext& ref, Vec2 u) const override;
    float pdfLi(const LightSampleContext& ref, const SurfaceInteraction& at) const override;
    /// A point uniform by area and a cosine-weighted direction from its front side: the flux of a
    /// sample is Le cos / ((1 / area) (cos / pi)) = Le pi area (the light's power, for every
    /// sample of a uniform emitter).
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    /// Le * area * pi: a one-sided Lambertian emitter (with a texture, its average Le).
    Color power() const override { return Le_ * geometry_.area(prim_) * kPi; }
    bool isDelta() const override { return false; }
    /// Its power over the squared distance to its bounds' centre, no nearer than the bounds'
    /// half-diagonal: never zero, since a part of the emitter may face ref when its centre does
    /// not.
    float importance(const LightSampleContext& ref) const override;
    uint32_t prim() const { return prim_; }

private:
    /// The apex of the cone of directions towards sphere s: ref moved towards its center by ref's
    /// error bound, so that a point on s (within rounding) counts as inside (pbrt-v4,
    /// Sphere::Sample). Cone and area sampling then choose alike in sampleLi and pdfLi.
    static Vec3 coneApex(const Sphere& s, const LightSampleContext& ref) {
        return offsetRayOrigin(ref.p, ref.pError, ref.n, s.center - ref.p);
    }
    /// The sphere this light is, or nullptr for a quad or triangle.
    const Sphere* sphere() const {
        return geometry_.kind(prim_) == PrimKind::Sphere
                   ? &geometry_.spheres()[geometry_.localIndex(prim_)]
                   : nullptr;
    }

    /// The radiance leaving the sampled point.
    Color LeAt(const SurfaceSample& at) const;

    const Geometry& geometry_;
    uint32_t prim_;
    Color Le_;
    const Material* textured_;
};

}  // namespace caustic
