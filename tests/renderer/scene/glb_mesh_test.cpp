// Mesh files from memory, glTF binary side (parseMeshBytes): a small .glb written here with known
// positions, and every kind of bad file, each an InputError naming the glTF object at fault.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "renderer/scene/mesh_file_expect.h"
#include "scene/mesh_file.h"
#include "support/glb_writer.h"

namespace caustic {
namespace {

using testing::appendBytes;
using testing::glbBytes;
using testing::GlbModel;
using testing::squareGlb;

using testing::kMeshPath;

TriangleMesh parseGlbBytes(const std::string& bytes, const MeshTransform& transform = {}) {
    return parseMeshBytes(bytes, MeshFormat::Glb, transform, "m.glb", kMeshPath);
}

#define EXPECT_GLB_ERROR(bytes, message) EXPECT_MESH_ERROR(bytes, MeshFormat::Glb, "m.glb", message)

// squareGlb() with one JSON value set.
std::string patchedGlb(const std::string& pointer, const nlohmann::json& value) {
    GlbModel m = squareGlb();
    m.gltf[nlohmann::json::json_pointer(pointer)] = value;
    return m.bytes();
}

void setU32(std::string& bytes, size_t offset, uint32_t value) {
    std::memcpy(bytes.data() + offset, &value, sizeof value);
}

TEST(MeshFileGlb, NodesWithTheirTransforms) {
    TriangleMesh m = parseGlbBytes(squareGlb().bytes());
    // Node 0 moves the square to z = -5; its child node 1 scales it by 2 and moves it 10 along x
    // inside node 0's frame.
    const std::vector<Vec3> expected{{0, 0, -5},  {1, 0, -5},  {1, 1, -5},  {0, 1, -5},
                                     {10, 0, -5}, {12, 0, -5}, {12, 2, -5}, {10, 2, -5}};
    EXPECT_EQ(m.positions, expected);
    const std::vector<glm::uvec3> triangles{{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
    EXPECT_EQ(m.triangles, triangles);
    MeshBounds b = boundsOf(m);
    EXPECT_EQ(b.min, Vec3(0, 0, -5));
    EXPECT_EQ(b.max, Vec3(12, 2, -5));
}

TEST(MeshFileGlb, TheSceneTransformComesAfterTheNodes) {
    MeshTransform t;
    t.scale = Vec3(0.5f);
    t.translate = Vec3(0, 1, 0);
    TriangleMesh m = parseGlbBytes(squareGlb().bytes(), t);
    ASSERT_EQ(m.positions.size(), 8u);
    EXPECT_EQ(m.positions[6], Vec3(6, 2, -2.5f));
}

TEST(MeshFileGlb, RotationMatrixAndMirror) {
    GlbModel m = squareGlb();
    m.gltf["scenes"][0]["nodes"] = {0, 2, 3};
    m.gltf["nodes"][0] = {{"mesh", 0}, {"rotation", {0, 0, std::sqrt(0.5), std::sqrt(0.5)}}};
    // Column-major: a translation by (0, 0, 7).
    m.gltf["nodes"][2] = {{"mesh", 0},
                          {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 7, 1}}};
    m.gltf["nodes"][3] = {{"mesh", 0}, {"scale", {-1, 1, 1}}};
    TriangleMesh mesh = parseGlbBytes(m.bytes());
    ASSERT_EQ(mesh.positions.size(), 12u);
    // 90 degrees about z: (1, 0, 0) -> (0, 1, 0), (0, 1, 0) -> (-1, 0, 0).
    EXPECT_NEAR(mesh.positions[1].x, 0.0f, 1e-6f);
    EXPECT_NEAR(mesh.positions[1].y, 1.0f, 1e-6f);
    EXPECT_NEAR(mesh.positions[3].x, -1.0f, 1e-6f);
    EXPECT_EQ(mesh.positions[5], Vec3(1, 0, 7));
    EXPECT_EQ(mesh.positions[9], Vec3(-1, 0, 0));
    // The mirrored copy keeps its front side: two corners of each triangle swap.
    EXPECT_EQ(mesh.triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(mesh.triangles[4], glm::uvec3(8, 10, 9));
    EXPECT_EQ(mesh.triangles[5], glm::uvec3(8, 11, 10));
}

TEST(MeshFileGlb, WithoutScenesEveryRootIsDrawn) {
    GlbModel m = squareGlb();
    m.gltf.erase("scene");
    m.gltf.erase("scenes");
    m.gltf["nodes"].push_back({{"mesh", 0}, {"translation", {0, 0, 1}}});
    EXPECT_EQ(parseGlbBytes(m.bytes()).triangles.size(), 6u);
    // A root in two scenes is drawn once.
    m.gltf["scenes"] = {{{"nodes", {0}}}, {{"nodes", {0, 0}}}};
    EXPECT_EQ(parseGlbBytes(m.bytes()).triangles.size(), 4u);
}

TEST(MeshFileGlb, IndexTypesAndUnindexed) {
    GlbModel m = squareGlb();
    m.gltf["nodes"] = {{{"mesh", 0}}};
    // UNSIGNED_BYTE 0 1 2 0 2 3 in a bufferView of its own.
    appendBytes(m.bin, std::vector<uint8_t>{0, 1, 2, 0, 2, 3, 0, 0});
    // UNSIGNED_INT 3 2 0.
    appendBytes(m.bin, std::vector<uint32_t>{3, 2, 0});
    m.gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 60}, {"byteLength", 6}});
    m.gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 68}, {"byteLength", 12}});
    m.gltf["buffers"][0]["byteLength"] = 80;
    m.gltf["accessors"].push_back(
        {{"bufferView", 2}, {"componentType", 5121}, {"count", 6}, {"type", "SCALAR"}});
    m.gltf["accessors"].push_back(
        {{"bufferView", 3}, {"componentType", 5125}, {"count", 3}, {"type", "SCALAR"}});
    m.gltf["meshes"][0]["primitives"][0]["indices"] = 2;
    EXPECT_EQ(parseGlbBytes(m.bytes()).triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}));
    m.gltf["meshes"][0]["primitives"][0]["indices"] = 3;
    EXPECT_EQ(parseGlbBytes(m.bytes()).triangles, (std::vector<glm::uvec3>{{3, 2, 0}}));
    // Without indices each three positions are a triangle: 4 are not whole triangles.
    m.gltf["meshes"][0]["primitives"][0].erase("indices");
    EXPECT_GLB_ERROR(m.bytes(),
                     "mesh 0 primitive 0: 4 unindexed vertices are not whole triangles (a "
                     "multiple of 3)");
    m.gltf["accessors"][0]["count"] = 3;
    EXPECT_EQ(parseGlbBytes(m.bytes()).triangles, (std::vector<glm::uvec3>{{0, 1, 2}}));
}

