// Chooses the light a shading point samples by the light's estimated contribution there, not by
// its power alone (pbrt-v4 12.6.3, ExhaustiveLightSampler, with simpler bounds): a dim spot light
// that shines on the point is chosen over a bright sun that the point faces away from. An
// environment is chosen with a fixed probability (1/2 beside other lights, as pbrt-v4's
// BVHLightSampler does for infinite lights). With more than kMaxLights lights (an emissive mesh's
// triangles) it chooses by power, as the photon tracer does. Built once per scene; thread-safe.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "lights/light.h"
#include "lights/light_sampler.h"

namespace caustic {

class LocalLightSampler {
public:
    static constexpr size_t kMaxLights = 64;

    LocalLightSampler() = default;
    /// Over `lights` (which must outlive it); `environment` is its index there, or lights.size()
    /// for none; `byPower` the scene's power sampler, used beyond kMaxLights.
    LocalLightSampler(const std::vector<std::unique_ptr<Light>>& lights, size_t environment,
                      const LightSampler& byPower);

    /// A light for the point, from u in [0,1); nullopt when none can light it.
    std::optional<SampledLight> sample(const LightSampleContext& ctx, float u) const;
    /// The probability that sample(ctx, .) picks light `index` (for multiple importance sampling).
    float pmf(const LightSampleContext& ctx, size_t index) const;

private:
    /// Each light's importance at the point (0 for the environment) and their sum.
    double importances(const LightSampleContext& ctx, float* out) const;
    float environmentShare() const {
        return !hasEnvironment_ ? 0.0f : lights_.size() > 1 ? 0.5f : 1.0f;
    }

    std::vector<const Light*> lights_;
    size_t environment_ = 0;
    bool hasEnvironment_ = false;
    const LightSampler* byPower_ = nullptr;  // non-null: choose by power
};

}  // namespace caustic
