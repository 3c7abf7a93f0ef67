// The GGX (Trowbridge-Reitz) microfacet distribution in a local shading frame, z the surface
// normal: the density of microfacet normals D, Smith's masking for it, and sampling of the normals
// visible from a direction. Walter et al. 2007, "Microfacet Models for Refraction through Rough
// Surfaces"; Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs";
// visible normals by spherical caps, Dupuy and Benyoub 2023, "Sampling Visible GGX Normals with
// Spherical Caps". Conventions as pbrt-v4, section 9.6.
#pragma once

#include "core/math.h"

namespace caustic {

class Ggx {
public:
    /// alphaX, alphaY: the distribution's width along the frame's x and y axes, > 0.
    Ggx(float alphaX, float alphaY) : alphaX_(alphaX), alphaY_(alphaY) {}

    /// The width of perceptual roughness r in [0, 1]: r^2 (Burley 2012; glTF 2.0, Appendix B).
    static float alphaOf(float roughness) { return roughness * roughness; }

    /// Density of microfacet normals per unit solid angle, normalized so that D(wm) cos(theta_m)
    /// integrates to 1 over the hemisphere (the microsurface projects to the macrosurface). Zero
    /// below the horizon. wm a unit vector. Thread-safe, as every method.
    float D(const Vec3& wm) const;
    /// Smith's Lambda for direction w: the masking G1(w) = 1 / (1 + Lambda(w)).
    float lambda(const Vec3& w) const;
    float G1(const Vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
    /// Height-correlated masking-shadowing of wo and wi (Heitz 2014, eq. 99).
    float G(const Vec3& wo, const Vec3& wi) const {
        return 1.0f / (1.0f + lambda(wo) + lambda(wi));
    }
    /// Density, per unit solid angle of wm, of the normals visible from w (w.z > 0): G1(w)
    /// max(0, w.wm) D(wm) / cos(theta_w) (Heitz 2014, eq. 38). It integrates to 1.
    float visibleD(const Vec3& w, const Vec3& wm) const;
    /// A normal visible from w (w.z > 0), from u in [0,1)^2; its density is visibleD(w, wm).
    Vec3 sampleVisible(const Vec3& w, Vec2 u) const;

    float alphaX() const { return alphaX_; }
    float alphaY() const { return alphaY_; }

private:
    float alphaX_, alphaY_;
};

}  // namespace caustic
