// Scene loading: every kind of bad scene is an InputError with the exact JSON path and message.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "lights/area_light.h"
#include "lights/point_light.h"
#include "materials/dielectric.h"
#include "materials/diffuse.h"
#include "renderer/scene/base_scene.h"
#include "scene/json_reader.h"
#include "scene/scene.h"
#include "support/temp_dir.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using testing::baseScene;
using testing::expectSceneError;
using testing::patched;
using testing::repoSceneOptions;
using testing::TempDir;
using testing::without;

Json withShape(const Json& shape) {
    Json doc = baseScene();
    doc["shapes"][0] = shape;
    return doc;
}

Json meshShape(const std::string& file) {
    return Json{{"type", "mesh"}, {"file", file}, {"material", "white"}};
}

// Each use is one bad-scene case; the trace names the line of the case that failed.
#define EXPECT_SCENE_ERROR_WITH(doc, path, message, options)   \
    do {                                                       \
        SCOPED_TRACE(path);                                    \
        expectSceneError((doc), (path), (message), (options)); \
    } while (0)
#define EXPECT_SCENE_ERROR(doc, path, message) \
    EXPECT_SCENE_ERROR_WITH(doc, path, message, repoSceneOptions())

// --- camera ---

TEST(SceneLoaderErrors, MissingCameraOrNotAnObject) {
    EXPECT_SCENE_ERROR(without("/camera"), "/camera", "missing required field");
    EXPECT_SCENE_ERROR(patched("/camera", {0, 0, 3}), "/camera",
                       "expected an object, got an array");
}

TEST(SceneLoaderErrors, CameraFieldMissingOrOfWrongType) {
    EXPECT_SCENE_ERROR(without("/camera/position"), "/camera/position", "missing required field");
    EXPECT_SCENE_ERROR(without("/camera/look_at"), "/camera/look_at", "missing required field");
    EXPECT_SCENE_ERROR(patched("/camera/fov", "40"), "/camera/fov",
                       "expected a number, got a string");
    EXPECT_SCENE_ERROR(patched("/camera/look_at", 0), "/camera/look_at",
                       "expected an array of 3 numbers, got a number");
    EXPECT_SCENE_ERROR(patched("/camera/width", "512"), "/camera/width",
                       "expected an integer, got a string");
}

TEST(SceneLoaderErrors, FovOutOfRange) {
    for (double fov : {0.0, 180.0, -10.0, 200.0})
        EXPECT_SCENE_ERROR(patched("/camera/fov", fov), "/camera/fov",
                           "must be in (0, 180) degrees");
}

TEST(SceneLoaderErrors, WidthZeroNegativeOrFractional) {
    EXPECT_SCENE_ERROR(patched("/camera/width", 0), "/camera/width",
                       "must be in [1, 16384], got 0");
    EXPECT_SCENE_ERROR(patched("/camera/width", -5), "/camera/width",
                       "must be in [1, 16384], got -5");
    EXPECT_SCENE_ERROR(patched("/camera/width", 2.5), "/camera/width",
                       "expected an integer, got a fraction");
}

TEST(SceneLoaderErrors, ResolutionTooLarge) {
    EXPECT_SCENE_ERROR(patched("/camera/height", 16385), "/camera/height",
                       "must be in [1, 16384], got 16385");
    SceneOptions small = repoSceneOptions();
    small.maxResolution = 1024;
    EXPECT_SCENE_ERROR_WITH(patched("/camera/height", 1025), "/camera/height",
                            "must be in [1, 1024], got 1025", small);
    // Larger than any integer: not wrapped around to a small or negative number.
    EXPECT_SCENE_ERROR(patched("/camera/height", std::numeric_limits<uint64_t>::max()),
                       "/camera/height", "is out of the range of an integer (|x| <= 2^53)");
    EXPECT_SCENE_ERROR(patched("/camera/height", 1e20), "/camera/height",
                       "is out of the range of an integer (|x| <= 2^53)");
}

TEST(SceneLoaderErrors, TooManyPixels) {
    SceneOptions options = repoSceneOptions();
    options.maxPixels = 1000000;
    Json doc = baseScene();
    doc["camera"]["width"] = 1000;
    doc["camera"]["height"] = 1000;
    EXPECT_NO_THROW(loadScene(doc, options));
    doc["camera"]["width"] = 1001;
    EXPECT_SCENE_ERROR_WITH(doc, "/camera/width", "width x height must be at most 1000000 pixels",
                            options);
}

