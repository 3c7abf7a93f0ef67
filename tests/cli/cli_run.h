// Runs the caustic CLI as a user does, a real process on real files, for the CLI tests.
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

namespace fs = std::filesystem;

struct CliRun {
    int exitCode;
    std::string output;  // stdout and stderr together
};

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

// A scratch folder per test, removed when the test ends.
class CliRender : public ::testing::Test {
protected:
    void TearDown() override { fs::remove_all(dir_); }
    fs::path tempDir() {
        fs::create_directories(dir_);
        return dir_;
    }

private:
    fs::path dir_ = fs::temp_directory_path() /
                    ("caustic-cli-test-" + std::to_string(getpid()) + "-" +
                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
};

inline void writeFile(const fs::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

}  // namespace caustic::testing
