// glTF's alpha: a mask cuts a surface out where its alpha is below the cutoff, for camera rays and
// shadow rays alike; a blend lets a ray through with probability 1 - alpha; bad alpha fields are
// errors at their JSON path.
#include <gtest/gtest.h>

#include "core/error.h"
#include "render/renderer.h"
#include "support/temp_dir.h"
#include "support/test_scenes.h"
#include "support/texture_images.h"

namespace caustic {
namespace {

using nlohmann::json;

// A black dielectric quad facing the camera, filling the middle of a 16 x 16 image, before a
// white environment.
json cardScene(const json& card) {
    return testing::withMaterial(R"({
      "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 30, "width": 16, "height": 16},
      "shapes": [{"type": "quad", "origin": [-0.4, -0.4, 0], "u": [0.8, 0, 0], "v": [0, 0.8, 0],
                  "material": "card"}],
      "environment": {"color": [1, 1, 1]}
    })",
                                 "card", card);
}

std::vector<float> renderIn(const testing::TempDir& dir, const json& doc, int spp) {
    auto scene = testing::loadWithAssets(dir, doc);
    return render(*scene,
                  testing::settingsFrom({{"integrator", "path"}, {"spp", spp}, {"seed", 5}}))
        .film->meanRgb();
}

double meanOver(const std::vector<float>& rgb, int x0, int x1, int y0, int y1) {
    double sum = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) sum += rgb[3 * size_t(y * 16 + x)];
    return sum / double((x1 - x0) * (y1 - y0));
}

const json kBlack = {
    {"type", "metallic_roughness"}, {"base_color", {0, 0, 0}}, {"metallic", 0}, {"roughness", 1}};

TEST(Alpha, AMaskCutsOutTheTexelsBelowTheCutoff) {
    testing::TempDir dir;
    // Alpha 0.2 on the image's left half, 0.9 on its right.
    testing::writeTextureImage(dir.path() / "half.png", 8, 8, 4, [](int x, int, int c) {
        return c < 3 ? 1.0f : x < 4 ? 0.2f : 0.9f;
    });
    json card = kBlack;
    card["base_color_texture"] = "half.png";
    card["alpha_mode"] = "mask";
    card["alpha_cutoff"] = 0.5;
    const std::vector<float> rgb = renderIn(dir, cardScene(card), 4);
    // The card spans pixels 4..11; well inside each half:
    const double left = meanOver(rgb, 5, 7, 5, 11), right = meanOver(rgb, 9, 11, 5, 11);
    EXPECT_NEAR(left, 1.0, 1e-4) << "the environment, through the cut-out half";
    EXPECT_LT(right, 0.1) << "the black card";
}

TEST(Alpha, ABlendIsHitWithProbabilityAlpha) {
    testing::TempDir dir;
    const std::vector<float> opaque = renderIn(dir, cardScene(kBlack), 64);
    json card = kBlack;
    card["alpha_mode"] = "blend";
    card["alpha"] = 0.3;
    const std::vector<float> blended = renderIn(dir, cardScene(card), 64);
    const double r = meanOver(opaque, 5, 11, 5, 11), b = meanOver(blended, 5, 11, 5, 11);
    std::printf("opaque card %.4f, alpha 0.3 blended %.4f, expected %.4f\n", r, b, 0.7 + 0.3 * r);
    // 36 pixels x 64 samples, each through with probability 0.7: a standard error of 0.0095 on
    // the fraction; 4 of them.
    EXPECT_NEAR(b, 0.7 + 0.3 * r, 0.04) << "opaque card " << r;
}

TEST(Alpha, ShadowRaysPassThroughCutOutSurfaces) {
    testing::TempDir dir;
    json doc = json::parse(R"({
      "camera": {"position": [0, 3, 0.01], "look_at": [0, 0, 0], "fov": 30, "width": 8, "height": 8},
      "materials": {"floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
                    "veil": {"type": "metallic_roughness", "alpha_mode": "mask", "alpha": 0}},
      "shapes": [{"type": "quad", "origin": [-5, 0, -5], "u": [0, 0, 10], "v": [10, 0, 0],
                  "material": "floor"}],
      "lights": [{"type": "directional", "direction": [0.3, -1, 0.2], "irradiance": [2, 2, 2]}]
    })");
    const std::vector<float> bare = renderIn(dir, doc, 4);
    // A fully cut-out sheet between the floor, the camera and the light.
    doc["shapes"].push_back(json::parse(
        R"({"type": "quad", "origin": [-5, 1, -5], "u": [0, 0, 10], "v": [10, 0, 0], "material": "veil"})"));
    const std::vector<float> veiled = renderIn(dir, doc, 4);
    ASSERT_EQ(bare.size(), veiled.size());
    for (size_t i = 0; i < bare.size(); ++i) EXPECT_NEAR(veiled[i], bare[i], 1e-4f) << i;
}

TEST(Alpha, BadAlphaFieldsAreErrorsAtTheirPath) {
    testing::TempDir dir;
    auto expectError = [&](const json& fields, const std::string& path, const std::string& what) {
        json card = kBlack;
        card.update(fields);
        try {
            renderIn(dir, cardScene(card), 1);
            FAIL() << fields.dump();
        } catch (const InputError& e) {
            EXPECT_EQ(e.path(), path);
            EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
        }
    };
    expectError({{"alpha_mode", "clip"}}, "/materials/card/alpha_mode", "blend, mask, opaque");
    expectError({{"alpha", 1.5}}, "/materials/card/alpha", "must be in [0, 1]");
    expectError({{"alpha_cutoff", 0.3}}, "/materials/card/alpha_cutoff",
                "applies to \"alpha_mode\": \"mask\" only");
    expectError({{"alpha_mode", "mask"}, {"alpha_cutoff", -1}}, "/materials/card/alpha_cutoff",
                "must be in [0, 1]");
}

}  // namespace
}  // namespace caustic