TEST(SceneLoaderErrors, LookAtEqualsPosition) {
    EXPECT_SCENE_ERROR(patched("/camera/look_at", {0, 0, 3}), "/camera/look_at",
                       "must differ from position");
}

TEST(SceneLoaderErrors, UpParallelToViewOrZero) {
    for (Json up : {Json{0, 0, 2}, Json{0, 0, -1}, Json{0, 0, 0}})
        EXPECT_SCENE_ERROR(patched("/camera/up", up), "/camera/up",
                           "must not be zero or parallel to the viewing direction");
}

// --- unknown names ---

TEST(SceneLoaderErrors, UnknownTopLevelFieldListsValidFields) {
    EXPECT_SCENE_ERROR(patched("/light", Json::array()), "/light",
                       "unknown field; valid fields here: background, camera, environment, lights, "
                       "materials, "
                       "settings, shapes");
}

TEST(SceneLoaderErrors, UnknownFieldInCameraShapeOrMaterial) {
    EXPECT_SCENE_ERROR(
        patched("/camera/aperture", 0.1), "/camera/aperture",
        "unknown field; valid fields here: fov, height, look_at, position, up, width");
    EXPECT_SCENE_ERROR(
        patched("/shapes/0/colour", {1, 0, 0}), "/shapes/0/colour",
        "unknown field; valid fields here: center, flip_normals, material, radius, type");
    EXPECT_SCENE_ERROR(patched("/materials/white/roughness", 0.5), "/materials/white/roughness",
                       "unknown field; valid fields here: albedo, emission, type");
    EXPECT_SCENE_ERROR(
        patched("/materials/glass/albedo", {1, 1, 1}), "/materials/glass/albedo",
        "unknown field; valid fields here: emission, fresnel, ior, roughness, tint, type");
}

TEST(SceneLoaderErrors, UnknownTypesListValidTypes) {
    EXPECT_SCENE_ERROR(patched("/materials/white/type", "glossy"), "/materials/white/type",
                       "unknown value \"glossy\"; valid: conductor, dielectric, diffuse, "
                       "metallic_roughness, mirror");
    EXPECT_SCENE_ERROR(patched("/shapes/0/type", "cone"), "/shapes/0/type",
                       "unknown value \"cone\"; valid: mesh, quad, sphere, triangle");
}

TEST(SceneLoaderErrors, UnknownMaterialNameListsDefinedNames) {
    Json doc = patched("/shapes/0/material", "gold");
    EXPECT_SCENE_ERROR(doc, "/shapes/0/material", "unknown material \"gold\"; valid: glass, white");
    doc["materials"] = Json::object();
    EXPECT_SCENE_ERROR(doc, "/shapes/0/material",
                       "unknown material \"gold\"; valid: (none defined)");
}

TEST(SceneLoaderErrors, MaterialNameIsEscapedInPath) {
    Json doc = baseScene();
    doc["materials"]["walls/floor~1"] = {{"type", "diffuse"}, {"albedo", {2, 0, 0}}};
    EXPECT_SCENE_ERROR(doc, "/materials/walls~1floor~01/albedo/0",
                       "must be <= 1 (energy conservation)");
}

// --- numbers ---

TEST(SceneLoaderErrors, NonFiniteNumbers) {
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_SCENE_ERROR(patched("/camera/position/0", inf), "/camera/position/0",
                       "must be a finite number");
    EXPECT_SCENE_ERROR(patched("/camera/fov", -inf), "/camera/fov", "must be a finite number");
    EXPECT_SCENE_ERROR(patched("/shapes/0/radius", nan), "/shapes/0/radius",
                       "must be a finite number");
    EXPECT_SCENE_ERROR(patched("/materials/white/emission", {0, nan, 0}),
                       "/materials/white/emission/1", "must be a finite number");
    EXPECT_SCENE_ERROR(patched("/camera/width", inf), "/camera/width", "must be a finite number");
}