TEST(MeshFileGlb, TruncatedFile) {
    std::string bytes = squareGlb().bytes();
    const size_t size = bytes.size();
    EXPECT_GLB_ERROR(bytes.substr(0, size - 10),
                     "truncated: the header says " + std::to_string(size) +
                         " bytes, the file has " + std::to_string(size - 10));
    // Cut inside the BIN chunk with the header's length mended: the chunk runs past the end.
    std::string cut = bytes.substr(0, size - 12);
    setU32(cut, 8, uint32_t(cut.size()));
    EXPECT_GLB_ERROR(cut, "chunk 1 (BIN): truncated: 60 bytes announced, 48 left");
    EXPECT_GLB_ERROR(bytes.substr(0, 7), "truncated: 7 bytes, and the GLB header alone has 12");
    EXPECT_GLB_ERROR(bytes.substr(0, 3), "truncated: 3 bytes, and the GLB header alone has 12");
    std::string headerOnly = bytes.substr(0, 12);
    setU32(headerOnly, 8, 12);
    EXPECT_GLB_ERROR(headerOnly, "chunk 0: missing (a .glb has a JSON chunk)");
}

TEST(MeshFileGlb, BinaryGarbageAndWrongHeader) {
    EXPECT_GLB_ERROR("\x89PNG\r\n\x1a\n\0\0\0\rIHDR",
                     "not a glTF binary (a .glb starts with \"glTF\")");
    EXPECT_GLB_ERROR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                     "not a glTF binary (a .glb starts with \"glTF\")");
    std::string bytes = squareGlb().bytes();
    std::string magic = bytes;
    magic[3] = 'X';
    EXPECT_GLB_ERROR(magic, "not a glTF binary (a .glb starts with \"glTF\")");
    std::string version = bytes;
    setU32(version, 4, 1);
    EXPECT_GLB_ERROR(version, "glTF binary version 1; only version 2 is read");
    std::string longer = bytes;
    setU32(longer, 8, uint32_t(bytes.size() + 4));
    EXPECT_GLB_ERROR(longer, "truncated: the header says " + std::to_string(bytes.size() + 4) +
                                 " bytes, the file has " + std::to_string(bytes.size()));
    std::string shorter = bytes;
    setU32(shorter, 8, uint32_t(bytes.size() - 4));
    EXPECT_GLB_ERROR(shorter, "the header says " + std::to_string(bytes.size() - 4) +
                                  " bytes, the file has " + std::to_string(bytes.size()));
    // Chunks: the JSON chunk must come first, and hold a JSON object.
    std::string swapped = bytes;
    setU32(swapped, 16, testing::kGlbBinChunk);
    EXPECT_GLB_ERROR(swapped,
                     "chunk 0 (BIN): a .glb has its JSON chunk first and at most one BIN "
                     "chunk, second");
    std::string notJson = glbBytes(nlohmann::json::array({1, 2}), squareGlb().bin);
    EXPECT_GLB_ERROR(notJson, "chunk 0 (JSON): not a JSON object of at most 64 levels");
    // An unknown chunk after the BIN chunk is skipped, as the specification asks.
    std::string extra = bytes;
    appendBytes(extra, std::vector<uint32_t>{4, 0x54584521, 0});
    setU32(extra, 8, uint32_t(extra.size()));
    EXPECT_EQ(parseGlbBytes(extra).triangles.size(), 4u);
}

