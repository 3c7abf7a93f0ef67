// The CLI as a user runs it: a real process, real files.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <tuple>

#include "cli/cli_run.h"
#include "film/image_io.h"

namespace {

namespace fs = std::filesystem;
using caustic::testing::CliRun;
using caustic::testing::kTinyScene;
using caustic::testing::runCli;
using caustic::testing::writeFile;

using CliRender = caustic::testing::CliTest;

TEST_F(CliRender, WritesPngAndExrAndASummaryLine) {
    fs::path dir = tempDir();
    writeFile(dir / "tiny.json", kTinyScene);
    CliRun r = runCli("render " + (dir / "tiny.json").string() + " -o " + (dir / "a.png").string() +
                      " -o " + (dir / "a.exr").string() + " --set spp=4 --set integrator=raycast");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "a.png"));
    EXPECT_TRUE(fs::exists(dir / "a.exr"));
    EXPECT_NE(r.output.find("raycast, 16x12, 4 spp"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rays/s"), std::string::npos) << r.output;
}

// The tiny scene's camera is 16 x 12: --width and --height override it, and one of them alone
// keeps its aspect ratio.
TEST_F(CliRender, WidthAndHeightOverrideTheCamera) {
    fs::path dir = tempDir();
    writeFile(dir / "tiny.json", kTinyScene);
    const std::string render = "render " + (dir / "tiny.json").string() + " --spp 1 -o ";
    for (auto [options, width, height] :
         {std::tuple{"--width 32", 32, 24}, std::tuple{"--height 6", 8, 6},
          std::tuple{"--width 20 --height 10", 20, 10}, std::tuple{"--set width=40", 40, 30}}) {
        fs::path out = dir / "sized.exr";
        CliRun r = runCli(render + out.string() + " " + options);
        ASSERT_EQ(r.exitCode, 0) << options << "\n" << r.output;
        caustic::RgbImage image = caustic::readImage(out);
        EXPECT_EQ(image.width, width) << options;
        EXPECT_EQ(image.height, height) << options;
        EXPECT_NE(r.output.find(std::to_string(width) + "x" + std::to_string(height)),
                  std::string::npos)
            << r.output;
    }
    CliRun r = runCli(render + (dir / "big.png").string() + " --width 20000");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("/settings/width: must be in [0, 16384], got 20000"), std::string::npos)
        << r.output;
}

TEST_F(CliRender, BadSceneIsOneLineAndExitCodeTwo) {
    fs::path dir = tempDir();
    std::string bad = kTinyScene;
    bad.replace(bad.find("\"radius\": 1"), 11, "\"radius\": -1");
    writeFile(dir / "bad.json", bad);
    CliRun r = runCli("render " + (dir / "bad.json").string() + " -o " + (dir / "b.png").string());
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.output, "caustic: error: " + (dir / "bad.json").string() +
                            ": /shapes/0/radius: must be > 0\n");
    EXPECT_FALSE(fs::exists(dir / "b.png"));
}

TEST_F(CliRender, BadSettingNamesItsPath) {
    fs::path dir = tempDir();
    writeFile(dir / "tiny.json", kTinyScene);
    CliRun r = runCli("render " + (dir / "tiny.json").string() + " -o " + (dir / "c.png").string() +
                      " --set spp=0");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("/settings/spp: must be in [1, 1000000], got 0"), std::string::npos)
        << r.output;
}

TEST_F(CliRender, MalformedJsonReportsLineAndColumn) {
    fs::path dir = tempDir();
    writeFile(dir / "broken.json", "{\n  \"camera\": [1, 2,\n}");
    CliRun r =
        runCli("render " + (dir / "broken.json").string() + " -o " + (dir / "d.png").string());
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("invalid JSON"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("line 3"), std::string::npos) << r.output;
}

TEST_F(CliRender, UsageErrors) {
    EXPECT_EQ(runCli("render").exitCode, 2);
    EXPECT_EQ(runCli("render scene.json").exitCode, 2);
    EXPECT_EQ(runCli("render scene.json -o out.jpg").exitCode, 2);
    EXPECT_EQ(runCli("frobnicate").exitCode, 2);
    EXPECT_EQ(runCli("render --help").exitCode, 0);
}

TEST_F(CliRender, MissingSceneFile) {
    CliRun r = runCli("render /nonexistent/scene.json -o /tmp/x.png");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("cannot open /nonexistent/scene.json"), std::string::npos) << r.output;
}

}  // namespace