TEST(SceneLoaderErrors, NumberOverflowsFloat) {
    // Positions are checked after they are made relative to the camera.
    EXPECT_SCENE_ERROR(patched("/shapes/0/center/2", 1e308), "/shapes/0/center/2",
                       "is out of the range of a float (|x| <= 3e38) relative to the camera");
    EXPECT_SCENE_ERROR(patched("/shapes/0/center/2", -1e39), "/shapes/0/center/2",
                       "is out of the range of a float (|x| <= 3e38) relative to the camera");
    EXPECT_SCENE_ERROR(patched("/shapes/0/radius", 1e39), "/shapes/0/radius",
                       "is out of the range of a float (|x| <= 3e38)");
}

TEST(SceneLoaderErrors, NegativeAndZeroRadius) {
    for (double radius : {-0.5, 0.0, -0.0})
        EXPECT_SCENE_ERROR(patched("/shapes/0/radius", radius), "/shapes/0/radius", "must be > 0");
    EXPECT_SCENE_ERROR(patched("/shapes/0/flip_normals", 1), "/shapes/0/flip_normals",
                       "expected a boolean, got a number");
}

TEST(SceneLoaderErrors, Vec3WithTwoElementsOrAString) {
    EXPECT_SCENE_ERROR(patched("/shapes/0/center", {0, 0}), "/shapes/0/center",
                       "expected an array of 3 numbers, got an array of 2");
    EXPECT_SCENE_ERROR(patched("/shapes/0/center", {0, "1", 0}), "/shapes/0/center/1",
                       "expected a number, got a string");
}

// --- materials ---

TEST(SceneLoaderErrors, ReflectanceOutsideZeroToOne) {
    EXPECT_SCENE_ERROR(patched("/materials/white/albedo", {0.5, 1.01, 0.5}),
                       "/materials/white/albedo/1", "must be <= 1 (energy conservation)");
    EXPECT_SCENE_ERROR(patched("/materials/white/albedo", {0.5, 0.5, -0.1}),
                       "/materials/white/albedo/2", "must be >= 0");
    EXPECT_SCENE_ERROR(patched("/materials/m", {{"type", "mirror"}, {"reflectance", {1, 1, 1.5}}}),
                       "/materials/m/reflectance/2", "must be <= 1 (energy conservation)");
    EXPECT_SCENE_ERROR(patched("/materials/glass/tint", {2, 1, 1}), "/materials/glass/tint/0",
                       "must be <= 1 (energy conservation)");
}

TEST(SceneLoaderErrors, DielectricIorAndFresnel) {
    EXPECT_SCENE_ERROR(patched("/materials/glass/ior", 0), "/materials/glass/ior", "must be > 0");
    EXPECT_SCENE_ERROR(patched("/materials/glass/ior", -1.5), "/materials/glass/ior",
                       "must be > 0");
    EXPECT_SCENE_ERROR(patched("/materials/glass/fresnel", "fast"), "/materials/glass/fresnel",
                       "unknown value \"fast\"; valid: exact, schlick");
}

TEST(SceneLoaderErrors, ConductorRoughnessAndFresnel) {
    const auto metal = [](const std::vector<std::pair<std::string, Json>>& fields) {
        Json m{{"type", "conductor"}, {"roughness", 0.3}};
        for (const auto& [key, value] : fields) m[key] = value;
        return m;
    };
    EXPECT_SCENE_ERROR(patched("/materials/m", metal({{"roughness", 1.5}})),
                       "/materials/m/roughness", "must be in [0, 1]");
    EXPECT_SCENE_ERROR(patched("/materials/m", metal({{"roughness", -0.1}})),
                       "/materials/m/roughness", "must be in [0, 1]");
    EXPECT_SCENE_ERROR(patched("/materials/m", metal({{"f0", {1, 1.2, 1}}})), "/materials/m/f0/1",
                       "must be <= 1 (energy conservation)");
    const Json both = metal({{"f0", {1, 1, 1}}, {"eta", {0.2, 0.9, 1.1}}});
    EXPECT_SCENE_ERROR(patched("/materials/m", both), "/materials/m/f0",
                       "give either f0 or eta and k, not both");
    EXPECT_SCENE_ERROR(patched("/materials/m", metal({{"eta", {0.2, 0, 1.1}}})),
                       "/materials/m/eta/1", "must be > 0");
    EXPECT_SCENE_ERROR(
        patched("/materials/m", metal({{"eta", {0.2, 0.9, 1.1}}, {"k", {-1, 0, 1}}})),
        "/materials/m/k/0", "must be >= 0");
    EXPECT_SCENE_ERROR(patched("/materials/m", metal({{"multiple_scattering", 1}})),
                       "/materials/m/multiple_scattering", "expected a boolean, got a number");
    EXPECT_SCENE_ERROR(
        patched("/materials/m", metal({{"albedo", {1, 1, 1}}})), "/materials/m/albedo",
        "unknown field; valid fields here: emission, eta, f0, k, multiple_scattering, "
        "roughness, type");
}