TEST(MeshFileGlb, NonFiniteVertex) {
    GlbModel m = squareGlb();
    float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(m.bin.data() + 2 * 12, &nan, sizeof nan);
    EXPECT_GLB_ERROR(m.bytes(), "accessor 0: vertex 2 is not finite (nan, 1, 0)");
    m = squareGlb();
    float inf = std::numeric_limits<float>::infinity();
    std::memcpy(m.bin.data() + 3 * 12 + 8, &inf, sizeof inf);
    EXPECT_GLB_ERROR(m.bytes(), "accessor 0: vertex 3 is not finite (0, 1, inf)");
    // Finite in the file, but not once node 1 scales it.
    EXPECT_GLB_ERROR(patchedGlb("/nodes/1/scale", {1e300, 1, 1}),
                     "node 1: vertex 1 of accessor 0 is not finite once transformed");
}

TEST(MeshFileGlb, IndexOutOfRange) {
    GlbModel m = squareGlb();
    uint16_t nine = 9;
    std::memcpy(m.bin.data() + 48 + 5 * 2, &nine, sizeof nine);
    EXPECT_GLB_ERROR(m.bytes(), "accessor 1: index 9 is out of range (POSITION has 4 vertices)");
    EXPECT_GLB_ERROR(patchedGlb("/meshes/0/primitives/0/attributes/POSITION", 7),
                     "accessor 7: does not exist (2 accessors)");
    // tinygltf checks this reference itself, in its own words.
    EXPECT_GLB_ERROR(patchedGlb("/meshes/0/primitives/0/indices", 7),
                     "glTF: primitive indices accessor out of bounds");
    EXPECT_GLB_ERROR(patchedGlb("/accessors/1/count", 5),
                     "accessor 1: 5 indices are not whole triangles (a multiple of 3)");
    EXPECT_GLB_ERROR(patchedGlb("/accessors/1/componentType", 5122),
                     "accessor 1: indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or "
                     "UNSIGNED_INT, not SHORT SCALAR");
}

