// Runs the caustic binary as a user does (a real process, real files), for the CLI tests.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace caustic::testing {

struct CliRun {
    int exitCode;
    std::string output;  // stdout and stderr together
};

/// Runs `caustic ARGS` through the shell (ARGS is shell text) and collects its output.
inline CliRun runCli(const std::string& args) {
    std::string cmd = std::string(CAUSTIC_CLI_PATH) + " " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    CliRun r{-1, ""};
    if (!pipe) return r;
    std::array<char, 4096> buf{};
    while (fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
    int status = pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

inline void writeFile(const std::filesystem::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

/// A scene that renders in milliseconds: a diffuse sphere under a point light, 16x12.
inline const char* kTinyScene = R"({
  "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "width": 16, "height": 12},
  "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
  "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}],
  "lights": [{"type": "point", "position": [0, 2, 2], "intensity": [10, 10, 10]}]
})";

/// A scratch folder per test, removed when the test ends.
class CliTest : public ::testing::Test {
protected:
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::filesystem::path tempDir() {
        std::filesystem::create_directories(dir_);
        return dir_;
    }

private:
    std::filesystem::path dir_ = std::filesystem::temp_directory_path() /
                                 ("caustic-cli-test-" + std::to_string(getpid()) + "-" +
                                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
};

}  // namespace caustic::testing