TEST(SceneLoaderErrors, MetallicRoughnessFactors) {
    const auto gltf = [](const std::vector<std::pair<std::string, Json>>& fields) {
        Json m{{"type", "metallic_roughness"}};
        for (const auto& [key, value] : fields) m[key] = value;
        return m;
    };
    EXPECT_NO_THROW(loadScene(patched("/materials/m", gltf({})), repoSceneOptions()));
    EXPECT_SCENE_ERROR(patched("/materials/m", gltf({{"base_color", {0.5, 1.5, 0.5}}})),
                       "/materials/m/base_color/1", "must be <= 1 (energy conservation)");
    EXPECT_SCENE_ERROR(patched("/materials/m", gltf({{"metallic", 1.2}})), "/materials/m/metallic",
                       "must be in [0, 1]");
    EXPECT_SCENE_ERROR(patched("/materials/m", gltf({{"metallic", -0.2}})), "/materials/m/metallic",
                       "must be in [0, 1]");
    EXPECT_SCENE_ERROR(patched("/materials/m", gltf({{"roughness", 2}})), "/materials/m/roughness",
                       "must be in [0, 1]");
    EXPECT_SCENE_ERROR(patched("/materials/m", gltf({{"f0", {1, 1, 1}}})), "/materials/m/f0",
                       "unknown field; valid fields here: alpha, alpha_cutoff, alpha_mode, "
                       "base_color, base_color_texture, emission, emissive_texture, ior, "
                       "metallic, metallic_roughness_texture, multiple_scattering, "
                       "normal_texture, roughness, transmission, type");
}

TEST(SceneLoaderErrors, MaterialsNotObjects) {
    EXPECT_SCENE_ERROR(patched("/materials/white", "diffuse"), "/materials/white",
                       "expected an object, got a string");
    EXPECT_SCENE_ERROR(patched("/materials", Json::array()), "/materials",
                       "expected an object, got an array");
    EXPECT_SCENE_ERROR(without("/materials"), "/materials", "missing required field");
}

// --- shapes ---

TEST(SceneLoaderErrors, QuadWithParallelEdges) {
    Json quad{{"type", "quad"}, {"origin", {0, 0, 0}}, {"u", {1, 0, 0}}, {"material", "white"}};
    quad["v"] = {-2, 0, 0};
    EXPECT_SCENE_ERROR(patched("/shapes/0", quad), "/shapes/0/v",
                       "must not be zero or parallel to u (the quad has no area)");
    quad["v"] = {0, 0, 0};
    EXPECT_SCENE_ERROR(patched("/shapes/0", quad), "/shapes/0/v",
                       "must not be zero or parallel to u (the quad has no area)");
}

TEST(SceneLoaderErrors, TriangleWithoutAreaOrWithTwoVertices) {
    Json tri{{"type", "triangle"}, {"material", "white"}};
    tri["vertices"] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    EXPECT_SCENE_ERROR(patched("/shapes/0", tri), "/shapes/0/vertices", "the triangle has no area");
    tri["vertices"] = {{0, 0, 0}, {1, 0, 0}};
    EXPECT_SCENE_ERROR(patched("/shapes/0", tri), "/shapes/0/vertices",
                       "expected an array of 3 points, got an array of 2");
    tri["vertices"] = "abc";
    EXPECT_SCENE_ERROR(patched("/shapes/0", tri), "/shapes/0/vertices",
                       "expected an array of 3 points, got a string");
    tri["vertices"] = {{0, 0, 0}, {1, 0, 0}, {0, 1}};
    EXPECT_SCENE_ERROR(patched("/shapes/0", tri), "/shapes/0/vertices/2",
                       "expected an array of 3 numbers, got an array of 2");
}

