// Helpers shared by the benchmark programs: the command line (CLI11), the machine line,
// statistics.
#pragma once

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.h"
#include "core/interrupt.h"

namespace caustic::bench {

inline std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("model name", 0) != 0) continue;
        size_t colon = line.find(':');
        if (colon != std::string::npos)
            return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
    return "unknown CPU";
}

inline int onlineCpus() {
    cpu_set_t set;
    return sched_getaffinity(0, sizeof(set), &set) == 0 ? CPU_COUNT(&set) : 0;
}

inline std::string commandLine(int argc, char** argv) {
    std::string cmd;
    for (int i = 0; i < argc; ++i) {
        std::string a = argv[i];
        bool quote = a.empty() || a.find_first_of(" \t'\"$") != std::string::npos;
        if (i > 0) cmd += ' ';
        if (quote) cmd += '\'';
        cmd += a;
        if (quote) cmd += '\'';
    }
    return cmd;
}

/// printf-formats one number.
inline std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), format, v);
    return buf;
}

using caustic::secondsSince;  // core/interrupt.h

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The first line of every benchmark's output: the machine and the exact command.
inline void printMachine(int argc, char** argv) {
    std::cout << "Machine: nproc " << onlineCpus() << ", OpenMP threads " << omp_get_max_threads()
              << ", " << cpuModel() << ". Command: `" << commandLine(argc, argv) << "`\n\n";
}

/// Adds --repeats (`help` says what is repeated) and --smoke (`smokeHelp` says what it runs), the
/// options every benchmark has.
inline void addCommonOptions(CLI::App& app, int& repeats, const std::string& help, bool& smoke,
                             const std::string& smokeHelp) {
    cli::addNumber(app, "--repeats", repeats, 1, 1e6, help);
    app.add_flag("--smoke", smoke, smokeHelp + ": checks that the benchmark runs (CTest)");
}

/// Parses a benchmark's command line into `app`'s options and prints the machine line. Returns
/// -1 when the benchmark should run; otherwise the exit code, after printing --help (0) or a usage
/// error (2).
inline int parseBenchmarkArgs(CLI::App& app, int argc, char** argv) {
    int exitCode = cli::parseCommandLine(app, argc, argv);
    if (exitCode < 0) printMachine(argc, argv);
    return exitCode;
}

}  // namespace caustic::bench
