// A primitive with an emissive material: uniform radiance Le from its front side.
#pragma once

#include "geometry/geometry.h"
#include "lights/light.h"

namespace caustic {

class AreaLight final : public Light {
public:
    AreaLight(const Geometry& geometry, uint32_t prim, const Color& Le)
        : geometry_(geometry), prim_(prim), Le_(Le) {}

    /// Samples a sphere seen from outside uniformly in the cone of directions it subtends; any
    /// other primitive (and a sphere from inside) uniformly by area, converted to solid angle.
    std::optional<LightSample> sampleLi(const LightSampleContext& ref, Vec2 u) const override;
    float pdfLi(const LightSampleContext& ref, const SurfaceInteraction& at) const override;
    /// A point uniform by area and a cosine-weighted direction from its front side: the flux of a
    /// sample is Le cos / ((1 / area) (cos / pi)) = Le pi area, the light's power, for every
    /// sample.
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    /// Le * area * pi: a one-sided Lambertian emitter.
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

    const Geometry& geometry_;
    uint32_t prim_;
    Color Le_;
};

}  // namespace caustic
