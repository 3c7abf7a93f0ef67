// Kulla and Conty's multiple-scattering lobe for GGX reflection ("Revisiting Physically Based
// Shading at Imageworks", SIGGRAPH 2017 course): the energy that single scattering off the
// microsurface loses, returned as a reciprocal, diffuse-like lobe coloured by the Fresnel term's
// average. With it a white rough metal in a white furnace stays white.
#pragma once

#include "core/math.h"

namespace caustic {

class MultipleScatteringLobe {
public:
    /// No lobe.
    MultipleScatteringLobe() = default;
    /// The lobe of GGX at perceptual `roughness` whose reflection has hemispherical-average
    /// Fresnel term `averageFresnel`; none when single scattering loses nothing.
    MultipleScatteringLobe(float roughness, const Color& averageFresnel);

    bool enabled() const { return enabled_; }
    /// 1 - E(mu): the energy single scattering loses from a direction of cosine mu (0 without the
    /// lobe). It is the share of the lobe in the directional albedo.
    float lost(float mu) const;
    /// f of the lobe for cosines muO, muI > 0: F_ms (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)),
    /// which integrates against cos_i to F_ms (1 - E(mu_o)).
    Color f(float muO, float muI) const {
        return enabled_ ? colour_ * (lost(muO) * lost(muI) * scale_) : Color(0.0f);
    }

private:
    bool enabled_ = false;
    float roughness_ = 0.0f;
    float scale_ = 0.0f;  // 1 / (pi (1 - E_avg))
    Color colour_{0.0f};  // F_ms
};

}  // namespace caustic