TEST(MeshFileGlb, EmptyOrWithoutTriangles) {
    EXPECT_GLB_ERROR("", "the file is empty");
    EXPECT_GLB_ERROR(patchedGlb("/nodes", nlohmann::json::array({nlohmann::json::object()})),
                     "has no triangles (no node of the scene has a triangle mesh)");
    // A mesh no node draws is not drawn.
    EXPECT_GLB_ERROR(patchedGlb("/scenes/0/nodes", nlohmann::json::array()),
                     "has no triangles (no node of the scene has a triangle mesh)");
}

TEST(MeshFileGlb, UrisAreRefused) {
    const std::string only = "; only a .glb with everything in its BIN chunk is accepted (no URIs)";
    EXPECT_GLB_ERROR(patchedGlb("/buffers/0/uri", "mesh.bin"),
                     "buffer 0: has the uri \"mesh.bin\"" + only);
    EXPECT_GLB_ERROR(patchedGlb("/buffers/0/uri", "data:application/octet-stream;base64,AAAA"),
                     "buffer 0: has a data: uri" + only);
    EXPECT_GLB_ERROR(patchedGlb("/images", {{{"uri", "../../../etc/passwd"}}}),
                     "image 0: has the uri \"../../../etc/passwd\"" + only);
    EXPECT_GLB_ERROR(patchedGlb("/images", {{{"uri", "data:image/png;base64,iVBORw0KGgo="}}}),
                     "image 0: has a data: uri" + only);
    EXPECT_GLB_ERROR(patchedGlb("/buffers/1", {{"byteLength", 4}}),
                     "buffer 1: a .glb without URIs holds one buffer, its BIN chunk");
    EXPECT_GLB_ERROR(patchedGlb("/images", 3), "\"images\" is not an array");
    // An image stored in the file is never decoded: materials are ignored.
    GlbModel m = squareGlb();
    m.gltf["images"] = {{{"bufferView", 1}, {"mimeType", "image/png"}}};
    EXPECT_EQ(parseGlbBytes(m.bytes()).triangles.size(), 4u);
}

TEST(MeshFileGlb, ByteRangesAreChecked) {
    EXPECT_GLB_ERROR(patchedGlb("/accessors/0/byteOffset", 12),
                     "accessor 0: 4 elements of 12 bytes, 12 apart from offset 12, run past the "
                     "end of bufferView 0 (48 bytes)");
    EXPECT_GLB_ERROR(patchedGlb("/accessors/0/count", 5),
                     "accessor 0: 5 elements of 12 bytes, 12 apart from offset 0, run past the "
                     "end of bufferView 0 (48 bytes)");
    EXPECT_GLB_ERROR(patchedGlb("/bufferViews/0/byteStride", 16),
                     "accessor 0: 4 elements of 12 bytes, 16 apart from offset 0, run past the "
                     "end of bufferView 0 (48 bytes)");
    EXPECT_GLB_ERROR(patchedGlb("/bufferViews/1/byteLength", 16),
                     "bufferView 1: 16 bytes at offset 48 run past the end of buffer 0 (60 bytes)");
    EXPECT_GLB_ERROR(patchedGlb("/accessors/0/bufferView", 5),
                     "accessor 0: bufferView 5 does not exist (2 bufferViews)");
    GlbModel m = squareGlb();
    m.gltf["accessors"][0].erase("bufferView");
    EXPECT_GLB_ERROR(m.bytes(), "accessor 0: has no bufferView (it would be all zeros)");
}

