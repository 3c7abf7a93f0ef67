// `caustic serve`'s command line: each flag's range is checked before the server starts (exit 2,
// the flag named), --help states every default and range, and usage of the program as a whole.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "cli/cli_run.h"

namespace {

using caustic::testing::CliRun;
using caustic::testing::runCli;

TEST(ServeCommand, RejectsOutOfRangeFlagsWithExitCodeTwo) {
    // Each value breaks one rule of the number parser: range, whole, finite, full string.
    const char* cases[][2] = {{"--port", "70000"},        {"--port", "80.5"},
                              {"--port", "8080x"},        {"--workers", "65"},
                              {"--lease-seconds", "nan"}, {"--lease-seconds", "inf"},
                              {"--max-photons", "1e10"},  {"--max-request-bytes", "-5"},
                              {"--max-memory-mib", "''"}};
    for (const auto& [flag, value] : cases) {
        CliRun r = runCli(std::string("serve --data /nonexistent/caustic ") + flag + " " + value);
        EXPECT_EQ(r.exitCode, 2) << flag << " " << value << ": " << r.output;
        EXPECT_EQ(r.output.rfind(std::string("caustic serve: ") + flag + ": must be a ", 0), 0)
            << r.output;
    }
}

TEST(ServeCommand, OtherUsageErrors) {
    CliRun r = runCli("serve --port");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    r = runCli("serve --no-such-flag");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--no-such-flag"), std::string::npos) << r.output;
    // Off loopback without a token: refused before anything listens.
    r = runCli("serve --host 0.0.0.0 --data /nonexistent/caustic");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--host: listening on 0.0.0.0 exposes the service"), std::string::npos)
        << r.output;
}

TEST(ServeCommand, AllowOriginTakesOnlyOriginsAndLogLevelOnlyLevels) {
    // "*" and "null" are no origin; a path or a trailing slash never matches a browser's Origin.
    for (const char* origin : {"'*'", "null", "http://localhost:5173/", "http://localhost:5173/app",
                               "localhost:5173", "ftp://localhost"}) {
        CliRun r =
            runCli(std::string("serve --data /nonexistent/caustic --allow-origin ") + origin);
        EXPECT_EQ(r.exitCode, 2) << origin << ": " << r.output;
        EXPECT_EQ(r.output.rfind("caustic serve: --allow-origin: must be scheme://host[:port]", 0),
                  0)
            << r.output;
    }
    CliRun r = runCli("serve --data /nonexistent/caustic --log-level loud");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output.rfind("caustic serve: --log-level: loud not in", 0), 0) << r.output;
}

TEST(ServeCommand, HelpStatesDefaultsAndRanges) {
    CliRun r = runCli("serve --help");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* line :
         {"--port INT in [0, 65535]=8080", "--workers INT in [0, 64]=1", "--store URL",
          "(Env:CAUSTIC_STORE)", "--task-passes INT in [1, 1048576]=8",
          "--lease-seconds NUMBER in [0.5, 3600]=10", "--max-spp INT in [1, 1000000]=65536",
          "--data DIR=data", "(Env:CAUSTIC_DATA)", "(Env:CAUSTIC_TOKEN)", "--allow-origin ORIGIN",
          "--log-level TEXT:{trace,debug,info,warning,error,critical,off}=info",
          "--access-log FILE|-"})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << " not in:\n" << r.output;
}

TEST(WorkerCommand, NeedsAPostgresStoreAndAWorker) {
    CliRun r = runCli("worker --help");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* line :
         {"--store URL REQUIRED", "--workers INT in [1, 64]=1", "--threads INT in [0, 1024]=0",
          "--block-after-failures", "--hand-in-seconds NUMBER in [0, 3600]=120"})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << " not in:\n" << r.output;
    r = runCli("worker --store postgresql://127.0.0.1:1/x --workers 0");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output.rfind("caustic worker: --workers: must be a ", 0), 0) << r.output;
}

// How long a start waits for PostgreSQL comes from CAUSTIC_STORE_WAIT too (the compose projects
// set it), checked as the flag is.
TEST(WorkerCommand, StoreWaitFromTheEnvironment) {
    EXPECT_NE(runCli("worker --help").output.find("(Env:CAUSTIC_STORE_WAIT)"), std::string::npos);
    setenv("CAUSTIC_STORE_WAIT", "4000", 1);
    CliRun r = runCli("worker --store postgresql://127.0.0.1:1/x");
    unsetenv("CAUSTIC_STORE_WAIT");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(r.output.rfind("caustic worker: --store-wait: must be a number in [0, 3600]", 0), 0)
        << r.output;
}

TEST(CausticCommand, VersionHelpAndUsage) {
    CliRun r = runCli("--version");
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_EQ(r.output.rfind("caustic ", 0), 0) << r.output;
    r = runCli("--help");
    EXPECT_EQ(r.exitCode, 0);
    for (const char* command : {"render", "serve", "settings"})
        EXPECT_NE(r.output.find(command), std::string::npos) << r.output;
    EXPECT_EQ(runCli("").exitCode, 2);
    EXPECT_EQ(runCli("frobnicate").exitCode, 2);
}

}  // namespace
