#include "command_line.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <stdexcept>

namespace caustic::cli {

double parseNumber(const std::string& text, double lo, double hi, bool integer) {
    // from_chars, unlike strtod, takes no leading spaces, no hexadecimal and no locale.
    double v = 0;
    const char* end = text.data() + text.size();
    auto [stop, error] = std::from_chars(text.data(), end, v);
    bool ok = error == std::errc() && stop == end && std::isfinite(v) && v >= lo && v <= hi &&
              (!integer || v == std::floor(v));
    if (!ok)
        throw std::invalid_argument(std::string("must be a ") + (integer ? "whole " : "") +
                                    "number in [" + formatNumber(lo) + ", " + formatNumber(hi) +
                                    "], got \"" + text + "\"");
    return v;
}

std::string formatNumber(double v) {
    char text[32];
    if (v == std::floor(v) && std::abs(v) <= 9007199254740992.0)
        std::snprintf(text, sizeof text, "%lld", static_cast<long long>(v));
    else
        std::snprintf(text, sizeof text, "%g", v);
    return text;
}

CLI::Validator numberIn(double lo, double hi, bool integer) {
    auto check = [=](std::string& text) {
        try {
            double v = parseNumber(text, lo, hi, integer);
            char exact[32];
            // 17 significant digits read back as the same double.
            std::snprintf(exact, sizeof exact, "%.17g", v);
            text = integer ? formatNumber(v) : std::string(exact);
            return std::string();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
    };
    // No description: rangeText() is the option's type name instead, which reads better than
    // CLI11's "TYPE:description".
    return CLI::Validator(check, "");
}

std::string rangeText(double lo, double hi, bool integer) {
    return std::string(integer ? "INT" : "NUMBER") + " in [" + formatNumber(lo) + ", " +
           formatNumber(hi) + "]";
}

namespace {

// "caustic render": the program and the subcommands parsed so far, for error messages.
std::string commandName(const CLI::App& app) {
    std::string name = app.get_name();
    for (const CLI::App* sub : app.get_subcommands()) name += " " + commandName(*sub);
    return name;
}

}  // namespace

int parseCommandLine(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
        return -1;
    } catch (const CLI::ParseError& e) {
        // --help and --version arrive as exceptions with exit code 0; App::exit prints them.
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
        const std::string command = commandName(app);
        std::cerr << command << ": " << e.what() << "\n"
                  << "(" << command << " --help lists the options)\n";
        return 2;
    }
}

}  // namespace caustic::cli