TEST(SceneLoaderErrors, ShapeMissingMaterialOrType) {
    EXPECT_SCENE_ERROR(without("/shapes/0/material"), "/shapes/0/material",
                       "missing required field");
    EXPECT_SCENE_ERROR(without("/shapes/0/type"), "/shapes/0/type", "missing required field");
}

TEST(SceneLoaderErrors, ErrorNamesTheIndexOfTheBadShape) {
    Json doc = baseScene();
    doc["shapes"].push_back(doc["shapes"][0]);
    doc["shapes"].push_back(doc["shapes"][0]);
    doc["shapes"][2]["radius"] = -1;
    EXPECT_SCENE_ERROR(doc, "/shapes/2/radius", "must be > 0");
    doc["shapes"][1] = 7;
    EXPECT_SCENE_ERROR(doc, "/shapes/1", "expected an object, got a number");
}

TEST(SceneLoaderErrors, ShapesNotAnArray) {
    EXPECT_SCENE_ERROR(patched("/shapes", baseScene()["shapes"][0]), "/shapes",
                       "expected an array, got an object");
    EXPECT_SCENE_ERROR(without("/shapes"), "/shapes", "missing required field");
}

// --- meshes ---

TEST(SceneLoaderErrors, MeshPathTraversal) {
    EXPECT_SCENE_ERROR(withShape(meshShape("../meshes/teapot.obj")), "/shapes/0/file",
                       "\"../meshes/teapot.obj\" must not leave the assets folder (\"..\")");
    EXPECT_SCENE_ERROR(withShape(meshShape("sub/../../CMakeLists.txt")), "/shapes/0/file",
                       "\"sub/../../CMakeLists.txt\" must not leave the assets folder (\"..\")");
}

TEST(SceneLoaderErrors, MeshAbsolutePath) {
    // Rejected even though the file exists and lies inside the assets folder.
    std::string absolute = CAUSTIC_SOURCE_DIR "/assets/meshes/teapot.obj";
    ASSERT_TRUE(std::filesystem::exists(absolute));
    EXPECT_SCENE_ERROR(withShape(meshShape(absolute)), "/shapes/0/file",
                       "\"" + absolute + "\" must be a path relative to the assets folder");
}

TEST(SceneLoaderErrors, MeshFileMissing) {
    EXPECT_SCENE_ERROR(withShape(meshShape("missing.obj")), "/shapes/0/file",
                       "no file \"missing.obj\" in the assets folder");
    EXPECT_SCENE_ERROR(withShape(meshShape("")), "/shapes/0/file",
                       "must name a file in the assets folder");
    EXPECT_SCENE_ERROR(withShape(meshShape(".")), "/shapes/0/file",
                       "no file \".\" in the assets folder");
}

TEST(SceneLoaderErrors, MeshWithoutAssetsFolder) {
    // Without a configured folder, names must not resolve against the working directory.
    std::filesystem::path cwd = std::filesystem::current_path();
    std::filesystem::current_path(CAUSTIC_SOURCE_DIR);
    EXPECT_SCENE_ERROR_WITH(withShape(meshShape("assets/meshes/teapot.obj")), "/shapes/0/file",
                            "no assets folder is configured", SceneOptions{});
    std::filesystem::current_path(cwd);
}

