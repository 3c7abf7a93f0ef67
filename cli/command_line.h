// What every Caustic command line shares (caustic and the benchmarks, all parsed by CLI11): the one
// number parser, number options whose --help states their range and default, and the exit codes.
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

namespace caustic::cli {

/// Parses `text` as a number written in full (decimal or scientific, no spaces or trailing
/// characters), finite, in [lo, hi] and, when `integer`, whole. Returns it; otherwise throws
/// std::invalid_argument "must be a [whole ]number in [lo, hi], got "text"".
double parseNumber(const std::string& text, double lo, double hi, bool integer);

/// `v` as short text: whole values up to 2^53 without a decimal point (1e6 is "1000000"), others
/// with up to 6 significant digits.
std::string formatNumber(double v);

/// A CLI11 transform that checks a value with parseNumber and rewrites it in plain decimal, so
/// that CLI11's own conversion sees "1000000" for "1e6" (it reads integers with strtoll, base 0:
/// "010" would be 8). Runs on each item of a list option.
CLI::Validator numberIn(double lo, double hi, bool integer);

/// "INT in [lo, hi]" or "NUMBER in [lo, hi]": the type column of --help.
std::string rangeText(double lo, double hi, bool integer);

/// The number type of a number option: T, or the items of a list option.
template <class T>
struct NumberItem {
    using type = T;
};
template <class T>
struct NumberItem<std::vector<T>> {
    using type = T;
};

/// Adds option `name` bound to `value` (a number, or a std::vector of them given as a
/// comma-separated list), each value checked by numberIn; --help shows the range, and the value
/// `value` holds now as the default.
template <class T>
CLI::Option* addNumber(CLI::App& app, const std::string& name, T& value, double lo, double hi,
                       const std::string& help) {
    constexpr bool integer = std::is_integral_v<typename NumberItem<T>::type>;
    CLI::Option* option = app.add_option(name, value, help)
                              ->transform(numberIn(lo, hi, integer))
                              ->type_name(rangeText(lo, hi, integer))
                              ->capture_default_str();
    if constexpr (!std::is_same_v<typename NumberItem<T>::type, T>) option->delimiter(',');
    return option;
}

/// Parses the command line into `app`. Returns -1 when the program should go on; otherwise the
/// exit code, after printing: 0 for --help (the help of the command it follows) or --version, on
/// stdout; 2 for a usage error, on stderr as "caustic render: --spp: ..." and a pointer to --help.
int parseCommandLine(CLI::App& app, int argc, char** argv);

}  // namespace caustic::cli
