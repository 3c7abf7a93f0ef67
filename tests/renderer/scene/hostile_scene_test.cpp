// Scenes written to hurt the loader (issue 12): nesting deep enough to overflow the call stack,
// and OBJ files whose `mtllib` names files outside the assets folder.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "render/settings.h"
#include "renderer/scene/base_scene.h"
#include "scene/json_reader.h"
#include "scene/scene.h"
#include "support/temp_dir.h"

namespace caustic {
namespace {

// `levels` objects nested in one another, {"a": {"a": ... 1}}, as text: nlohmann::json parses and
// destroys any depth without recursion, but copies and compares recursively.
std::string nestedObjects(int levels) {
    std::string text;
    for (int i = 0; i < levels; ++i) text += "{\"a\": ";
    return text + "1" + std::string(levels, '}');
}

// The base scene with `settings` set to the given JSON text.
Json withSettingsText(const std::string& settings) {
    std::string base = testing::baseScene().dump();
    return parseJson(base.substr(0, base.size() - 1) + ", \"settings\": " + settings + "}");
}

// The path of the object at `level` in the settings' chain of "a"s (the root is level 1, the
// settings object level 2).
std::string settingsPathAt(int level) {
    std::string path = "/settings";
    for (int l = 3; l <= level; ++l) path += "/a";
    return path;
}

void expectTooDeep(const Json& doc, const std::string& path) {
    try {
        loadScene(doc, SceneOptions{});
        ADD_FAILURE() << "loaded; expected an error at " << path;
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), path);
        EXPECT_EQ(e.message(), "nested deeper than 64 levels of arrays and objects");
    }
}

// Bug 3: settings nested 100000 deep overflowed the stack when the loader copied them.
TEST(HostileScenes, SettingsNestedTooDeepAreRefusedWithTheirPath) {
    expectTooDeep(withSettingsText(nestedObjects(100000)), settingsPathAt(65));
}

TEST(HostileScenes, SixtyFourLevelsLoadAndSixtyFiveDoNot) {
    // 63 objects in the settings: the deepest is level 64.
    std::unique_ptr<Scene> scene = loadScene(withSettingsText(nestedObjects(63)), SceneOptions{});
    EXPECT_TRUE(scene->settings.contains("a"));
    expectTooDeep(withSettingsText(nestedObjects(64)), settingsPathAt(65));
}

TEST(HostileScenes, ArraysNestedTooDeepAreRefusedWherever) {
    const int levels = 100000;
    Json doc = testing::patched("/camera/position", Json::array());
    std::string text = doc.dump(), arrays = std::string(levels, '[') + std::string(levels, ']');
    size_t at = text.find("\"position\":[]") + 11;
    doc = parseJson(text.replace(at, 2, arrays));
    // Root 1, camera 2, position 3: level 65 is position's 62nd nested array.
    std::string path = "/camera/position";
    for (int level = 4; level <= 65; ++level) path += "/0";
    expectTooDeep(doc, path);
}

TEST(HostileScenes, DepthCheckWalksAnyShape) {
    Json wide = Json::array(), item = Json::parse(R"({"x": [1, 2, [3]]})");
    for (int i = 0; i < 1000; ++i) wide.push_back(item);
    EXPECT_NO_THROW(checkJsonDepth(wide, "/w", 4));
    EXPECT_THROW(checkJsonDepth(wide, "/w", 3), InputError);
    EXPECT_NO_THROW(checkJsonDepth(Json(1.5), "", 0));
    try {
        checkJsonDepth(Json::parse(R"({"k/~": [[]]})"), "/p", 2);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/p/k~1~0/0");  // RFC 6901 escapes
    }
}

TEST(HostileScenes, TryParseJsonRefusesDeepTextWhileParsing) {
    EXPECT_EQ(tryParseJson(nestedObjects(64)), parseJson(nestedObjects(64)));
    EXPECT_EQ(tryParseJson(nestedObjects(65)), std::nullopt);
    EXPECT_EQ(tryParseJson(nestedObjects(1000000)), std::nullopt);
    EXPECT_EQ(tryParseJson("[[1]]", 2), Json::parse("[[1]]"));
    EXPECT_EQ(tryParseJson("[[1]]", 1), std::nullopt);
    EXPECT_EQ(tryParseJson("{\"a\": "), std::nullopt);
    EXPECT_EQ(tryParseJson("7"), Json(7));
}

TEST(HostileScenes, SettingValuesNestedTooDeepStayText) {
    std::string deep = std::string(100000, '[') + std::string(100000, ']');
    EXPECT_EQ(parseSettingValue(deep), Json(deep));
    EXPECT_EQ(parseSettingValue("[[[1]]]"), Json::parse("[[[1]]]"));
}

// A mesh "m.obj" in `dir`/assets whose mtllib names `mtllib`, with two triangles.
SceneOptions assetsWithMtllib(const testing::TempDir& dir, const std::string& mtllib) {
    std::filesystem::create_directories(dir.path() / "assets");
    dir.write("assets/m.obj", "mtllib " + mtllib +
                                  "\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                  "f 1 2 3\nf 2 4 3\n");
    SceneOptions options;
    options.assetsDir = dir.path() / "assets";
    return options;
}

// Loads the scene in a child process (a gtest death test) that SIGALRM ends after 5 s: a loader
// that opened a FIFO would block there for ever, one reading /dev/zero would never finish, and the
// test still ends. The child exits 0 once the mesh's two triangles loaded.
void expectMeshLoadsPromptly(const SceneOptions& options) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    Json doc = testing::baseScene();
    doc["shapes"][0] = {{"type", "mesh"}, {"file", "m.obj"}, {"material", "white"}};
    EXPECT_EXIT(
        {
            alarm(5);
            std::_Exit(loadScene(doc, options)->geometry.size() == 2 ? 0 : 1);
        },
        ::testing::ExitedWithCode(0), "");
}

// Bug 4: tinyobjloader read `mtllib` relative to the OBJ's folder, wherever that led.
TEST(HostileScenes, MtllibNamingDevZeroIsNotRead) {
    testing::TempDir dir;
    expectMeshLoadsPromptly(assetsWithMtllib(dir, "../../../../../../../../../../../dev/zero"));
}

TEST(HostileScenes, MtllibNamingAFileOutsideTheAssetsFolderIsNotOpened) {
    testing::TempDir dir;
    // Opening a FIFO for reading blocks until a writer comes; none ever does.
    ASSERT_EQ(mkfifo((dir.path() / "outside.mtl").c_str(), 0600), 0);
    expectMeshLoadsPromptly(assetsWithMtllib(dir, "../outside.mtl"));
}

}  // namespace
}  // namespace caustic
