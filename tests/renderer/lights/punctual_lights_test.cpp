// Spot and directional lights: the light they give a point, and the photons they emit carry their
// power.
#include <gtest/gtest.h>

#include "core/rng.h"
#include "lights/directional_light.h"
#include "lights/spot_light.h"

namespace caustic {
namespace {

TEST(SpotLight, FallsOffAsGltfsSpotBetweenTheCones) {
    // glTF KHR_lights_punctual: t = (cos - cos outer) / (cos inner - cos outer), clamped, squared.
    SpotLight spot(Vec3(0.0f), Vec3(0, -2, 0), Color(1.0f), 20.0f, 40.0f);
    auto at = [](float degrees) {
        const float r = radians(degrees);
        return Vec3(std::sin(r), -std::cos(r), 0.0f);
    };
    EXPECT_FLOAT_EQ(spot.falloff(at(0)), 1.0f);
    EXPECT_FLOAT_EQ(spot.falloff(at(19.9f)), 1.0f);
    const float t = (std::cos(radians(30)) - std::cos(radians(40))) /
                    (std::cos(radians(20)) - std::cos(radians(40)));
    EXPECT_NEAR(spot.falloff(at(30)), t * t, 1e-6f);
    EXPECT_EQ(spot.falloff(at(40.1f)), 0.0f);
    EXPECT_EQ(spot.falloff(at(120)), 0.0f);
}

TEST(SpotLight, GivesIntensityTimesFalloffOverDistanceSquared) {
    SpotLight spot(Vec3(0, 2, 0), Vec3(0, -1, 0), Color(8, 4, 2), 10.0f, 30.0f);
    auto s = spot.sampleLi(Vec3(0.0f), Vec2(0.5f));
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->Li.r, 2.0f);
    EXPECT_EQ(s->wi, Vec3(0, 1, 0));
    EXPECT_FALSE(spot.sampleLi(Vec3(3, 0, 0), Vec2(0.5f)));  // outside the cone
    // A hard-edged cone (inner == outer).
    SpotLight hard(Vec3(0, 2, 0), Vec3(0, -1, 0), Color(1.0f), 30.0f, 30.0f);
    EXPECT_FLOAT_EQ(hard.falloff(glm::normalize(Vec3(0.5f, -1, 0))), 1.0f);
    EXPECT_EQ(hard.falloff(glm::normalize(Vec3(0.6f, -1, 0))), 0.0f);
}

TEST(PunctualLights, PhotonsCarryTheirPower) {
    Bounds3 box;
    box.extend(Vec3(-1, 0, -2));
    box.extend(Vec3(3, 1, 2));
    SpotLight spot(Vec3(0.0f), Vec3(1, -1, 0), Color(3, 2, 1), 15.0f, 50.0f);
    DirectionalLight sun(Vec3(1, -2, 0.5f), Color(2, 1, 0.5f), box);
    for (const Light* light : {static_cast<const Light*>(&spot), static_cast<const Light*>(&sun)}) {
        Rng rng = Rng::forSample(7, 0, 0, 0);
        DVec3 sum(0.0);
        const int n = 200000;
        for (int i = 0; i < n; ++i)
            if (auto le = light->sampleLe(rng.uniform2(), rng.uniform2())) sum += DVec3(le->power);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(sum[c] / n, light->power()[c], 0.01 * light->power()[c]) << "channel " << c;
    }
}

TEST(DirectionalLight, LightsEveryPointAlongOneDirection) {
    Bounds3 box;
    box.extend(Vec3(-1.0f));
    box.extend(Vec3(1.0f));
    DirectionalLight sun(Vec3(0, -2, 0), Color(3.0f), box);
    auto s = sun.sampleLi(Vec3(0.5f, -0.5f, 0.2f), Vec2(0.1f));
    ASSERT_TRUE(s);
    EXPECT_EQ(s->wi, Vec3(0, 1, 0));
    EXPECT_FLOAT_EQ(s->Li.g, 3.0f);
    // The shadow ray's far end is outside the scene.
    EXPECT_GT(s->at.p.y, 1.0f);
    // Its flux: E pi R^2, R the bounding sphere's radius sqrt(3).
    EXPECT_NEAR(sun.power().r, 3.0f * kPi * 3.0f, 1e-4f);
}

}  // namespace
}  // namespace caustic
