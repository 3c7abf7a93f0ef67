// Textured materials in scenes: a constant texture renders as its factor would, a normal map turns
// the shading normal as glTF defines (tangent along +s, bitangent up the image), MikkTSpace
// tangents on a mesh, and every bad texture field is an error at its JSON path.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "render/renderer.h"
#include "scene/mesh_tangents.h"
#include "support/temp_dir.h"
#include "support/test_scenes.h"
#include "support/texture_images.h"

namespace caustic {
namespace {

using nlohmann::json;

json quadScene(const json& material) {
    return testing::withMaterial(R"({
      "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 30, "width": 8, "height": 8},
      "shapes": [{"type": "quad", "origin": [-2, -2, 0], "u": [4, 0, 0], "v": [0, 4, 0],
                  "material": "m"}],
      "lights": [{"type": "directional", "direction": [0.3, -0.2, -1], "irradiance": [2, 2, 2]}]
    })",
                                 "m", material);
}

std::unique_ptr<Scene> load(const testing::TempDir& dir, const json& doc) {
    return testing::loadWithAssets(dir, doc);
}

TEST(TexturedScene, AConstantTextureRendersAsItsValueTimesTheFactor) {
    testing::TempDir dir;
    // sRGB 8-bit (188, 120, 40) and a metallic-roughness texture of G = 0.6, B = 0.25.
    const float rgb[3] = {188.0f / 255.0f, 120.0f / 255.0f, 40.0f / 255.0f};
    testing::writeTextureImage(dir.path() / "base.png", 8, 8, 3,
                               [&](int, int, int c) { return rgb[c]; });
    testing::writeTextureImage(dir.path() / "mr.png", 8, 8, 3, [](int, int, int c) {
        return c == 1 ? 153.0f / 255.0f : c == 2 ? 64.0f / 255.0f : 0.0f;
    });
    const json textured = quadScene({{"type", "metallic_roughness"},
                                     {"base_color", {1.0, 0.5, 1.0}},
                                     {"metallic", 1.0},
                                     {"roughness", 0.5},
                                     {"base_color_texture", "base.png"},
                                     {"metallic_roughness_texture", "mr.png"}});
    auto decode = [](float v) { return std::pow((v + 0.055f) / 1.055f, 2.4f); };
    const json plain =
        quadScene({{"type", "metallic_roughness"},
                   {"base_color", {decode(rgb[0]), 0.5f * decode(rgb[1]), decode(rgb[2])}},
                   {"metallic", 64.0 / 255.0},
                   {"roughness", 0.5 * 153.0 / 255.0}});
    const RenderSettings settings =
        testing::settingsFrom({{"integrator", "raycast"}, {"spp", 4}, {"seed", 3}});
    const std::vector<float> a = render(*load(dir, textured), settings).film->meanRgb();
    const std::vector<float> b = render(*load(dir, plain), settings).film->meanRgb();
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        EXPECT_NEAR(a[i], b[i], 2e-3f * std::max(1.0f, b[i])) << "value " << i;
}

// The normal a constant normal map gives at the quad's centre: the quad faces +z with s along +x
// and the image's top at +y, so tangent-space (x, y, z) is world (x, y, z).
Vec3 mappedNormalAtCentre(const testing::TempDir& dir, const Vec3& encoded, float scale = 1.0f) {
    testing::writeTextureImage(dir.path() / "normal.png", 4, 4, 3,
                               [&](int, int, int c) { return encoded[c]; });
    auto scene =
        load(dir, quadScene({{"type", "metallic_roughness"},
                             {"normal_texture", {{"file", "normal.png"}, {"scale", scale}}}}));
    const Ray ray{Vec3(0.0f, 0.0f, 3.0f), Vec3(0.0f, 0.0f, -1.0f)};
    Hit hit;
    const Geometry& g = scene->geometry;
    auto h = g.intersect(0, ray, kInfinity);
    EXPECT_TRUE(h.has_value());
    g.finish(0, ray, *h, hit);
    SurfaceInteraction si = g.interaction(ray, hit);
    MaterialScratch scratch;
    scene->shade(si, scratch);
    return si.ns;
}

TEST(TexturedScene, ANormalMapTurnsTheShadingNormalInTheTangentFrame) {
    testing::TempDir dir;
    auto encode = [](const Vec3& n) { return 0.5f * n + Vec3(0.5f); };
    const Vec3 tilted = glm::normalize(Vec3(0.4f, -0.3f, 0.8f));
    const Vec3 ns = mappedNormalAtCentre(dir, encode(tilted));
    // 8-bit rounding of the encoded normal: within 0.01.
    EXPECT_NEAR(ns.x, tilted.x, 0.01f);
    EXPECT_NEAR(ns.y, tilted.y, 0.01f);
    EXPECT_NEAR(ns.z, tilted.z, 0.01f);
    // glTF's scale multiplies x and y before normalizing: 0 leaves the surface's normal.
    const Vec3 flat = mappedNormalAtCentre(dir, encode(tilted), 0.0f);
    EXPECT_NEAR(flat.z, 1.0f, 1e-4f);
    // A normal that points below the surface is brought back in front of it.
    const Vec3 below = mappedNormalAtCentre(dir, encode(glm::normalize(Vec3(1.0f, 0.0f, -0.5f))));
    EXPECT_GT(below.z, 0.0f);
}

