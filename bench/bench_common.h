// Helpers shared by the benchmark programs: argument parsing, the machine line, statistics.
#pragma once

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace caustic::bench {

inline int parsePositive(const std::string& text, const std::string& what) {
    size_t used = 0;
    int v = 0;
    try {
        v = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || v <= 0)
        throw std::invalid_argument(what + ": expected a positive integer, got \"" + text + "\"");
    return v;
}

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

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The first line of every benchmark's output: the machine and the exact command.
inline void printMachine(int argc, char** argv);

/// Calls handle(option, value) for every option in `args`; value() consumes and returns the
/// option's argument, or throws when there is none. Also handles --repeats and --smoke, the
/// options every benchmark has.
template <class Handle>
void forEachOption(const std::vector<std::string>& args, int& repeats, bool& smoke, Handle handle) {
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw std::invalid_argument(a + " needs a value");
            return args[++i];
        };
        if (a == "--repeats")
            repeats = parsePositive(value(), a);
        else if (a == "--smoke")
            smoke = true;
        else if (!handle(a, value))
            throw std::invalid_argument("unknown option \"" + a + "\"");
    }
}

/// The items of a comma-separated list; throws for an empty list.
inline std::vector<std::string> splitList(const std::string& text, const std::string& option) {
    std::vector<std::string> items;
    std::stringstream list(text);
    for (std::string item; std::getline(list, item, ',');) items.push_back(item);
    if (items.empty()) throw std::invalid_argument(option + ": empty list");
    return items;
}

/// Starts a benchmark: parses the arguments with `parse` and prints the machine line. For --help it
/// prints `usage` (exit code 0), after an error the message and `usage` (exit code 2), and then
/// returns nullopt.
template <class Options>
std::optional<Options> startBenchmark(const char* program, const char* usage, int argc, char** argv,
                                      Options (*parse)(const std::vector<std::string>&),
                                      int& exitCode) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (std::find(args.begin(), args.end(), "--help") != args.end()) {
        std::cout << usage;
        exitCode = 0;
        return std::nullopt;
    }
    try {
        Options options = parse(args);
        printMachine(argc, argv);
        return options;
    } catch (const std::exception& e) {
        std::cerr << program << ": " << e.what() << "\n" << usage;
        exitCode = 2;
        return std::nullopt;
    }
}

inline void printMachine(int argc, char** argv) {
    std::cout << "Machine: nproc " << onlineCpus() << ", OpenMP threads " << omp_get_max_threads()
              << ", " << cpuModel() << ". Command: `" << commandLine(argc, argv) << "`\n\n";
}

}  // namespace caustic::bench
