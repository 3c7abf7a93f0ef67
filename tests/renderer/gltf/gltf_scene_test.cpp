// glTF files as scenes (gltf/gltf_scene.h): small files written here, each for one of the
// conventions the glTF sample models exercise (hierarchies, mirroring nodes, quantized meshes,
// texture transforms, missing normals and tangents, punctual light units, cameras), the
// overrides a job gives, and hostile files, each an InputError naming the glTF object.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>

#include "core/error.h"
#include "film/image_io.h"
#include "gltf/gltf_scene.h"
#include "scene/scene.h"
#include "support/glb_writer.h"

namespace caustic {
namespace {

using testing::appendBytes;
using testing::GlbModel;
using testing::squareGlb;

constexpr double kPi = 3.14159265358979323846;

const std::string kName = "m.glb", kPath = "/scene/gltf";
const MeshErrors kErrors{kName, kPath};

GltfScene imported(const GlbModel& m, const GltfImportOptions& options = {}) {
    return importGltf(loadGlbModel(m.bytes(), kErrors), options, kErrors);
}

// The scene the imported file makes, with `overrides`.
std::unique_ptr<Scene> sceneOf(const GlbModel& m, const Json& overrides = Json::object()) {
    GltfScene g = imported(m);
    SceneOptions options;
    options.embedded = g.embedded;
    return loadScene(gltfSceneWithOverrides(g, overrides, "/scene", {}), options);
}

void expectImportError(const GlbModel& m, const std::string& message) {
    try {
        imported(m);
        ADD_FAILURE() << "imported; expected \"" << message << "\"";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), kPath);
        EXPECT_EQ(e.message(), kName + ": " + message);
    }
}

// A PNG of the given pixels (OpenImageIO's writer).
std::string pngOf(int width, int height, float value) {
    RgbImage image{width, height, std::vector<float>(size_t(width) * height * 3, value)};
    return encodeImage(image, "png");
}

// squareGlb() with `image` as image 0 in bufferView 2, used by material 0 as base colour.
GlbModel texturedSquare(const std::string& image) {
    GlbModel m = squareGlb();
    const size_t offset = m.bin.size();
    m.bin += image;
    m.gltf["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", image.size()}});
    m.gltf["buffers"][0]["byteLength"] = m.bin.size();
    m.gltf["images"] = {{{"bufferView", 2}, {"mimeType", "image/png"}, {"name", "checker"}}};
    m.gltf["textures"] = {{{"source", 0}}};
    m.gltf["materials"] = {
        {{"name", "Paint"},
         {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0}}}}};
    m.gltf["meshes"][0]["primitives"][0]["material"] = 0;
    return m;
}

TEST(GltfScene, MeshesMaterialsAndTheDefaultEnvironment) {
    GltfScene g = imported(squareGlb());
    // Two nodes draw the square: two embedded meshes, each of glTF's default material.
    ASSERT_EQ(g.embedded->meshes.size(), 2u);
    EXPECT_EQ(g.scene["shapes"][1],
              Json({{"type", "mesh"}, {"embedded", 1}, {"material", "default"}}));
    EXPECT_EQ(g.scene["materials"]["default"], Json({{"type", "metallic_roughness"},
                                                     {"base_color", {1.0, 1.0, 1.0}},
                                                     {"metallic", 1.0},
                                                     {"roughness", 1.0}}));
    // Node 1 is node 0's child: translated (0, 0, -5) + (10, 0, 0), scaled by 2.
    EXPECT_EQ(g.embedded->meshes[1].mesh.positions[2], Vec3(12, 2, -5));
    EXPECT_EQ(g.summary["triangles"], 4);
    // No light in the file: the neutral white environment.
    EXPECT_EQ(g.scene["environment"], Json({{"color", {1.0, 1.0, 1.0}}}));
    EXPECT_TRUE(g.embedded->meshes[0].mesh.normals.empty());  // no NORMAL: flat
}