TEST(SceneLoaderErrors, MeshLinkOutOfAssetsFolder) {
    TempDir dir;
    std::filesystem::create_directories(dir.path() / "assets");
    dir.write("outside.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::filesystem::create_symlink(dir.path() / "outside.obj", dir.path() / "assets/link.obj");
    SceneOptions options;
    options.assetsDir = dir.path() / "assets";
    EXPECT_SCENE_ERROR_WITH(withShape(meshShape("link.obj")), "/shapes/0/file",
                            "\"link.obj\" must not leave the assets folder", options);
}

TEST(SceneLoaderErrors, MeshFileContents) {
    TempDir dir;
    dir.write("empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    dir.write("huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1e30 0\nf 1 2 3\n");
    SceneOptions options;
    options.assetsDir = dir.path();
    EXPECT_SCENE_ERROR_WITH(withShape(meshShape("empty.obj")), "/shapes/0/file",
                            "empty.obj has no faces", options);
    Json doc = withShape(meshShape("huge.obj"));
    EXPECT_NO_THROW(loadScene(doc, options));
    // A scale that overflows the vertices to infinity.
    doc["shapes"][0]["transform"] = {{"scale", 1e10}};
    EXPECT_SCENE_ERROR_WITH(doc, "/shapes/0/file", "vertex 3 of huge.obj is not finite", options);
}

TEST(SceneLoaderErrors, MeshTransform) {
    Json doc = withShape(meshShape("teapot.obj"));
    doc["shapes"][0]["transform"] = {{"scale", 0}};
    EXPECT_SCENE_ERROR(doc, "/shapes/0/transform/scale", "must not be zero");
    doc["shapes"][0]["transform"] = {{"scale", {1, 0, 1}}};
    EXPECT_SCENE_ERROR(doc, "/shapes/0/transform/scale", "must not be zero");
    doc["shapes"][0]["transform"] = {{"rotate_y", 30}};
    EXPECT_SCENE_ERROR(doc, "/shapes/0/transform/rotate_y",
                       "unknown field; valid fields here: rotate, scale, translate");
}

// --- lights, background, settings, the document ---

TEST(SceneLoaderErrors, LightOfUnknownTypeOrMissingIntensity) {
    Json light{{"type", "area"}, {"position", {0, 1, 0}}, {"intensity", {1, 1, 1}}};
    EXPECT_SCENE_ERROR(patched("/lights", Json::array({light})), "/lights/0/type",
                       "unknown value \"area\"; valid: directional, point, spot");
    light["type"] = "point";
    light["intensity"] = {1, -1, 1};
    EXPECT_SCENE_ERROR(patched("/lights", Json::array({light})), "/lights/0/intensity/1",
                       "must be >= 0");
    light.erase("intensity");
    EXPECT_SCENE_ERROR(patched("/lights", Json::array({light})), "/lights/0/intensity",
                       "missing required field");
    EXPECT_SCENE_ERROR(patched("/lights", light), "/lights", "expected an array, got an object");
}

TEST(SceneLoaderErrors, BackgroundSettingsAndDocument) {
    EXPECT_SCENE_ERROR(patched("/background", {0, -0.5, 0}), "/background/1", "must be >= 0");
    EXPECT_SCENE_ERROR(patched("/settings", {"spp", 16}), "/settings",
                       "expected an object, got an array");
    EXPECT_SCENE_ERROR(Json::array(), "", "expected an object, got an array");
    EXPECT_SCENE_ERROR(Json(), "", "expected an object, got null");
}

// The InputError of parsing `text`.
InputError jsonTextError(const std::string& text) {
    try {
        parseJson(text);
    } catch (const InputError& e) {
        return e;
    }
    ADD_FAILURE() << "parsed: " << text;
    return InputError("(none)", "(none)");
}

TEST(SceneLoaderErrors, InvalidJsonText) {
    InputError e = jsonTextError("{\n  \"camera\": {,\n}");
    EXPECT_EQ(e.path(), "");
    EXPECT_EQ(e.message().rfind("invalid JSON: parse error at line 2, column 14: ", 0), 0u)
        << e.message();
    EXPECT_EQ(std::string(e.what()), "/: " + e.message());
    e = jsonTextError("");
    EXPECT_EQ(e.message().rfind("invalid JSON: parse error at line 1, column 1: ", 0), 0u)
        << e.message();
    // Not a syntax error, but still bad input: an InputError, not nlohmann's out_of_range.
    e = jsonTextError("{\"camera\": {\"fov\": 1e400}}");
    EXPECT_EQ(e.path(), "");
    EXPECT_EQ(e.message(), "invalid JSON: number overflow parsing '1e400'");
}

TEST(SceneLoaderErrors, MissingSceneFile) {
    std::string file = CAUSTIC_SOURCE_DIR "/scenes/no-such-scene.json";
    try {
        readJsonFile(file);
        ADD_FAILURE() << "missing file read";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "");
        EXPECT_EQ(e.message(), "cannot open " + file);
    }
}

}  // namespace
}  // namespace caustic
