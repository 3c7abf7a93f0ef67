// The one number parser of every command line (cli/command_line.h) and the CLI11 options built on
// it, parsed in-process.
#include "command_line.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using caustic::cli::addNumber;
using caustic::cli::formatNumber;
using caustic::cli::parseNumber;

TEST(ParseNumber, AcceptsDecimalAndScientificInRange) {
    EXPECT_EQ(parseNumber("42", 0, 100, true), 42);
    EXPECT_EQ(parseNumber("1e6", 1, 1e9, true), 1e6);
    EXPECT_EQ(parseNumber("010", 0, 100, true), 10);  // decimal, never octal
    EXPECT_EQ(parseNumber("-2.5", -20, 20, false), -2.5);
    EXPECT_EQ(parseNumber("0.5", 0.5, 3600, false), 0.5);  // bounds are inclusive
    EXPECT_EQ(parseNumber("3600", 0.5, 3600, false), 3600);
}

// The message parseNumber refuses `text` with; empty if it accepts it.
std::string refusal(const std::string& text, double lo, double hi, bool integer) {
    try {
        parseNumber(text, lo, hi, integer);
        return "";
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
}

TEST(ParseNumber, RefusesWithAClearMessage) {
    for (const char* text :
         {"", " 5", "5 ", "5x", "0x10", "+5", "nan", "inf", "-inf", "1e999", "70000", "-1", "80.5"})
        EXPECT_EQ(refusal(text, 0, 65535, true),
                  "must be a whole number in [0, 65535], got \"" + std::string(text) + "\"");
    EXPECT_EQ(refusal("nan", 0.5, 3600, false), "must be a number in [0.5, 3600], got \"nan\"");
}

TEST(FormatNumber, WholeValuesWithoutExponent) {
    EXPECT_EQ(formatNumber(1e6), "1000000");
    EXPECT_EQ(formatNumber(9007199254740991.0), "9007199254740991");
    EXPECT_EQ(formatNumber(0.5), "0.5");
    EXPECT_EQ(formatNumber(-20), "-20");
}

// Parses `args` (after the program name) into `app`; CLI11 throws for a bad value.
void parse(CLI::App& app, std::vector<std::string> args) {
    std::vector<char*> argv{const_cast<char*>("test")};
    for (std::string& a : args) argv.push_back(a.data());
    app.parse(int(argv.size()), argv.data());
}

TEST(AddNumber, ConvertsThroughTheParserAndStatesTheRange) {
    CLI::App app;
    int64_t photons = 10;
    double seconds = 10;
    std::vector<int> sizes = {500, 1000};
    addNumber(app, "--photons", photons, 1, 1e9, "photon paths");
    addNumber(app, "--seconds", seconds, 0.5, 3600, "a lease");
    addNumber(app, "--sizes", sizes, 1, 16384, "resolutions");
    const std::string help = app.help();
    EXPECT_NE(help.find("--photons INT in [1, 1000000000]=10"), std::string::npos) << help;
    EXPECT_NE(help.find("--seconds NUMBER in [0.5, 3600]=10"), std::string::npos) << help;

    parse(app, {"--photons", "1e6", "--seconds", "0.75", "--sizes", "64,128"});
    EXPECT_EQ(photons, 1000000);
    EXPECT_EQ(seconds, 0.75);
    EXPECT_EQ(sizes, (std::vector<int>{64, 128}));
}

TEST(AddNumber, BadValueIsAValidationErrorNamingTheOption) {
    CLI::App app;
    int port = 8080;
    std::vector<int> sizes;
    addNumber(app, "--port", port, 0, 65535, "port");
    addNumber(app, "--sizes", sizes, 1, 16384, "resolutions");
    try {
        parse(app, {"--port", "0x50"});
        FAIL() << "0x50 was accepted";
    } catch (const CLI::ValidationError& e) {
        EXPECT_STREQ(e.what(), "--port: must be a whole number in [0, 65535], got \"0x50\"");
    }
    EXPECT_THROW(parse(app, {"--sizes", "64,0"}), CLI::ValidationError);
}

}  // namespace