TEST(GltfScene, NormalsTexcoordsAndAMirroringNode) {
    GlbModel m = squareGlb();
    const size_t normals = m.bin.size();
    appendBytes(m.bin, std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    const size_t uvs = m.bin.size();
    appendBytes(m.bin, std::vector<float>{0, 1, 1, 1, 1, 0, 0, 0});
    m.gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", normals}, {"byteLength", 48}});
    m.gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", uvs}, {"byteLength", 32}});
    m.gltf["buffers"][0]["byteLength"] = m.bin.size();
    m.gltf["accessors"].push_back(
        {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}});
    m.gltf["accessors"].push_back(
        {{"bufferView", 3}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
    m.gltf["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 2;
    m.gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 3;
    m.gltf["nodes"][1]["scale"] = {2, 2, -2};  // mirrors z
    GltfScene g = imported(m);
    const TriangleMesh& plain = g.embedded->meshes[0].mesh;
    const TriangleMesh& mirrored = g.embedded->meshes[1].mesh;
    EXPECT_EQ(plain.normals[0], Vec3(0, 0, 1));
    EXPECT_EQ(plain.texcoords[1], Vec2(1, 1));
    // The normal follows the inverse transpose (z flips), and the winding swaps so that the
    // front stays the side the normals face.
    EXPECT_EQ(mirrored.normals[0], Vec3(0, 0, -1));
    EXPECT_EQ(plain.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mirrored.triangles[0], glm::uvec3(0, 2, 1));
    const Vec3 e1 = mirrored.positions[2] - mirrored.positions[0];
    const Vec3 e2 = mirrored.positions[1] - mirrored.positions[0];
    EXPECT_GT(glm::dot(glm::cross(e1, e2), mirrored.normals[0]), 0.0f);
}

TEST(GltfScene, QuantizedPositionsAndNormalizedTexcoords) {
    // KHR_mesh_quantization: SHORT positions scaled by the node, normalized UNSIGNED_BYTE
    // texture coordinates.
    GlbModel m = squareGlb();
    m.bin.clear();
    appendBytes(m.bin,
                std::vector<int16_t>{0, 0, 0, 0, 100, 0, 0, 0, 100, 100, 0, 0, 0, 100, 0, 0});
    appendBytes(m.bin, std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    appendBytes(m.bin, std::vector<uint8_t>{0, 255, 255, 255, 255, 0, 0, 0});
    m.gltf["bufferViews"] = {
        {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 32}, {"byteStride", 8}},
        {{"buffer", 0}, {"byteOffset", 32}, {"byteLength", 12}},
        {{"buffer", 0}, {"byteOffset", 44}, {"byteLength", 8}}};
    m.gltf["buffers"][0]["byteLength"] = m.bin.size();
    m.gltf["accessors"][0]["componentType"] = 5122;  // SHORT
    m.gltf["accessors"].push_back({{"bufferView", 2},
                                   {"componentType", 5121},
                                   {"normalized", true},
                                   {"count", 4},
                                   {"type", "VEC2"}});
    m.gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
    m.gltf["nodes"] = {{{"mesh", 0}, {"scale", {0.01, 0.01, 0.01}}}};
    m.gltf["extensionsUsed"] = {"KHR_mesh_quantization"};
    m.gltf["extensionsRequired"] = {"KHR_mesh_quantization"};
    GltfScene g = imported(m);
    const TriangleMesh& mesh = g.embedded->meshes[0].mesh;
    EXPECT_NEAR(mesh.positions[2].x, 1.0f, 1e-6f);
    EXPECT_NEAR(mesh.positions[2].y, 1.0f, 1e-6f);
    EXPECT_EQ(mesh.texcoords[0], Vec2(0, 1));
    EXPECT_EQ(mesh.texcoords[2], Vec2(1, 0));
}

// The square, its two triangles compressed by Draco's encoder (KHR_draco_mesh_compression): the
// accessors keep counts and types, the extension's bufferView holds the data.
GlbModel dracoSquare() {
    draco::TriangleSoupMeshBuilder builder;
    builder.Start(2);
    const int position =
        builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    builder.SetAttributeValuesForFace(position, draco::FaceIndex(0), p[0], p[1], p[2]);
    builder.SetAttributeValuesForFace(position, draco::FaceIndex(1), p[0], p[2], p[3]);
    std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
    draco::EncoderBuffer buffer;
    EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
    GlbModel m = squareGlb();
    m.bin.assign(buffer.data(), buffer.size());
    m.gltf["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", buffer.size()}}};
    m.gltf["buffers"][0]["byteLength"] = m.bin.size();
    m.gltf["accessors"][0].erase("bufferView");
    m.gltf["accessors"][0]["count"] = mesh->num_points();
    m.gltf["accessors"][1].erase("bufferView");
    m.gltf["meshes"][0]["primitives"][0]["extensions"] = {
        {"KHR_draco_mesh_compression",
         {{"bufferView", 0},
          {"attributes",
           {{"POSITION", mesh->GetNamedAttributeId(draco::GeometryAttribute::POSITION)}}}}}};
    m.gltf["extensionsUsed"] = m.gltf["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    return m;
}

TEST(GltfScene, DracoCompressedMeshes) {
    GltfScene g = imported(dracoSquare());
    const TriangleMesh& mesh = g.embedded->meshes[1].mesh;
    ASSERT_EQ(mesh.triangles.size(), 2u);
    // The same square as the uncompressed file, within the 14-bit quantization.
    float area = 0;
    for (const glm::uvec3& t : mesh.triangles)
        area += 0.5f * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                              mesh.positions[t.z] - mesh.positions[t.x]));
    EXPECT_NEAR(area, 4.0f, 1e-3f);  // node 1 scales by 2
    for (const Vec3& p : mesh.positions) EXPECT_NEAR(p.z, -5.0f, 1e-5f);
    // Garbage in the bufferView is an error naming the primitive.
    GlbModel broken = dracoSquare();
    for (size_t i = 8; i < broken.bin.size(); ++i) broken.bin[i] = char(0xA5);
    try {
        imported(broken);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(e.message().find("mesh 0 primitive 0: KHR_draco_mesh_compression: "),
                  std::string::npos)
            << e.message();
    }
}

