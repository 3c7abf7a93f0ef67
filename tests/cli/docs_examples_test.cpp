// The scene examples of docs/scene-format.md render as written: each ```json block holding a
// scene (an object with a "camera") goes through `caustic render`, so the documentation cannot
// drift from the loader. A scene naming an uploaded "asset" needs the render service's asset
// store (tests/server/test_api.py uploads a mesh and renders it); here it is counted, not rendered.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/cli_run.h"

namespace {

namespace fs = std::filesystem;
using caustic::testing::CliRun;
using caustic::testing::runCli;
using caustic::testing::writeFile;

using DocsExamples = caustic::testing::CliTest;

// The text of every fenced block opened by "```json".
std::vector<std::string> jsonBlocks(const std::string& markdown) {
    std::vector<std::string> blocks;
    std::istringstream in(markdown);
    std::string line, block;
    bool inside = false;
    while (std::getline(in, line)) {
        if (!inside && line == "```json") {
            inside = true;
            block.clear();
        } else if (inside && line == "```") {
            inside = false;
            blocks.push_back(block);
        } else if (inside) {
            block += line + "\n";
        }
    }
    return blocks;
}

bool namesAnAsset(const nlohmann::json& scene) {
    for (const nlohmann::json& shape : scene.value("shapes", nlohmann::json::array()))
        if (shape.contains("asset")) return true;
    return false;
}

TEST_F(DocsExamples, EverySceneOfTheSceneFormatRenders) {
    std::ifstream in(fs::path(CAUSTIC_SOURCE_DIR) / "docs" / "scene-format.md");
    ASSERT_TRUE(in) << "docs/scene-format.md is missing";
    std::stringstream text;
    text << in.rdbuf();
    fs::path dir = tempDir();
    int rendered = 0, withAssets = 0;
    for (const std::string& block : jsonBlocks(text.str())) {
        nlohmann::json doc = nlohmann::json::parse(block);  // every json block is valid JSON
        if (!doc.is_object() || !doc.contains("camera")) continue;
        if (namesAnAsset(doc)) {
            ++withAssets;
            continue;
        }
        fs::path scene = dir / ("example-" + std::to_string(rendered) + ".json");
        writeFile(scene, block);
        // One sample per pixel: the point is that the scene loads and renders, not the image.
        CliRun r = runCli("render " + scene.string() + " -o " + (dir / "out.png").string() +
                          " --spp 1 --no-progress");
        EXPECT_EQ(r.exitCode, 0) << "example " << rendered << ":\n" << block << "\n" << r.output;
        ++rendered;
    }
    // The introduction, the Cornell box and the bunny; the uploaded mesh.
    EXPECT_EQ(rendered, 3);
    EXPECT_EQ(withAssets, 1);
}

}  // namespace
