// The directional albedo E(mu, roughness) of GGX reflection with a Fresnel factor of 1, and its
// cosine-weighted average over the hemisphere: the energy single scattering off the microsurface
// keeps. 1 - E is what the microfacet model loses by leaving out light that scatters between
// microfacets more than once, and what Kulla and Conty's multiple-scattering lobe adds back (Kulla
// and Conty 2017, "Revisiting Physically Based Shading at Imageworks", SIGGRAPH course).
#pragma once

#include <array>

namespace caustic {

class GgxAlbedo {
public:
    /// The table, computed on the first call (4 million visible-normal samples, about 0.1 s on
    /// 2 cores) by the loading of a scene with a rough conductor; then shared, read-only.
    /// Thread-safe.
    static const GgxAlbedo& get();

    /// E at mu = cos(theta_o) in [0, 1] and perceptual roughness in [0, 1] (alpha = roughness^2),
    /// interpolated bilinearly.
    float albedo(float mu, float roughness) const;
    /// 2 int_0^1 E(mu) mu dmu for the same piecewise-linear E, interpolated linearly in roughness:
    /// the exact average of what albedo() returns, so that the lobe it scales conserves energy.
    float average(float roughness) const;
    /// The same with the Fresnel factor (1 - wo.wm)^5 in place of 1: with it, the albedo of GGX
    /// reflection with Schlick's Fresnel term of any F0 is F0 albedo + (1 - F0) schlickAlbedo.
    float schlickAlbedo(float mu, float roughness) const;
    float schlickAverage(float roughness) const;

    static constexpr int kMu = 32, kRoughness = 32;

private:
    GgxAlbedo();
    struct Table {
        std::array<float, kMu * kRoughness> albedo{};
        std::array<float, kRoughness> average{};
        float at(float mu, float roughness) const;
        float averageAt(float roughness) const;
    };
    Table one_, schlick_;
};

}  // namespace caustic