// The square with EXT_meshopt_compression: its positions and indices compressed by
// meshoptimizer's encoders in buffer 0, the views' own buffer a fallback holding no data.
GlbModel meshoptSquare() {
    const std::vector<float> positions{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<unsigned> indices{0, 1, 2, 0, 2, 3};
    std::string vertexData(meshopt_encodeVertexBufferBound(4, 12), '\0');
    vertexData.resize(
        meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(vertexData.data()),
                                   vertexData.size(), positions.data(), 4, 12));
    std::string indexData(meshopt_encodeIndexBufferBound(6, 4), '\0');
    indexData.resize(meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(indexData.data()),
                                               indexData.size(), indices.data(), 6));
    GlbModel m = squareGlb();
    const size_t indexOffset = (vertexData.size() + 3) / 4 * 4;
    m.bin = vertexData;
    m.bin.resize(indexOffset, '\0');
    m.bin += indexData;
    m.gltf["buffers"] = {
        {{"byteLength", m.bin.size()}},
        {{"byteLength", 60}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
    auto compressed = [](size_t offset, size_t length, int stride, int count, const char* mode) {
        return Json{{"EXT_meshopt_compression",
                     {{"buffer", 0},
                      {"byteOffset", offset},
                      {"byteLength", length},
                      {"byteStride", stride},
                      {"count", count},
                      {"mode", mode}}}};
    };
    m.gltf["bufferViews"] = {
        {{"buffer", 1},
         {"byteOffset", 0},
         {"byteLength", 48},
         {"byteStride", 12},
         {"extensions", compressed(0, vertexData.size(), 12, 4, "ATTRIBUTES")}},
        {{"buffer", 1},
         {"byteOffset", 48},
         {"byteLength", 12},
         {"extensions", compressed(indexOffset, indexData.size(), 2, 6, "TRIANGLES")}}};
    m.gltf["extensionsUsed"] = m.gltf["extensionsRequired"] = {"EXT_meshopt_compression"};
    return m;
}

TEST(GltfScene, MeshoptCompressedMeshes) {
    GltfScene g = imported(meshoptSquare());
    const TriangleMesh& mesh = g.embedded->meshes[1].mesh;  // node 1: moved, scaled by 2
    ASSERT_EQ(mesh.triangles.size(), 2u);
    EXPECT_EQ(mesh.triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(mesh.positions[2], Vec3(12, 2, -5));
    // A range past its buffer, and data that does not decode, name the bufferView.
    GlbModel past = meshoptSquare();
    past.gltf["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 100000;
    expectImportError(
        past, "bufferView 1: EXT_meshopt_compression: 100000 bytes at offset " +
                  past.gltf["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteOffset"]
                      .dump() +
                  " run past the end of buffer 0 (" +
                  std::to_string((past.bin.size() + 3) / 4 * 4) +  // padded to 4
                  " bytes)");
    GlbModel garbage = meshoptSquare();
    for (char& c : garbage.bin) c = char(0x5A);
    try {
        imported(garbage);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(
            e.message().find("bufferView 0: EXT_meshopt_compression: the data does not decode"),
            std::string::npos)
            << e.message();
    }
}

TEST(GltfScene, TexturesWithTheirTransform) {
    GlbModel m = texturedSquare(pngOf(8, 4, 0.5f));
    m.gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        {"KHR_texture_transform",
         {{"offset", {0.5, 0}}, {"rotation", kPi / 2}, {"scale", {2, 3}}}}};
    m.gltf["extensionsUsed"] = {"KHR_texture_transform"};
    GltfScene g = imported(m);
    const Json& slot = g.scene["materials"]["Paint"]["base_color_texture"];
    EXPECT_EQ(slot["embedded"], 0);
    EXPECT_EQ(slot["transform"]["offset"], Json({0.5, 0.0}));
    EXPECT_NEAR(slot["transform"]["rotation"].get<double>(), 90.0, 1e-9);
    EXPECT_EQ(slot["transform"]["scale"], Json({2.0, 3.0}));
    ASSERT_EQ(g.embedded->images.size(), 1u);
    EXPECT_EQ(g.summary["textures"][0]["width"], 8);
    EXPECT_EQ(g.summary["textures"][0]["height"], 4);
    // The image decodes into the scene's texture store.
    SceneOptions options;
    options.embedded = g.embedded;
    auto scene = loadScene(gltfSceneWithOverrides(g, Json::object(), "/scene", {}), options);
    ASSERT_TRUE(scene->textures);
}

TEST(GltfScene, ANormalMapGetsMikkTSpaceTangents) {
    GlbModel m = texturedSquare(pngOf(4, 4, 0.5f));
    m.gltf["materials"][0]["normalTexture"] = {{"index", 0}, {"scale", 0.5}};
    auto scene = sceneOf(m);
    bool tangents = false;
    for (const BuiltPart& p : scene->built.parts())
        tangents = tangents || p.part == "tangent frames";
    EXPECT_TRUE(tangents);
}

TEST(GltfScene, PunctualLightsInTheirUnits) {
    GlbModel m = squareGlb();
    m.gltf["extensionsUsed"] = {"KHR_lights_punctual"};
    m.gltf["extensions"] = {
        {"KHR_lights_punctual",
         {{"lights",
           {{{"type", "point"}, {"intensity", 683}, {"color", {1, 0.5, 0.25}}, {"name", "bulb"}},
            {{"type", "spot"},
             {"intensity", 100},
             {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}}},
            {{"type", "directional"}, {"intensity", 1000}}}}}}};
    // The lights' nodes: a point at (1, 2, 3); a spot and a sun turned to look down (-y).
    const double half = std::sqrt(0.5);
    m.gltf["nodes"].push_back(
        {{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    m.gltf["nodes"].push_back({{"rotation", {-half, 0, 0, half}},
                               {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    m.gltf["nodes"].push_back({{"rotation", {-half, 0, 0, half}},
                               {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    m.gltf["scenes"][0]["nodes"] = {0, 2, 3, 4};
    GltfScene g = imported(m);
    const Json& lights = g.scene["lights"];
    ASSERT_EQ(lights.size(), 3u);
    EXPECT_EQ(lights[0]["type"], "point");
    EXPECT_EQ(lights[0]["candela"], 683.0);
    EXPECT_EQ(lights[0]["color"], Json({1.0, 0.5, 0.25}));
    EXPECT_EQ(lights[0]["position"], Json({1.0, 2.0, 3.0}));
    EXPECT_NEAR(lights[1]["outer_angle"].get<double>(), 0.5 * 180 / kPi, 1e-9);
    EXPECT_NEAR(lights[1]["inner_angle"].get<double>(), 0.1 * 180 / kPi, 1e-9);
    EXPECT_NEAR(lights[1]["direction"][1].get<double>(), -1.0, 1e-9);
    EXPECT_EQ(lights[2]["lux"], 1000.0);
    EXPECT_NEAR(lights[2]["direction"][1].get<double>(), -1.0, 1e-9);
    EXPECT_FALSE(g.scene.contains("environment"));  // the file lights itself
    // A job changes the file's lights by name, or leaves them out.
    Json changed =
        gltfSceneWithOverrides(g, {{"lights", {{"bulb", {{"candela", 10}}}}}}, "/scene", {});
    EXPECT_EQ(changed["lights"][0]["candela"], 10);
    EXPECT_EQ(changed["lights"][0]["color"], Json({1.0, 0.5, 0.25}));
    changed = gltfSceneWithOverrides(g, {{"lights", {{"bulb", nullptr}}}}, "/scene", {});
    EXPECT_EQ(changed["lights"].size(), 2u);
    EXPECT_EQ(changed["lights"][0]["type"], "spot");
    try {
        gltfSceneWithOverrides(g, {{"lights", {{"lamp", nullptr}}}}, "/scene", {});
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/scene/lights/lamp");
        EXPECT_EQ(e.message(), "no light of that name in the file; its lights: bulb");
    }
    // In the scene: 683 cd of colour (1, 0.5, 0.25) is 1 W/sr in red (683 lm/W).
    SceneOptions options;
    options.embedded = g.embedded;
    auto scene = loadScene(gltfSceneWithOverrides(g, Json::object(), "/scene", {}), options);
    EXPECT_EQ(scene->lights.size(), 3u);
}

GlbModel withCamera(double yfov, double aspect) {
    GlbModel m = squareGlb();
    m.gltf["cameras"] = {
        {{"type", "perspective"},
         {"name", "Front"},
         {"perspective", {{"yfov", yfov}, {"aspectRatio", aspect}, {"znear", 0.1}}}}};
    m.gltf["nodes"].push_back({{"camera", 0}, {"translation", {0.5, 0.5, 4}}});
    m.gltf["scenes"][0]["nodes"] = {0, 2};
    return m;
}

TEST(GltfScene, TheFilesCameraAndTheAutomaticOne) {
    GltfScene g = imported(withCamera(0.5, 2.0));
    Json scene = gltfSceneWithOverrides(g, Json::object(), "/scene", {});
    EXPECT_EQ(scene["camera"]["position"], Json({0.5, 0.5, 4.0}));
    EXPECT_EQ(scene["camera"]["look_at"], Json({0.5, 0.5, 3.0}));  // -z of the node
    EXPECT_NEAR(scene["camera"]["fov"].get<double>(), 0.5 * 180 / kPi, 1e-9);
    EXPECT_EQ(scene["camera"]["width"], 960);
    EXPECT_EQ(scene["camera"]["height"], 480);  // aspect ratio 2
    EXPECT_EQ(g.summary["camera"], Json({{"gltf", 0}, {"name", "Front"}}));
    // By name, with a width: the height follows the aspect ratio.
    scene =
        gltfSceneWithOverrides(g, {{"camera", {{"gltf", "Front"}, {"width", 200}}}}, "/scene", {});
    EXPECT_EQ(scene["camera"]["height"], 100);
    // Automatic: the bounds' sphere fits the view, seen from azimuth 30, elevation 20.
    scene = gltfSceneWithOverrides(g, {{"camera", {{"auto", Json::object()}}}}, "/scene", {});
    const Json& c = scene["camera"];
    const Vec3 center(c["look_at"][0], c["look_at"][1], c["look_at"][2]);
    const Vec3 eye(c["position"][0], c["position"][1], c["position"][2]);
    EXPECT_NEAR(center.x, 6.0f, 1e-5f);  // bounds x 0..12, y 0..2, z -5
    const Vec3 d = glm::normalize(eye - center);
    EXPECT_NEAR(std::asin(d.y) * 180 / kPi, 20.0, 1e-4);
    EXPECT_NEAR(std::atan2(d.x, d.z) * 180 / kPi, 30.0, 1e-4);
    const double radius = 0.5 * std::sqrt(12.0 * 12 + 2 * 2);
    EXPECT_NEAR(glm::length(eye - center), radius / std::sin(20 * kPi / 180), 1e-3);
    // Unknown names are errors at their path, listing what the file has.
    try {
        gltfSceneWithOverrides(g, {{"camera", {{"gltf", "Back"}}}}, "/scene", {});
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/scene/camera/gltf");
        EXPECT_EQ(e.message(), "no perspective camera \"Back\" in the file; it has 0 \"Front\"");
    }
}

TEST(GltfScene, OverridesChangeMaterialsByNameAndTheEnvironment) {
    GlbModel m = texturedSquare(pngOf(2, 2, 1.0f));
    auto scene = sceneOf(
        m, {{"materials", {{"Paint", {{"roughness", 0.25}}}}},
            {"environment", nullptr},
            {"lights", {{{"type", "point"}, {"position", {0, 1, 0}}, {"intensity", {1, 1, 1}}}}}});
    EXPECT_FALSE(scene->environment);
    EXPECT_EQ(scene->lights.size(), 1u);
    GltfScene g = imported(m);
    try {
        gltfSceneWithOverrides(g, {{"materials", {{"Pain", {{"roughness", 0.25}}}}}}, "/scene", {});
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/scene/materials/Pain");
        EXPECT_EQ(e.message(), "no material of that name in the file; its materials: Paint");
    }
}

TEST(GltfScene, ExtensionsRequiredAndUsed) {
    GlbModel m = squareGlb();
    m.gltf["extensionsUsed"] = {"KHR_materials_sheen", "KHR_texture_transform"};
    GltfScene g = imported(m);
    EXPECT_EQ(g.warnings, std::vector<std::string>{"the extension KHR_materials_sheen is not "
                                                   "supported; ignored"});
    m.gltf["extensionsRequired"] = {"KHR_materials_sheen"};
    expectImportError(m,
                      "the file requires the extension \"KHR_materials_sheen\", which Caustic does "
                      "not support (it reads EXT_meshopt_compression, KHR_draco_mesh_compression, "
                      "KHR_lights_punctual, "
                      "KHR_materials_emissive_strength, "
                      "KHR_materials_ior, KHR_materials_transmission, KHR_materials_volume, "
                      "KHR_mesh_quantization, KHR_texture_transform)");
}

// A PNG whose header says width x height, with one empty zlib stream of pixel data: a reader must
// refuse it from the header, before it allocates.
std::string pngHeader(uint32_t width, uint32_t height) {
    auto crc32 = [](const std::string& bytes) {
        uint32_t crc = 0xFFFFFFFFu;
        for (unsigned char b : bytes) {
            crc ^= b;
            for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
        }
        return ~crc;
    };
    auto be32 = [](uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    std::string ihdr = "IHDR" + be32(width) + be32(height) + std::string{8, 2, 0, 0, 0};
    const std::string idat = "IDAT" + std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8);
    return std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + ihdr + be32(crc32(ihdr)) + be32(8) +
           idat + be32(crc32(idat)) + be32(0) + "IEND" + be32(crc32("IEND"));
}

TEST(GltfScene, HostileFilesAreErrorsNamingTheObject) {
    GltfImportOptions options;
    options.maxPixels = int64_t(16384) * 16384;
    try {
        imported(texturedSquare(pngHeader(65535, 65535)), options);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(e.message().find("image 0 (checker): "), std::string::npos) << e.message();
        EXPECT_NE(e.message().find("65535 x 65535 pixels, over the limit of 268435456"),
                  std::string::npos)
            << e.message();
    }
    GlbModel m = squareGlb();
    m.gltf["materials"] = {{{"name", "Hot"}, {"pbrMetallicRoughness", {{"metallicFactor", 1.5}}}}};
    m.gltf["meshes"][0]["primitives"][0]["material"] = 0;
    expectImportError(
        m, "material 0 (Hot): pbrMetallicRoughness: metallicFactor is 1.5, not in [0, 1]");
    m = squareGlb();
    m.gltf["meshes"][0]["primitives"][0]["material"] = 3;
    expectImportError(m, "mesh 0 primitive 0: material 3 does not exist (0 materials)");
    // A 100-deep chain of nodes whose last child is its first: a cycle, named.
    m = squareGlb();
    m.gltf["nodes"] = Json::array();
    for (int i = 0; i < 100; ++i)
        m.gltf["nodes"].push_back({{"mesh", 0}, {"children", {(i + 1) % 100}}});
    m.gltf["scenes"][0]["nodes"] = Json::array();
    expectImportError(m, "node 0: its own ancestor (the node hierarchy has a cycle)");
    // An accessor count whose byte size would overflow.
    m = squareGlb();
    m.gltf["accessors"][0]["count"] = uint64_t(1) << 62;
    try {
        imported(m);
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(e.message().find("accessor 0: "), std::string::npos) << e.message();
    }
}

TEST(GltfScene, OddButValidFilesImport) {
    // An indexed strip of 4 indices: 2 triangles (only mode 4 needs a multiple of 3).
    GlbModel strip = squareGlb();
    strip.gltf["meshes"][0]["primitives"][0]["mode"] = 5;
    strip.gltf["accessors"][1]["count"] = 4;
    EXPECT_EQ(imported(strip).embedded->meshes[0].mesh.triangles.size(), 2u);
    // Names of the wrong type are no names (tinygltf ignores them too), not a failure.
    GlbModel named = squareGlb();
    named.gltf["asset"]["generator"] = 7;
    named.gltf["materials"] = {{{"name", 5}}, {{"name", "material 0"}}};
    named.gltf["meshes"][0]["primitives"][0]["material"] = 1;  // used first: takes "material 0"
    named.gltf["meshes"].push_back(named.gltf["meshes"][0]);
    named.gltf["meshes"][1]["primitives"][0]["material"] = 0;
    named.gltf["nodes"][1]["mesh"] = 1;
    GltfScene g = imported(named);
    EXPECT_EQ(g.summary["generator"], "");
    EXPECT_EQ(g.scene["materials"].size(), 2u);  // neither overwrote the other
    EXPECT_TRUE(g.scene["materials"].contains("material 0"));
    EXPECT_TRUE(g.scene["materials"].contains("material 0 (2)"));
    // Many point primitives: a few listed, then a count.
    GlbModel points = squareGlb();
    Json prim = points.gltf["meshes"][0]["primitives"][0];
    prim["mode"] = 0;
    for (int i = 0; i < 20; ++i) points.gltf["meshes"][0]["primitives"].push_back(prim);
    const GltfScene p = imported(points);
    EXPECT_EQ(p.warnings.size(), 9u);
    EXPECT_EQ(p.warnings.back(), "and 32 more primitives of points or lines, not drawn");
}

TEST(GltfScene, ImagesMustBePngJpegOrWebp) {
    GlbModel m = texturedSquare("BM not really an image but long enough");
    expectImportError(m, "image 0 (checker): not a PNG, JPEG or WebP image");
}

TEST(GltfScene, EmbeddedNeedsAModel) {
    Json doc = {{"camera", {{"position", {0, 0, 5}}, {"look_at", {0, 0, 0}}}},
                {"materials", {{"m", {{"type", "diffuse"}}}}},
                {"shapes", {{{"type", "mesh"}, {"embedded", 0}, {"material", "m"}}}}};
    try {
        loadScene(doc, SceneOptions{});
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/shapes/0/embedded");
        EXPECT_EQ(e.message(),
                  "names a model file's mesh, and this scene comes from no model file");
    }
}

}  // namespace
}  // namespace caustic
