// The Fresnel reflectance of a metal, per RGB channel: exact from its complex index of refraction
// eta + i k (relative to the outside medium), or Schlick's approximation from its reflectance at
// normal incidence F0, as glTF's metallic-roughness model takes it.
#pragma once

#include "core/math.h"

namespace caustic {

/// Unpolarized reflectance of a conductor for each channel's eta + i k at cosThetaI in [0, 1]
/// (pbrt-v4 eq. 9.6, in Lagarde's real-arithmetic form, "Memo on Fresnel equations", 2013).
Color fresnelConductor(float cosThetaI, const Color& eta, const Color& k);

/// F0 + (1 - F0)(1 - cos)^5 (Schlick 1994, eq. 24), per channel.
Color fresnelSchlickF0(float cosThetaI, const Color& f0);

class ConductorFresnel {
public:
    /// From the reflectance at normal incidence, each channel in [0, 1].
    static ConductorFresnel fromF0(const Color& f0);
    /// From the complex index of refraction, eta > 0 and k >= 0 per channel.
    static ConductorFresnel fromComplexIor(const Color& eta, const Color& k);

    /// The reflectance at cosThetaI in [0, 1].
    Color operator()(float cosThetaI) const;
    /// The hemispherical average 2 int_0^1 F(mu) mu dmu (Kulla and Conty 2017, "Revisiting
    /// Physically Based Shading at Imageworks", the multiple-scattering Fresnel term).
    const Color& average() const { return average_; }

private:
    bool schlick_ = true;
    Color f0_{1.0f}, eta_{1.0f}, k_{0.0f};
    Color average_{1.0f};
};

}  // namespace caustic
