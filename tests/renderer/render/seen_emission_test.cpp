// The emission seen directly, estimated over emission_samples camera rays per sample
// (render/seen_emission.h): exact to the stratification's bound at a lamp's edge for every
// integrator, conservative in what it skips, and free where no emitter can be seen.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "core/rng.h"
#include "render/seen_emission.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::mergePatched;
using testing::sceneFromJson;
using testing::settingsFrom;

constexpr float kLe = 2.0f;

// A black-albedo lamp filling the right part of the view from world x = 0.1234 on, facing the
// camera, over a black background: every pixel's value is kLe times the fraction of it the lamp
// covers, and nothing else (albedo 0 reflects nothing).
json lampEdgeScene() {
    return json::parse(R"({
      "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 30, "width": 32,
                 "height": 8},
      "materials": {"lamp": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [2, 2, 2]}},
      "shapes": [{"type": "quad", "origin": [0.1234, -10, 0], "u": [10, 0, 0], "v": [0, 20, 0],
                  "material": "lamp"}]
    })");
}

// The largest difference, over the pixels, between the image's red channel and kLe times the
// pixel's covered fraction. The edge is a vertical line on the screen (the lamp's plane faces
// the camera, so it projects linearly).
float worstEdgeError(const Scene& scene, const std::vector<float>& rgb) {
    float edge = 0, y = 0;
    // The loaded scene is stored relative to the camera's position, (0, 0, 4).
    EXPECT_TRUE(scene.camera.raster(Vec3(0.1234f, 0.0f, -4.0f), edge, y));
    float worst = 0;
    for (int py = 0; py < scene.camera.height(); ++py)
        for (int px = 0; px < scene.camera.width(); ++px) {
            float covered = std::clamp(float(px) + 1.0f - edge, 0.0f, 1.0f);
            float value = rgb[3 * size_t(py * scene.camera.width() + px)];
            worst = std::max(worst, std::abs(value - kLe * covered));
        }
    return worst;
}

TEST(SeenEmission, ALampsEdgeIsResolvedBySppTimesEmissionSamplesPoints) {
    // With the sobol samplers a pass's 16 x 8 points in a pixel are a (0,7,2)-net: one point in
    // each 1/128 of the pixel's width, so the covered fraction is off by at most 1/128 (and the
    // two passes' mean too); the samples' own 16 points resolve it to 1/16 only.
    auto scene = sceneFromJson(lampEdgeScene());
    const float bound = kLe / 128.0f + 1e-4f;  // and the rounding of the edge's projection
    for (const std::string& integrator : testing::integratorVariants()) {
        for (const std::string sampler : {"sobol", "sobol_sequence"}) {
            SCOPED_TRACE(integrator + ", " + sampler);
            json base =
                mergePatched(testing::integratorVariant(integrator), {{"spp", 32},
                                                                      {"spp_per_pass", 16},
                                                                      {"sampler", sampler},
                                                                      {"photons", 1000},
                                                                      {"indirect_photons", 1000}});
            RenderResult split = render(*scene, settingsFrom(base));
            EXPECT_LE(worstEdgeError(*scene, split.film->meanRgb()), bound);
            EXPECT_EQ(split.stats.droppedSamples, 0u);
            // The samples' own rays do worse: the bound has teeth.
            RenderResult own =
                render(*scene, settingsFrom(mergePatched(base, {{"emission_samples", 0}})));
            EXPECT_GT(worstEdgeError(*scene, own.film->meanRgb()), bound);
        }
    }
}

TEST(SeenEmission, SkipsOnlyPixelsThroughWhichNoEmitterIsSeen) {
    auto scene = sceneFromJson(testing::exampleScene("cornell-box", 48, 36));
    auto accel = createAccelerator("embree", scene->geometry);
    SeenEmission seen(*scene, *accel);
    ASSERT_TRUE(seen.any());
    int outlined = 0, seenPixels = 0;
    Rng rng(7);
    for (int y = 0; y < scene->camera.height(); ++y)
        for (int x = 0; x < scene->camera.width(); ++x) {
            const bool may = seen.mayBeSeenIn(x, y);
            outlined += may;
            bool lampSeen = false;
            for (int i = 0; i < 64; ++i) {
                Vec2 u = rng.uniform2();
                Ray ray = scene->camera.generateRay(float(x) + u.x, float(y) + u.y);
                std::optional<Hit> hit = accel->intersect(ray, kInfinity);
                uint64_t rays = 0;
                Color Le = seen.along(ray, rays, 1.0f);
                bool emits = hit && scene->material(hit->prim).isEmissive();
                // along() sees what the accelerator finds, and skips no ray that meets a lamp.
                EXPECT_EQ(!isBlack(Le), emits) << x << ", " << y;
                lampSeen = lampSeen || emits;
            }
            if (lampSeen) {
                EXPECT_TRUE(may) << "pixel " << x << ", " << y;
            }
            seenPixels += lampSeen;
        }
    EXPECT_GT(seenPixels, 0);
    // The lamp's outline is a small part of the screen.
    EXPECT_LT(outlined, 4 * seenPixels);
}

TEST(SeenEmission, AnEmitterReachingBehindTheCameraMayBeSeenAnywhere) {
    // A lamp floor running under and behind the camera: its box has corners behind the camera,
    // which do not project.
    auto scene = sceneFromJson(json::parse(R"({
      "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 30, "width": 8, "height": 8},
      "materials": {"lamp": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [1, 1, 1]}},
      "shapes": [{"type": "quad", "origin": [-10, -1, 10], "u": [20, 0, 0], "v": [0, 0, -20],
                  "material": "lamp"}]
    })"));
    auto accel = createAccelerator("embree", scene->geometry);
    SeenEmission seen(*scene, *accel);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) EXPECT_TRUE(seen.mayBeSeenIn(x, y)) << x << ", " << y;
}

TEST(SeenEmission, PixelsThatCannotSeeAnEmitterAreUnchangedToTheBit) {
    // The samples' own random numbers do not move: where no extra ray is traced, the image is
    // the one without them, bit for bit.
    auto scene = sceneFromJson(testing::exampleScene("cornell-box", 32, 24));
    const json base{{"spp", 8}, {"spp_per_pass", 4}, {"sampler", "sobol"}};
    RenderResult own = render(*scene, settingsFrom(mergePatched(base, {{"emission_samples", 0}})));
    RenderResult split = render(*scene, settingsFrom(base));
    std::vector<float> a = own.film->meanRgb(), b = split.film->meanRgb();
    auto accel = createAccelerator("embree", scene->geometry);
    SeenEmission seen(*scene, *accel);
    int skipped = 0, outlined = 0, changed = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            const size_t i = 3 * size_t(y * 32 + x);
            const bool same = std::memcmp(&a[i], &b[i], 3 * sizeof(float)) == 0;
            if (seen.mayBeSeenIn(x, y)) {
                ++outlined;
                changed += !same;
            } else {
                ++skipped;
                EXPECT_TRUE(same) << "pixel " << x << ", " << y;
            }
        }
    EXPECT_GT(skipped, 24 * 32 / 2);
    EXPECT_GT(changed, 0);
    // The extra rays are counted, at most 8 a sample in the outlined pixels.
    EXPECT_GT(split.stats.rays, own.stats.rays);
    EXPECT_LE(split.stats.rays - own.stats.rays, uint64_t(8 * 8 * outlined));
}

}  // namespace
}  // namespace caustic
