// Mesh files from memory, OBJ side (parseMeshBytes): known answers, the real meshes, and every
// kind of bad file, each an InputError naming the line at fault. The media type table too.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "renderer/scene/mesh_file_expect.h"
#include "scene/mesh_counts.h"
#include "scene/mesh_file.h"

namespace caustic {
namespace {

using testing::kMeshPath;

TriangleMesh parseObjText(const std::string& text, const MeshTransform& transform = {}) {
    return parseMeshBytes(text, MeshFormat::Obj, transform, "bunny.obj", kMeshPath);
}

#define EXPECT_OBJ_ERROR(text, message) \
    EXPECT_MESH_ERROR(text, MeshFormat::Obj, "bunny.obj", message)

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(MeshFileFormats, MediaTypesAndNames) {
    EXPECT_EQ(meshFormatOfMediaType("model/obj"), MeshFormat::Obj);
    EXPECT_EQ(meshFormatOfMediaType("model/gltf-binary"), MeshFormat::Glb);
    EXPECT_EQ(meshFormatOfMediaType("Model/OBJ; charset=utf-8"), MeshFormat::Obj);
    EXPECT_EQ(meshFormatOfMediaType(" model/gltf-binary ;x=y"), MeshFormat::Glb);
    for (const char* other : {"", "model/gltf+json", "text/plain", "model/objx", "model"})
        EXPECT_EQ(meshFormatOfMediaType(other), std::nullopt) << other;
    for (MeshFormat f : {MeshFormat::Obj, MeshFormat::Glb}) {
        EXPECT_EQ(meshFormatOfMediaType(mediaTypeOf(f)), f);
        EXPECT_EQ(meshFormatNamed(nameOf(f)), f);
    }
    EXPECT_STREQ(mediaTypeOf(MeshFormat::Obj), "model/obj");
    EXPECT_STREQ(mediaTypeOf(MeshFormat::Glb), "model/gltf-binary");
    EXPECT_STREQ(nameOf(MeshFormat::Obj), "obj");
    EXPECT_STREQ(nameOf(MeshFormat::Glb), "glb");
    EXPECT_EQ(meshFormatNamed("OBJ"), std::nullopt);
    EXPECT_EQ(meshFormatNamed("gltf"), std::nullopt);
}

TEST(MeshFileObj, KnownAnswer) {
    // Relative indices, texture and normal indices, a comment, CRLF and a lone CR line end, and an
    // mtllib that must not be opened.
    TriangleMesh m = parseObjText(
        "# two triangles\r\nmtllib /dev/zero\nv 0 0 0\nv 2 0 0\rv 0 3 0\nvt 0 0\nvn 0 0 1\n"
        "f 1/1/1 2/1/1 3/1/1\nv 5 5 -1\nf -4//1 -3//1 -1//1");
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.positions[1], Vec3(2, 0, 0));
    EXPECT_EQ(m.positions[2], Vec3(0, 3, 0));
    EXPECT_EQ(m.positions[3], Vec3(5, 5, -1));
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(m.triangles[1], glm::uvec3(0, 1, 3));
    MeshBounds b = boundsOf(m);
    EXPECT_EQ(b.min, Vec3(0, 0, -1));
    EXPECT_EQ(b.max, Vec3(5, 5, 0));
}

TEST(MeshFileObj, PolygonsAreTriangulatedAndTransformed) {
    MeshTransform t;
    t.scale = Vec3(2.0f);
    t.translate = Vec3(0, 0, 1);
    TriangleMesh m =
        parseObjText("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\nf 1 2 3 5 4\n", t);
    ASSERT_EQ(m.positions.size(), 5u);
    EXPECT_EQ(m.positions[4], Vec3(1, 4, 1));
    EXPECT_EQ(m.triangles.size(), 3u);  // a pentagon
    MeshBounds b = boundsOf(m);
    EXPECT_EQ(b.min, Vec3(0, 0, 1));
    EXPECT_EQ(b.max, Vec3(2, 4, 1));
}

TEST(MeshFileObj, RealMeshesLoadAsTheirFiles) {
    const std::filesystem::path meshes = CAUSTIC_SOURCE_DIR "/assets/meshes";
    for (const char* name : {"teapot.obj", "spot.obj", "stanford-bunny.obj"}) {
        SCOPED_TRACE(name);
        std::ifstream in(meshes / name, std::ios::binary);
        std::stringstream bytes;
        bytes << in.rdbuf();
        ASSERT_GT(bytes.str().size(), 0u);
        TriangleMesh fromBytes = parseMeshBytes(bytes.str(), MeshFormat::Obj, {}, name, kMeshPath);
        TriangleMesh fromFile = loadObj(meshes / name, {}, kMeshPath);
        EXPECT_EQ(fromBytes.positions, fromFile.positions);
        EXPECT_EQ(fromBytes.triangles, fromFile.triangles);
        MeshCounts counts = countObj(meshes / name, kMeshPath);
        EXPECT_EQ(fromBytes.positions.size(), counts.vertices);
        EXPECT_EQ(fromBytes.triangles.size(), counts.triangles);
    }
}

TEST(MeshFileObj, TruncatedFile) {
    EXPECT_OBJ_ERROR(kTriangle + "f 1 2",
                     "line 4: the file ends in the middle of a statement (truncated): a face "
                     "needs 3 corners, got 2");
    EXPECT_OBJ_ERROR("v 0 0 0\nv 1 0",
                     "line 2: the file ends in the middle of a statement (truncated): a vertex "
                     "needs 3 numbers, got 2");
    EXPECT_OBJ_ERROR(kTriangle + "f 1 2 3\nv 1 0 1.5e",
                     "line 5: the file ends in the middle of a statement (truncated): vertex "
                     "\"1.5e\" is not a number");
    // The same lines with their end of line are bad lines, not a cut file.
    EXPECT_OBJ_ERROR(kTriangle + "f 1 2\n", "line 4: a face needs 3 corners, got 2");
}

TEST(MeshFileObj, BinaryGarbage) {
    EXPECT_OBJ_ERROR(kTriangle +
                         "f 1 2 3\n\x7f"
                         "ELF\x02\x01",
                     "line 5: binary data (byte 0x7f)");
    EXPECT_OBJ_ERROR(std::string("v 0 0 0\nv 1\0 0 0\n", 17), "line 2: binary data (byte 0x00)");
    EXPECT_OBJ_ERROR("\x89PNG\r\n\x1a\n", "line 2: binary data (byte 0x1a)");
    // A comment with UTF-8 is text.
    EXPECT_EQ(parseObjText("# caf\xc3\xa9\n" + kTriangle + "f 1 2 3\n").triangles.size(), 1u);
}

TEST(MeshFileObj, NonFiniteOrBadVertex) {
    EXPECT_OBJ_ERROR("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
                     "line 2: vertex \"nan\" is not a finite number");
    EXPECT_OBJ_ERROR("v 0 0 0\nv 1 0 0\nv 0 1 -inf\nf 1 2 3\n",
                     "line 3: vertex \"-inf\" is not a finite number");
    EXPECT_OBJ_ERROR("v 1e39 0 0\n", "line 1: vertex \"1e39\" is out of the range of a float");
    EXPECT_OBJ_ERROR("v 1e999 0 0\n", "line 1: vertex \"1e999\" is out of range");
    EXPECT_OBJ_ERROR("v 0 zero 0\n", "line 1: vertex \"zero\" is not a number");
    EXPECT_OBJ_ERROR("\n\nv\n", "line 3: a vertex needs 3 numbers, got 0");
    // What tinyobjloader writes and reads: signs, no leading digit, exponents; extra numbers.
    EXPECT_EQ(
        parseObjText("v +1 -.5 2E-3 1\nv 1. 0 0 0.5 0.5 0.5\nv 0 1 0\nf 1 2 3\n").positions[0],
        Vec3(1.0f, -0.5f, 2e-3f));
}

TEST(MeshFileObj, IndexOutOfRange) {
    EXPECT_OBJ_ERROR(kTriangle + "f 1 2 4\n",
                     "line 4: vertex index 4 is out of range (3 vertices above it)");
    EXPECT_OBJ_ERROR(kTriangle + "f -1 -2 -4\n",
                     "line 4: vertex index -4 is out of range (3 vertices above it)");
    // A vertex defined below the face that uses it is out of range at that line.
    EXPECT_OBJ_ERROR("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n",
                     "line 3: vertex index 3 is out of range (2 vertices above it)");
    EXPECT_OBJ_ERROR(kTriangle + "f 0 1 2\n",
                     "line 4: vertex index 0 in a face (OBJ counts vertices from 1)");
    EXPECT_OBJ_ERROR(kTriangle + "f 1 2 99999999999999999999\n",
                     "line 4: face corner \"99999999999999999999\" is not v, v/vt, v//vn or "
                     "v/vt/vn");
    EXPECT_OBJ_ERROR(kTriangle + "f 1/x 2 3\n",
                     "line 4: face corner \"1/x\" is not v, v/vt, v//vn or v/vt/vn");
    EXPECT_OBJ_ERROR(kTriangle + "f 1/0 2 3\n",
                     "line 4: face corner \"1/0\" is not v, v/vt, v//vn or v/vt/vn");
    EXPECT_OBJ_ERROR(kTriangle + "f 1 2 3 # done\n",
                     "line 4: face corner \"#\" is not v, v/vt, v//vn or v/vt/vn");
}

TEST(MeshFileObj, EmptyOrWithoutTriangles) {
    EXPECT_OBJ_ERROR("", "the file is empty");
    EXPECT_OBJ_ERROR(" \r\n\t\n", "the file is empty");
    EXPECT_OBJ_ERROR("# only a comment\n", "has no faces (no triangles)");
    EXPECT_OBJ_ERROR(kTriangle + "l 1 2 3\np 1\n", "has no faces (no triangles)");
}

TEST(MeshFileObj, PolygonCornersAreBounded) {
    // Ear clipping is quadratic in a polygon's corners: a face of more than 256 is refused. A
    // convex polygon of 256 corners (on a circle) makes 254 triangles.
    std::ostringstream vertices, face;
    face << "f";
    for (size_t i = 0; i < kMaxObjFaceCorners + 1; ++i) {
        const double angle = 2 * kPi * double(i) / double(kMaxObjFaceCorners + 1);
        vertices << "v " << std::cos(angle) << ' ' << std::sin(angle) << " 0\n";
        if (i < kMaxObjFaceCorners) face << ' ' << i + 1;
    }
    EXPECT_EQ(parseObjText(vertices.str() + face.str() + "\n").triangles.size(),
              kMaxObjFaceCorners - 2);
    EXPECT_OBJ_ERROR(vertices.str() + face.str() + " 257\n",
                     "line 258: a face of 257 corners; at most 256 are read (split the polygon)");
}

TEST(MeshFileObj, TrianglesOverTheLimitStopTheLinePass) {
    // Counted before tinyobjloader builds any: the line that passes the limit is named, as a
    // MeshOverLimit (a limit, not a malformed file).
    const std::string text = kTriangle + "f 1 2 3\nf 1 2 3 1\nf 1 2 3\n";
    EXPECT_EQ(parseMeshBytes(text, MeshFormat::Obj, {}, "", kMeshPath, 4).triangles.size(), 4u);
    try {
        parseMeshBytes(text, MeshFormat::Obj, {}, "bunny.obj", kMeshPath, 2);
        ADD_FAILURE() << "loaded past its triangle limit";
    } catch (const MeshOverLimit& e) {
        EXPECT_EQ(e.path(), kMeshPath);
        EXPECT_EQ(e.message(),
                  "bunny.obj: line 5: the faces so far make 3 triangles, over the limit of 2");
    }
}

TEST(MeshFileObj, VerticesOverThreeATriangleOfTheLimitStopTheLinePass) {
    // tinyobjloader keeps every vertex, used or not: a file of one face and millions of "v" lines
    // would take their memory within its triangle limit.
    std::string text = kTriangle + "vn 0 0 1\nvn 0 0 1\nvt 0 0\nf 1 2 3\n";
    EXPECT_EQ(parseMeshBytes(text, MeshFormat::Obj, {}, "", kMeshPath, 1).triangles.size(), 1u);
    try {
        parseMeshBytes("v 0 0 0\n" + text, MeshFormat::Obj, {}, "", kMeshPath, 1);
        ADD_FAILURE() << "loaded 4 vertices for a limit of 1 triangle";
    } catch (const MeshOverLimit& e) {
        EXPECT_EQ(
            e.message(),
            "line 4: 4 vertices, over the limit of 3 (3 for each of the 1 triangles allowed)");
    }
    EXPECT_THROW(
        parseMeshBytes(text + "vt 0 0\nvt 0 0\nvt 0 0\n", MeshFormat::Obj, {}, "", kMeshPath, 1),
        MeshOverLimit);
}

TEST(MeshFileObj, NoNameMeansTheMessageAlone) {
    try {
        parseMeshBytes("", MeshFormat::Obj, {}, "", kMeshPath);
        ADD_FAILURE() << "an empty file loaded";
    } catch (const InputError& e) {
        EXPECT_EQ(e.message(), "the file is empty");
    }
}

}  // namespace
}  // namespace caustic
