// Scene files written to hurt the CLI: each is refused with exit code 2 and one line naming the
// JSON path, never a crash.
#include <gtest/gtest.h>

#include <string>

#include "cli/cli_run.h"

namespace {

using CliRender = caustic::testing::CliTest;
using caustic::testing::CliRun;
using caustic::testing::runCli;
using caustic::testing::writeFile;

// `settings` nested 100000 objects deep once overflowed the stack of `caustic render` (issue 12,
// bug 3: the loader copied the settings recursively; the server's depth limit hid it).
TEST_F(CliRender, SettingsNestedTooDeepAreRefusedWithTheirPath) {
    const int levels = 100000;
    std::string settings, closing(levels, '}');
    for (int i = 0; i < levels; ++i) settings += "{\"a\": ";
    std::string scene = R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
        "materials": {"white": {"type": "diffuse"}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}],
        "settings": )" + settings +
                        "1" + closing + "}";
    auto dir = tempDir();
    writeFile(dir / "deep.json", scene);
    CliRun r =
        runCli("render " + (dir / "deep.json").string() + " -o " + (dir / "out.png").string());
    // The root is level 1 and the settings object level 2: level 65 is the settings' 64th "a".
    std::string path = "/settings";
    for (int level = 3; level <= 65; ++level) path += "/a";
    EXPECT_EQ(r.exitCode, 2) << r.output.substr(0, 500);
    EXPECT_EQ(r.output, "caustic: error: " + (dir / "deep.json").string() + ": " + path +
                            ": nested deeper than 64 levels of arrays and objects\n");
}

// A --set value nested 50000 deep (an argument holds up to 128 KiB) would overflow the stack of a
// sanitizer build when the settings are merged; it is kept as text, which no setting takes.
TEST_F(CliRender, SetValueNestedTooDeepIsText) {
    const int levels = 50000;
    auto dir = tempDir();
    writeFile(dir / "tiny.json", R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
        "materials": {"white": {"type": "diffuse"}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}]})");
    CliRun r =
        runCli("render " + (dir / "tiny.json").string() + " -o " + (dir / "out.png").string() +
               " --set spp=" + std::string(levels, '[') + std::string(levels, ']'));
    EXPECT_EQ(r.exitCode, 2) << r.output.substr(0, 500);
    EXPECT_EQ(r.output, "caustic: error: " + (dir / "tiny.json").string() +
                            ": /settings/spp: expected an integer, got a string\n");
}

}  // namespace