TEST(MeshTangents, MikkTSpaceFollowsTheTextureLayoutAndSplitsSeams) {
    // A square in the xy plane, s along +x and the image's top at +y; the right half's
    // coordinates mirrored in s (a seam at x = 1, where MikkTSpace's tangent flips).
    TriangleMesh mesh;
    mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0),
                      Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)};
    mesh.texcoords = {Vec2(0, 1), Vec2(1, 1), Vec2(1, 0), Vec2(0, 0), Vec2(0, 1), Vec2(0, 0)};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
    const std::vector<glm::vec4> tangents = generateTangents(mesh);
    ASSERT_EQ(tangents.size(), mesh.positions.size());
    // Vertices 1 and 2 lie on the seam: each is split in two.
    EXPECT_EQ(mesh.positions.size(), 8u);
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
        for (int c = 0; c < 3; ++c) {
            const glm::vec4& t = tangents[mesh.triangles[f][c]];
            const float expectedX = f < 2 ? 1.0f : -1.0f;
            EXPECT_NEAR(t.x, expectedX, 1e-5f) << "face " << f;
            EXPECT_NEAR(t.y, 0.0f, 1e-5f);
            // The bitangent sign (n x t) makes it point up the image (+y) on both sides.
            const Vec3 bitangent = t.w * glm::cross(Vec3(0, 0, 1), Vec3(t));
            EXPECT_NEAR(bitangent.y, 1.0f, 1e-5f) << "face " << f;
        }
}

void expectTextureError(const testing::TempDir& dir, const json& material, const std::string& path,
                        const std::string& what, bool admission = false) {
    SceneOptions options;
    options.assetsDir = dir.path();
    options.countMeshesOnly = admission;
    options.maxPixels = 1000;
    try {
        loadScene(quadScene(material), options);
        FAIL() << "no error for " << material.dump();
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), path) << e.message();
        EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
    }
}

TEST(TexturedScene, BadTextureFieldsAreErrorsAtTheirJsonPath) {
    testing::TempDir dir;
    testing::writeChecker(dir.path() / "small.png", 16, 2);
    testing::writeChecker(dir.path() / "large.png", 64, 2);
    testing::writeTextureImage(dir.path() / "inf.exr", 4, 4, 3,
                               [](int x, int, int) { return x == 3 ? INFINITY : 1.0f; });
    dir.write("broken.png", "\x89PNG but not really");
    const std::string at = "/materials/m/base_color_texture";
    auto with = [](const json& texture) {
        return json{{"type", "metallic_roughness"}, {"base_color_texture", texture}};
    };
    expectTextureError(dir, with("missing.png"), at,
                       "no file \"missing.png\" in the assets folder");
    expectTextureError(dir, with({{"file", "../small.png"}}), at + "/file", "must not leave");
    expectTextureError(dir, with("broken.png"), at, "cannot read image broken.png");
    expectTextureError(dir, with("large.png"), at, "is 64 x 64 pixels, over the limit of 1000");
    expectTextureError(dir, with("large.png"), at, "over the limit of 1000", /*admission=*/true);
    expectTextureError(dir, with("inf.exr"), at, "texel (3, 0) is negative or not finite");
    expectTextureError(dir, with({{"file", "small.png"}, {"filter", "bicubic"}}), at + "/filter",
                       "anisotropic");
    expectTextureError(dir, with({{"file", "small.png"}, {"wrap", "clamp"}}), at + "/wrap",
                       "unknown field; valid fields here: embedded, file, filter, transform");
    expectTextureError(dir, with({{"file", "small.png"}, {"transform", {{"scale", {1}}}}}),
                       at + "/transform/scale", "must be an array of 2 numbers");
    // "scale" is a normal map's alone.
    expectTextureError(dir, with({{"file", "small.png"}, {"scale", 2}}), at + "/scale",
                       "unknown field");
    expectTextureError(dir, with(3), at, "");
    expectTextureError(dir,
                       {{"type", "metallic_roughness"},
                        {"normal_texture", {{"file", "small.png"}, {"scale", -1}}}},
                       "/materials/m/normal_texture/scale", "must be >= 0");
}

}  // namespace
}  // namespace caustic

namespace caustic {
namespace {

TEST(ObjTexcoords, VtIsReadPerCornerWithTRunningDownTheImage) {
    std::istringstream obj(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.25 0.5\n"
        "f 1/1 2/2 3/3\nf 1/5 3/3 4/4\n");
    const TriangleMesh mesh = parseObj(obj, "t.obj", MeshTransform{}, "/shapes/0/file", true);
    // Vertex 1 appears with two texture coordinates: two vertices.
    ASSERT_EQ(mesh.positions.size(), 5u);
    ASSERT_EQ(mesh.texcoords.size(), 5u);
    EXPECT_TRUE(mesh.normals.empty());
    EXPECT_EQ(mesh.texcoords[mesh.triangles[0][0]], Vec2(0.0f, 1.0f));
    EXPECT_EQ(mesh.texcoords[mesh.triangles[0][2]], Vec2(1.0f, 0.0f));
    EXPECT_EQ(mesh.texcoords[mesh.triangles[1][0]], Vec2(0.25f, 0.5f));
    EXPECT_EQ(mesh.positions[mesh.triangles[1][0]], Vec3(0.0f));
    // Without a textured material they are not read: the positions stay as the file has them.
    obj.clear();
    obj.seekg(0);
    const TriangleMesh plain = parseObj(obj, "t.obj", MeshTransform{}, "/shapes/0/file");
    EXPECT_EQ(plain.positions.size(), 4u);
    EXPECT_TRUE(plain.texcoords.empty());
    std::istringstream bad("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nf 1/1 2/2 3/3\n");
    EXPECT_THROW(parseObj(bad, "t.obj", MeshTransform{}, "/shapes/0/file", true), InputError);
}

}  // namespace
}  // namespace caustic
