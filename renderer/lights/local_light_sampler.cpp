#include "lights/local_light_sampler.h"

namespace caustic {

LocalLightSampler::LocalLightSampler(const std::vector<std::unique_ptr<Light>>& lights,
                                     size_t environment, const LightSampler& byPower) {
    if (lights.size() > kMaxLights) {
        byPower_ = &byPower;
        return;
    }
    for (const auto& light : lights) lights_.push_back(light.get());
    environment_ = environment;
    hasEnvironment_ = environment < lights.size();
}

double LocalLightSampler::importances(const LightSampleContext& ctx, float* out) const {
    double total = 0.0;
    for (size_t i = 0; i < lights_.size(); ++i) {
        out[i] = hasEnvironment_ && i == environment_ ? 0.0f : lights_[i]->importance(ctx);
        total += double(out[i]);
    }
    return total;
}

std::optional<SampledLight> LocalLightSampler::sample(const LightSampleContext& ctx,
                                                      float u) const {
    if (byPower_) return byPower_->sample(u);
    if (lights_.empty()) return std::nullopt;
    // One light: nothing to choose (and no importance to compute on every sample).
    if (lights_.size() == 1) return SampledLight{lights_[0], 1.0f};
    const float share = environmentShare();
    float importance[kMaxLights];
    const double total = importances(ctx, importance);
    // Nothing else can light the point: the environment alone, if any.
    if (!(total > 0.0))
        return hasEnvironment_ ? std::optional(SampledLight{lights_[environment_], 1.0f})
                               : std::nullopt;
    if (u < share) return SampledLight{lights_[environment_], share};
    const double target = double((u - share) / (1.0f - share)) * total;
    double running = 0.0;
    size_t chosen = lights_.size();
    for (size_t i = 0; i < lights_.size(); ++i) {
        if (!(importance[i] > 0.0f)) continue;
        chosen = i;
        running += double(importance[i]);
        if (target < running) break;
    }
    return SampledLight{lights_[chosen], float((1.0 - share) * importance[chosen] / total)};
}

float LocalLightSampler::pmf(const LightSampleContext& ctx, size_t index) const {
    if (byPower_) return byPower_->pmf(index);
    if (index >= lights_.size()) return 0.0f;
    if (lights_.size() == 1) return 1.0f;
    float importance[kMaxLights];
    const double total = importances(ctx, importance);
    if (!(total > 0.0)) return hasEnvironment_ && index == environment_ ? 1.0f : 0.0f;
    const float share = environmentShare();
    if (hasEnvironment_ && index == environment_) return share;
    return float((1.0 - share) * importance[index] / total);
}

}  // namespace caustic
