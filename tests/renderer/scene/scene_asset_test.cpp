// The scene's "asset" mesh form: an uploaded mesh named by id and found through
// SceneOptions::resolveMeshAsset; counted from its stored counts when only counting.
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "renderer/scene/base_scene.h"
#include "scene/scene.h"
#include "support/glb_writer.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using testing::baseScene;
using testing::expectSceneError;
using testing::repoSceneOptions;

const std::string kId(64, 'a');
const std::string kOtherId = std::string(63, '0') + "f";
const std::string kSquareObj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

Json assetShape(const std::string& id) {
    return Json{{"type", "mesh"}, {"asset", id}, {"material", "white"}};
}

Json withShapes(const std::vector<Json>& shapes) {
    Json doc = baseScene();
    doc["shapes"] = shapes;
    return doc;
}

// A store of two assets that records what it was asked.
struct FakeStore {
    struct Call {
        std::string id, path;
        bool needBytes;
    };
    std::vector<Call> calls;

    MeshAssetResolver resolver() {
        return [this](const std::string& id, const std::string& path, bool needBytes) {
            calls.push_back({id, path, needBytes});
            MeshAsset a;
            if (id == kId) {
                a.format = MeshFormat::Obj;
                a.counts = MeshCounts{4, 2};
                a.bytes = std::make_shared<const std::string>(kSquareObj);
            } else if (id == kOtherId) {
                a.format = MeshFormat::Glb;
                a.counts = MeshCounts{8, 4};
                a.bytes = std::make_shared<const std::string>(testing::squareGlb().bytes());
            } else {
                throw InputError(path, "no asset " + id);
            }
            if (!needBytes) a.bytes = nullptr;
            return a;
        };
    }
    SceneOptions options(bool countOnly = false) {
        SceneOptions o = repoSceneOptions();
        o.resolveMeshAsset = resolver();
        o.countMeshesOnly = countOnly;
        return o;
    }
};

TEST(SceneMeshAsset, ResolvedAssetsAreLoaded) {
    FakeStore store;
    Json glb = assetShape(kOtherId);
    glb["transform"] = {{"translate", {0, 0, 0}}, {"scale", 0.5}};
    auto scene = loadScene(withShapes({assetShape(kId), glb}), store.options());
    // The OBJ's square is two triangles; the .glb's two nodes draw its square twice.
    EXPECT_EQ(scene->geometry.size(), 2u + 4u);
    EXPECT_TRUE(scene->countedMeshes.empty());
    ASSERT_EQ(store.calls.size(), 2u);
    EXPECT_EQ(store.calls[0].id, kId);
    EXPECT_EQ(store.calls[0].path, "/shapes/0/asset");
    EXPECT_TRUE(store.calls[0].needBytes);
    EXPECT_EQ(store.calls[1].path, "/shapes/1/asset");
}

TEST(SceneMeshAsset, CountingUsesTheStoredCountsAndNoBytes) {
    FakeStore store;
    auto scene =
        loadScene(withShapes({assetShape(kId), assetShape(kOtherId)}), store.options(true));
    ASSERT_EQ(scene->countedMeshes.size(), 2u);
    EXPECT_EQ(scene->countedMeshes[0].counts.vertices, 4u);
    EXPECT_EQ(scene->countedMeshes[0].counts.triangles, 2u);
    EXPECT_EQ(scene->countedMeshes[1].counts.vertices, 8u);
    EXPECT_EQ(scene->countedMeshes[1].counts.triangles, 4u);
    EXPECT_EQ(scene->geometry.size(), 0u);
    for (const FakeStore::Call& call : store.calls) EXPECT_FALSE(call.needBytes);
}

TEST(SceneMeshAsset, UnknownOrMalformedIds) {
    FakeStore store;
    const std::string unknown(64, 'b');
    expectSceneError(withShapes({assetShape(kId), assetShape(unknown)}), "/shapes/1/asset",
                     "no asset " + unknown, store.options());
    expectSceneError(withShapes({assetShape(unknown)}), "/shapes/0/asset", "no asset " + unknown,
                     store.options(true));
    const std::string notAnId =
        "must be an asset id: 64 lowercase hexadecimal digits (the SHA-256 of the file)";
    for (const std::string& bad :
         {std::string(64, 'A'), std::string(63, 'a'), std::string(65, 'a'), std::string(64, 'g'),
          std::string(""), "../" + std::string(61, 'a'), std::string(63, 'a') + '\0'}) {
        SCOPED_TRACE(bad);
        expectSceneError(withShapes({assetShape(bad)}), "/shapes/0/asset", notAnId,
                         store.options());
    }
    // The id is checked before the store is asked.
    EXPECT_EQ(store.calls.size(), 3u);
    Json number = assetShape(kId);
    number["asset"] = 7;
    expectSceneError(withShapes({number}), "/shapes/0/asset", "expected a string, got a number",
                     store.options());
}

TEST(SceneMeshAsset, ExactlyOneOfFileAndAsset) {
    FakeStore store;
    Json both = assetShape(kId);
    both["file"] = "teapot.obj";
    expectSceneError(withShapes({both}), "/shapes/0",
                     "a mesh has one of \"file\", \"asset\" and \"embedded\", not two",
                     store.options());
    Json neither = assetShape(kId);
    neither.erase("asset");
    expectSceneError(withShapes({neither}), "/shapes/0",
                     "a mesh needs \"file\" (an OBJ in the assets folder) or \"asset\" (an "
                     "uploaded mesh's id)",
                     store.options());
    EXPECT_TRUE(store.calls.empty());
}

TEST(SceneMeshAsset, WithoutAStore) {
    expectSceneError(withShapes({assetShape(kId)}), "/shapes/0/asset",
                     "this renderer has no asset store; use \"file\"", repoSceneOptions());
}

TEST(SceneMeshAsset, ABadFileNamesTheAssetAndItsLine) {
    SceneOptions o = repoSceneOptions();
    o.resolveMeshAsset = [](const std::string&, const std::string&, bool) {
        return MeshAsset{MeshFormat::Obj, MeshCounts{3, 1},
                         std::make_shared<const std::string>("v 0 0 0\nv 1 0 0\nf 1 2 3\n")};
    };
    expectSceneError(
        withShapes({assetShape(kId)}), "/shapes/0/asset",
        "asset " + kId + ": line 3: vertex index 3 is out of range (2 vertices above it)", o);
    // A store that gives no bytes for a render is a store bug, reported at the shape.
    o.resolveMeshAsset = [](const std::string&, const std::string&, bool) {
        return MeshAsset{MeshFormat::Obj, MeshCounts{3, 1}, nullptr};
    };
    expectSceneError(withShapes({assetShape(kId)}), "/shapes/0/asset",
                     "the asset store gave no bytes for asset " + kId, o);
}

}  // namespace
}  // namespace caustic
