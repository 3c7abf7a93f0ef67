// Mesh counts from a line scan: the same vertex and triangle counts as loading the mesh, without
// parsing it, and a cache that reads a file again only when its size or time changes.
#include "scene/mesh_counts.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/mesh_loader.h"
#include "scene/scene.h"
#include "support/temp_dir.h"

namespace caustic {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

const fs::path kAssets = CAUSTIC_SOURCE_DIR "/assets/meshes";

void expectCountsOfLoad(const fs::path& file) {
    SCOPED_TRACE(file.string());
    MeshCounts counts = countObj(file, "/file");
    TriangleMesh mesh = loadObj(file, MeshTransform{}, "/file");
    EXPECT_EQ(counts.triangles, mesh.triangles.size());
    EXPECT_EQ(counts.normals, !mesh.normals.empty());
    // With normals the vertices are the distinct (position, normal) pairs: counted as a bound.
    if (counts.normals)
        EXPECT_GE(counts.vertices, mesh.positions.size());
    else
        EXPECT_EQ(counts.vertices, mesh.positions.size());
}

TEST(MeshCounts, ExampleMeshesCountAsTheyLoad) {
    for (const char* name : {"stanford-bunny.obj", "teapot.obj", "spot.obj"})
        expectCountsOfLoad(kAssets / name);
    EXPECT_EQ(countObj(kAssets / "stanford-bunny.obj", "/file").triangles, 69451u);
}

TEST(MeshCounts, PolygonsNormalsTabsCrlfAndNoFinalNewline) {
    TempDir dir;
    // A quad (2 triangles) and a pentagon (3); texture coordinates, comments, groups and a
    // two-corner face count for nothing; CRLF line ends, tabs, and no newline after the last face.
    dir.write("mixed.obj",
              "# a comment with v and f in it\r\n"
              "v 0 0 0\r\nv 1 0 0\r\n\tv 1 1 0\r\nv 0 1 0\r\nv -1 0.5 0\r\n"
              "vn 0 0 1\r\nvt 0 0\r\ng part\r\n"
              "f 1/1/1 2/1/1 3/1/1 4/1/1\r\n"
              "f 1 2\r\n"
              "f\t1 2 3 4 5");
    MeshCounts counts = countObj(dir.path() / "mixed.obj", "/file");
    // With normals, a bound: one vertex a corner, three a triangle.
    EXPECT_TRUE(counts.normals);
    EXPECT_EQ(counts.vertices, 15u);
    EXPECT_EQ(counts.triangles, 5u);
    expectCountsOfLoad(dir.path() / "mixed.obj");
}

TEST(MeshCounts, NoFacesOrNoFileIsAnInputError) {
    TempDir dir;
    dir.write("empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    try {
        countObj(dir.path() / "empty.obj", "/shapes/2/file");
        ADD_FAILURE() << "counted a mesh without faces";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/shapes/2/file");
        EXPECT_EQ(e.message(), "empty.obj has no faces");  // as loadObj says it
    }
    EXPECT_THROW(countObj(dir.path() / "missing.obj", "/file"), InputError);
}

// Counting parses no number: a vertex that loading refuses is only counted. The worker's load
// finds it (tests/server: the job then fails with the load's path and detail).
TEST(MeshCounts, CountsOnlySceneDoesNotParseTheMesh) {
    TempDir dir;
    dir.write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n");
    nlohmann::json doc = nlohmann::json::parse(R"({
      "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
      "materials": {"white": {"type": "diffuse"}},
      "shapes": [{"type": "mesh", "file": "bad.obj", "material": "white"}]
    })");
    SceneOptions options;
    options.assetsDir = dir.path();
    EXPECT_THROW(loadScene(doc, options), InputError);
    options.countMeshesOnly = true;
    std::unique_ptr<Scene> scene = loadScene(doc, options);
    ASSERT_EQ(scene->countedMeshes.size(), 1u);
    EXPECT_EQ(scene->countedMeshes[0].counts.vertices, 3u);
    EXPECT_EQ(scene->countedMeshes[0].counts.triangles, 1u);
    EXPECT_EQ(scene->geometry.size(), 0u);
    // Everything else is still validated: the file must exist inside the assets folder.
    doc["shapes"][0]["file"] = "../bad.obj";
    EXPECT_THROW(loadScene(doc, options), InputError);
}

TEST(MeshCounts, CacheScansAFileOncePerSizeAndTime) {
    TempDir dir;
    const fs::path file = dir.path() / "m.obj";
    dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    MeshCountCache cache;
    EXPECT_EQ(cache.counts(file, "/file").triangles, 1u);
    EXPECT_EQ(cache.counts(dir.path() / "." / "m.obj", "/file").triangles, 1u);
    EXPECT_EQ(cache.scans(), 1u);

    // Rewritten with the same size and its old time restored: the cache cannot tell, and answers
    // without reading the file (its body now has no face at all).
    const fs::file_time_type modified = fs::last_write_time(file);
    dir.write("m.obj", "# 0 0 0\n# 1 0 0\n# 0 1 0\n# 1 2 3\n");
    fs::last_write_time(file, modified);
    EXPECT_EQ(cache.counts(file, "/file").triangles, 1u);
    EXPECT_EQ(cache.scans(), 1u);

    // A new time: scanned again.
    fs::last_write_time(file, modified + std::chrono::seconds(1));
    EXPECT_THROW(cache.counts(file, "/file"), InputError);
    dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
    EXPECT_EQ(cache.counts(file, "/file").triangles, 2u);
    EXPECT_EQ(cache.scans(), 3u);
}

}  // namespace
}  // namespace caustic
