// Chooses a light in proportion to its power. Lights of zero power are never chosen and cost
// nothing. Built once per scene; const and thread-safe.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "lights/light.h"

namespace caustic {

struct SampledLight {
    const Light* light;
    float pmf;  ///< Probability with which it was chosen.
};

class LightSampler {
public:
    LightSampler() = default;
    /// Indexes `lights` (which must outlive it) by the luminance of their power.
    explicit LightSampler(const std::vector<std::unique_ptr<Light>>& lights);

    /// The light whose cumulative power interval holds u in [0,1); nullopt when nothing emits.
    std::optional<SampledLight> sample(float u) const;
    /// Probability of choosing light `index` (an index into the constructor's vector).
    float pmf(size_t index) const;
    bool empty() const { return chosen_.empty(); }
    size_t memoryBytes() const;

private:
    std::vector<const Light*> chosen_;  // lights with power > 0
    std::vector<size_t> indexOf_;       // their index in the scene's vector
    std::vector<float> cdf_;            // cdf_[i] = power of chosen_[0..i) / total; size n + 1
    std::vector<float> pmfByIndex_;
};

}  // namespace caustic
