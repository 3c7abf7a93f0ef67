// The light chosen at a shading point: in proportion to each light's contribution estimate there,
// the environment with a fixed share, the probabilities it reports are the ones it samples with,
// and a light that cannot reach the point is never chosen.
#include "lights/local_light_sampler.h"

#include <gtest/gtest.h>

#include "lights/directional_light.h"
#include "lights/environment_light.h"
#include "lights/point_light.h"
#include "lights/spot_light.h"

namespace caustic {
namespace {

TEST(LocalLightSampler, ChoosesByContributionAtThePoint) {
    Bounds3 box;
    box.extend(Vec3(-1.0f));
    box.extend(Vec3(1.0f));
    std::vector<std::unique_ptr<Light>> lights;
    lights.push_back(std::make_unique<PointLight>(Vec3(0, 2, 0), Color(1.0f)));
    // A spot aimed away from the point: it cannot light it.
    lights.push_back(
        std::make_unique<SpotLight>(Vec3(0, 2, 0), Vec3(1, 0, 0), Color(100.0f), 10.0f, 20.0f));
    lights.push_back(std::make_unique<DirectionalLight>(Vec3(0, -1, 0), Color(0.5f), box));
    lights.push_back(std::make_unique<EnvironmentLight>(Color(0.3f), box));
    const LightSampler byPower(lights);
    const LocalLightSampler sampler(lights, 3, byPower);
    SurfaceInteraction si;
    si.p = si.pError = Vec3(0.0f);
    si.n = si.ns = Vec3(0, 1, 0);
    const LightSampleContext ctx(si);
    // Point: 1 / 2^2 = 0.25; spot: 0; directional: 0.5; the environment: half of the choices.
    EXPECT_FLOAT_EQ(sampler.pmf(ctx, 0), 0.5f * 0.25f / 0.75f);
    EXPECT_EQ(sampler.pmf(ctx, 1), 0.0f);
    EXPECT_FLOAT_EQ(sampler.pmf(ctx, 2), 0.5f * 0.5f / 0.75f);
    EXPECT_EQ(sampler.pmf(ctx, 3), 0.5f);
    int counts[4] = {0, 0, 0, 0};
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        auto s = sampler.sample(ctx, (float(i) + 0.5f) / float(n));
        ASSERT_TRUE(s);
        size_t index = 0;
        while (lights[index].get() != s->light) ++index;
        EXPECT_FLOAT_EQ(s->pmf, sampler.pmf(ctx, index));
        ++counts[index];
    }
    for (size_t i = 0; i < 4; ++i)
        EXPECT_NEAR(counts[i], n * sampler.pmf(ctx, i), 2.0) << "light " << i;
}

TEST(LocalLightSampler, AGrazingLightKeepsAShareBoundedBelow) {
    // A point light in the surface's geometric plane contributes through a shading normal or a
    // glossy lobe; its cosine counts as kMinImportanceCosine, not 0, so its samples' weight
    // (contribution / pmf) stays bounded.
    std::vector<std::unique_ptr<Light>> lights;
    lights.push_back(std::make_unique<PointLight>(Vec3(2, 0, 0), Color(1.0f)));  // grazing
    lights.push_back(std::make_unique<PointLight>(Vec3(0, 2, 0), Color(1.0f)));  // overhead
    const LightSampler byPower(lights);
    const LocalLightSampler sampler(lights, lights.size(), byPower);
    SurfaceInteraction si;
    si.p = si.pError = Vec3(0.0f);
    si.n = si.ns = Vec3(0, 1, 0);
    const LightSampleContext ctx(si);
    EXPECT_FLOAT_EQ(sampler.pmf(ctx, 0), kMinImportanceCosine / (1.0f + kMinImportanceCosine));
    EXPECT_FLOAT_EQ(sampler.pmf(ctx, 1), 1.0f / (1.0f + kMinImportanceCosine));
}

TEST(LocalLightSampler, ManyLightsAreChosenByPower) {
    std::vector<std::unique_ptr<Light>> lights;
    for (size_t i = 0; i <= LocalLightSampler::kMaxLights; ++i)
        lights.push_back(std::make_unique<PointLight>(Vec3(float(i), 1, 0), Color(float(i + 1))));
    const LightSampler byPower(lights);
    const LocalLightSampler sampler(lights, lights.size(), byPower);
    for (size_t i = 0; i < lights.size(); i += 7)
        EXPECT_EQ(sampler.pmf(Vec3(0.0f), i), byPower.pmf(i));
}

}  // namespace
}  // namespace caustic
