#include "materials/multiple_scattering.h"

#include "materials/ggx_albedo.h"

namespace caustic {

MultipleScatteringLobe::MultipleScatteringLobe(float roughness, const Color& averageFresnel)
    : roughness_(roughness) {
    const float averageAlbedo = GgxAlbedo::get().average(roughness);
    if (!(1.0f - averageAlbedo >= 1e-6f)) return;
    enabled_ = true;
    scale_ = 1.0f / (kPi * (1.0f - averageAlbedo));
    // F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)): the light that leaves after any number of
    // bounces between microfacets, each losing 1 - F_avg (Kulla and Conty 2017, slide 21).
    colour_ = averageFresnel * averageFresnel * averageAlbedo /
              (Color(1.0f) - averageFresnel * (1.0f - averageAlbedo));
}

float MultipleScatteringLobe::lost(float mu) const {
    return enabled_ ? 1.0f - GgxAlbedo::get().albedo(mu, roughness_) : 0.0f;
}

}  // namespace caustic