TEST(MeshFileGlb, TrianglePrimitivesOnly) {
    // Lines and points are left out; a file with nothing else has no triangles.
    EXPECT_GLB_ERROR(patchedGlb("/meshes/0/primitives/0/mode", 1),
                     "has no triangles (no node of the scene has a triangle mesh); mesh 0 "
                     "primitive 0: mode 1 (lines) is not drawn; only triangles are");
    // Strips and fans (glTF 2.0, "Meshes"): 6 corners make 4 triangles, twice.
    TriangleMesh strip = parseGlbBytes(patchedGlb("/meshes/0/primitives/0/mode", 5));
    ASSERT_EQ(strip.triangles.size(), 8u);
    EXPECT_EQ(strip.triangles[1], glm::uvec3(1, 0, 2));  // odd ones: (i, i + 2, i + 1)
    TriangleMesh fan = parseGlbBytes(patchedGlb("/meshes/0/primitives/0/mode", 6));
    ASSERT_EQ(fan.triangles.size(), 8u);
    EXPECT_EQ(fan.triangles[0], glm::uvec3(1, 2, 0));
    EXPECT_EQ(parseGlbBytes(patchedGlb("/meshes/0/primitives/0/mode", 4)).triangles.size(), 4u);
    EXPECT_GLB_ERROR(patchedGlb("/accessors/0/componentType", 5125),
                     "accessor 0: POSITION must be VEC3 of FLOAT (or of BYTE, UNSIGNED_BYTE, "
                     "SHORT, UNSIGNED_SHORT with KHR_mesh_quantization), not UNSIGNED_INT VEC3");
    EXPECT_GLB_ERROR(patchedGlb("/meshes/0/primitives/0/attributes", {{"NORMAL", 0}}),
                     "mesh 0 primitive 0: has no POSITION attribute");
}

TEST(MeshFileGlb, NodeHierarchyIsChecked) {
    EXPECT_GLB_ERROR(patchedGlb("/nodes/1/children", {0}),
                     "node 0: its own ancestor (the node hierarchy has a cycle)");
    EXPECT_GLB_ERROR(patchedGlb("/nodes/1/children", {1}),
                     "node 1: a child of both node 0 and node 1 (a node has one parent)");
    EXPECT_GLB_ERROR(patchedGlb("/nodes/0/children", {4}),
                     "node 0: child 4 does not exist (2 nodes)");
    EXPECT_GLB_ERROR(patchedGlb("/scenes/0/nodes", {0, 1}),
                     "scene 0: node 1 is a root but a child of node 0");
    EXPECT_GLB_ERROR(patchedGlb("/scenes/0/nodes", {3}),
                     "scene 0: node 3 does not exist (2 nodes)");
    EXPECT_GLB_ERROR(patchedGlb("/nodes/1/mesh", 2), "node 1: mesh 2 does not exist (1 meshes)");
    EXPECT_GLB_ERROR(patchedGlb("/nodes/1/rotation", {0, 0, 0, 0}),
                     "node 1: rotation is not a unit quaternion");
    EXPECT_GLB_ERROR(patchedGlb("/nodes/1/matrix", {1, 0, 0}),
                     "node 1: matrix has 3 numbers, not 16");
}

TEST(MeshFileGlb, WhatTheReaderThrowsIsAnError) {
    // tinygltf reads some arrays with at(): this file's buffer declares 0 bytes and has views into
    // it, so tinygltf throws std::out_of_range, which the loader reports (a fuzzing finding, kept
    // in tests/fuzz/mesh/empty-buffer-with-views.chunks; with the buffer's true length it reads,
    // and the missing node is reported instead).
    const std::string json = R"({"accessors":[{"bufferView":0,"componentType":5126,"count":4,)"
                             R"("max":[1,1,0],"min":[0,0,0],"type":"VEC3"},{"bufferView":1,)"
                             R"("componentType":5123,"count":6,"type":"SCALAR"}],)"
                             R"("asset":{"version":"2.0"},"bufferViews":[{"buffer":0,)"
                             R"("byteLength":48,"byteOffset":0},{"buffer":0,"byteLength":12,)"
                             R"("byteOffset":48}],"buffers":[{"byteLength":0,"scale":[2,2,2],)"
                             R"("translation":[10,0,0]}],"scene":0,"scenes":[{"nodes":[0]}]})";
    const std::string bin(48 + 12, '\0');
    EXPECT_GLB_ERROR(testing::glbFromChunks(json, bin),
                     "glTF: an index or a byte range in the document points outside what the file "
                     "holds");
}

