#include "lights/light_sampler.h"

#include <algorithm>

namespace caustic {

LightSampler::LightSampler(const std::vector<std::unique_ptr<Light>>& lights)
    : pmfByIndex_(lights.size(), 0.0f) {
    std::vector<double> power;
    double total = 0.0;
    for (size_t i = 0; i < lights.size(); ++i) {
        double p = luminance(lights[i]->power());
        if (!(p > 0.0)) continue;
        chosen_.push_back(lights[i].get());
        indexOf_.push_back(i);
        power.push_back(p);
        total += p;
    }
    if (chosen_.empty()) return;
    cdf_.resize(chosen_.size() + 1);
    double running = 0.0;
    cdf_[0] = 0.0f;
    for (size_t i = 0; i < chosen_.size(); ++i) {
        running += power[i];
        cdf_[i + 1] = static_cast<float>(running / total);
        pmfByIndex_[indexOf_[i]] = static_cast<float>(power[i] / total);
    }
    cdf_.back() = 1.0f;
}

std::optional<SampledLight> LightSampler::sample(float u) const {
    if (chosen_.empty()) return std::nullopt;
    // First interval whose upper end exceeds u; never one of zero width.
    auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), u);
    size_t i = std::min<size_t>(static_cast<size_t>(it - cdf_.begin()) - 1, chosen_.size() - 1);
    return SampledLight{chosen_[i], pmfByIndex_[indexOf_[i]]};
}

float LightSampler::pmf(size_t index) const {
    return index < pmfByIndex_.size() ? pmfByIndex_[index] : 0.0f;
}

size_t LightSampler::memoryBytes() const {
    return chosen_.capacity() * sizeof(const Light*) + indexOf_.capacity() * sizeof(size_t) +
           cdf_.capacity() * sizeof(float) + pmfByIndex_.capacity() * sizeof(float);
}

}  // namespace caustic