TEST(MeshFileGlb, InstancesAreBoundedBeforeAnyIsRead) {
    // 3072 unindexed positions make 3072 + 1024 = 2^12 elements per instance: 2^13 instances
    // reach kMaxGlbElements, one more passes it.
    static_assert(kMaxGlbElements == uint64_t(1) << 25);
    GlbModel m;
    appendBytes(m.bin, std::vector<float>(3072 * 3, 0.0f));
    nlohmann::json nodes = nlohmann::json::array();
    nlohmann::json roots = nlohmann::json::array();
    for (int i = 0; i <= 8192; ++i) {
        nodes.push_back({{"mesh", 0}});
        roots.push_back(i);
    }
    m.gltf = {{"asset", {{"version", "2.0"}}},
              {"scenes", {{{"nodes", roots}}}},
              {"nodes", nodes},
              {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
              {"accessors",
               {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3072}, {"type", "VEC3"}}}},
              {"bufferViews", {{{"buffer", 0}, {"byteLength", m.bin.size()}}}},
              {"buffers", {{{"byteLength", m.bin.size()}}}}};
    EXPECT_GLB_ERROR(m.bytes(),
                     "node 8192: the nodes' meshes make more than 33554432 vertices and triangles "
                     "together, the most a glTF file may make");
}

TEST(MeshFileGlb, TheCallersTriangleLimitHoldsAsNodesAreCounted) {
    // Two nodes of two triangles each: a limit of 3 stops at the second node, before any is read,
    // as a MeshOverLimit (a service's limit, not a malformed file).
    const std::string bytes = squareGlb().bytes();
    EXPECT_EQ(parseMeshBytes(bytes, MeshFormat::Glb, {}, "m.glb", kMeshPath, 4).triangles.size(),
              4u);
    try {
        parseMeshBytes(bytes, MeshFormat::Glb, {}, "m.glb", kMeshPath, 3);
        ADD_FAILURE() << "loaded past its triangle limit";
    } catch (const MeshOverLimit& e) {
        EXPECT_EQ(e.message(),
                  "m.glb: node 1: the nodes' meshes make 4 triangles and 8 vertices "
                  "so far, over the limit of 3 triangles (and 3 vertices each)");
    }
}

TEST(MeshFileGlb, TheJsonChunkIsBounded) {
    // tinygltf keeps a node in a few hundred bytes: "{}," must not become 10 GB.
    GlbModel m = squareGlb();
    m.gltf["nodes"] = nlohmann::json::array();
    for (size_t i = 0; i <= kMaxGlbObjects; ++i)
        m.gltf["nodes"].push_back(nlohmann::json::object());
    EXPECT_GLB_ERROR(m.bytes(), "chunk 0 (JSON): 65537 nodes; at most 65536 of each are read");
    std::string padded = squareGlb().gltf.dump() + std::string(kMaxGlbJsonBytes, ' ');
    padded.resize((padded.size() + 3) / 4 * 4, ' ');
    EXPECT_GLB_ERROR(testing::glbFromChunks(padded, squareGlb().bin),
                     "chunk 0 (JSON): " + std::to_string(padded.size()) +
                         " bytes; at most 16777216 are read (the mesh data goes in the BIN chunk)");
}

}  // namespace
}  // namespace caustic
