// The strict JSON readers: RFC 6901 pointers, type names in messages, number, integer and vec3
// readers, and JsonObject's required, default and unknown fields.
#include "scene/json_reader.h"

#include <cstdint>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"

namespace caustic {
namespace {

// Runs `f`, which must throw InputError; returns it.
template <typename F>
InputError inputError(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e;
    }
    ADD_FAILURE() << "no InputError thrown";
    return InputError("(none)", "(none)");
}

#define EXPECT_INPUT_ERROR(statement, expectedPath, expectedMessage) \
    do {                                                             \
        InputError e_ = inputError([&] { (void)(statement); });      \
        EXPECT_EQ(e_.path(), expectedPath);                          \
        EXPECT_EQ(e_.message(), expectedMessage);                    \
    } while (0)

const double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// --- JSON pointers (RFC 6901, section 3: '~' is written "~0" and '/' is written "~1") ---

TEST(JsonReaderPointer, AppendsKeysAndIndices) {
    EXPECT_EQ(jsonPointer("", "camera"), "/camera");
    EXPECT_EQ(jsonPointer("/camera", "fov"), "/camera/fov");
    EXPECT_EQ(jsonPointer("/shapes", size_t(3)), "/shapes/3");
    EXPECT_EQ(jsonPointer("", size_t(0)), "/0");
    EXPECT_EQ(jsonPointer("/materials", ""), "/materials/");
}

TEST(JsonReaderPointer, EscapesTildeAndSlash) {
    EXPECT_EQ(jsonPointer("", "a/b"), "/a~1b");
    EXPECT_EQ(jsonPointer("", "m~n"), "/m~0n");
    EXPECT_EQ(jsonPointer("", "~/"), "/~0~1");
    EXPECT_EQ(jsonPointer("", "/~"), "/~1~0");
    // "~1" as a key is a tilde and a one, not a slash: the tilde is escaped first.
    EXPECT_EQ(jsonPointer("", "~1"), "/~01");
    EXPECT_EQ(jsonPointer("", "//"), "/~1~1");
    // Other characters, including '.', spaces and non-ASCII, are not escaped.
    EXPECT_EQ(jsonPointer("", "a b.c"), "/a b.c");
    EXPECT_EQ(jsonPointer("", "caf\xc3\xa9"), "/caf\xc3\xa9");
}

TEST(JsonReaderPointer, ResolvesWithAStandardImplementation) {
    Json doc;
    for (std::string key : {"a/b", "m~n", "~1", "~0/~1", "", "plain"})
        doc["outer/~"][key] = {{"leaf", Json::array({key})}};
    for (auto it = doc["outer/~"].begin(); it != doc["outer/~"].end(); ++it) {
        std::string pointer =
            jsonPointer(jsonPointer(jsonPointer("", "outer/~"), it.key()), "leaf");
        pointer = jsonPointer(pointer, size_t(0));
        EXPECT_EQ(doc.at(Json::json_pointer(pointer)), it.key()) << pointer;
    }
}

// --- type names ---

TEST(JsonReaderTypeName, NamesEveryType) {
    EXPECT_EQ(jsonTypeName(Json()), "null");
    EXPECT_EQ(jsonTypeName(Json::object()), "an object");
    EXPECT_EQ(jsonTypeName(Json::array()), "an array");
    EXPECT_EQ(jsonTypeName(Json("x")), "a string");
    EXPECT_EQ(jsonTypeName(Json(true)), "a boolean");
    EXPECT_EQ(jsonTypeName(Json(-3)), "a number");
    EXPECT_EQ(jsonTypeName(Json(3u)), "a number");
    EXPECT_EQ(jsonTypeName(Json(2.5)), "a number");
    EXPECT_EQ(jsonTypeName(Json::binary({1, 2})), "binary data");
}

// --- numbers ---

TEST(JsonReaderNumber, ReadsFiniteNumbers) {
    EXPECT_EQ(readNumber(Json(1), "/x"), 1.0f);
    EXPECT_EQ(readNumber(Json(-7), "/x"), -7.0f);
    EXPECT_EQ(readNumber(Json(2.5), "/x"), 2.5f);
    EXPECT_EQ(readNumber(Json(uint64_t(1) << 40), "/x"), 1099511627776.0f);
    EXPECT_EQ(readNumber(Json(3.0e38), "/x"), 3.0e38f);
    EXPECT_EQ(readNumber(Json(-3.0e38), "/x"), -3.0e38f);
    EXPECT_EQ(readNumber(Json(1e-300), "/x"), 0.0f);
}

TEST(JsonReaderNumber, RejectsOtherTypes) {
    EXPECT_INPUT_ERROR(readNumber(Json("1"), "/a/0"), "/a/0", "expected a number, got a string");
    EXPECT_INPUT_ERROR(readNumber(Json(true), "/a"), "/a", "expected a number, got a boolean");
    EXPECT_INPUT_ERROR(readNumber(Json(), "/a"), "/a", "expected a number, got null");
    EXPECT_INPUT_ERROR(readNumber(Json::array({1}), "/a"), "/a", "expected a number, got an array");
    EXPECT_INPUT_ERROR(readNumber(Json::object(), "/a"), "/a", "expected a number, got an object");
}

TEST(JsonReaderNumber, RejectsNonFiniteAndFloatOverflow) {
    EXPECT_INPUT_ERROR(readNumber(Json(kInf), "/a"), "/a", "must be a finite number");
    EXPECT_INPUT_ERROR(readNumber(Json(-kInf), "/a"), "/a", "must be a finite number");
    EXPECT_INPUT_ERROR(readNumber(Json(kNaN), "/a"), "/a", "must be a finite number");
    EXPECT_INPUT_ERROR(readNumber(Json(1e308), "/a"), "/a",
                       "is out of the range of a float (|x| <= 3e38)");
    EXPECT_INPUT_ERROR(readNumber(Json(-3.5e38), "/a"), "/a",
                       "is out of the range of a float (|x| <= 3e38)");
    // JSON text cannot carry a non-finite number; parseJson rejects 1e400 (scene_loader_test).
}

// --- integers ---

TEST(JsonReaderInteger, ReadsIntegers) {
    EXPECT_EQ(readInteger(Json(42), "/x"), 42);
    EXPECT_EQ(readInteger(Json(-7), "/x"), -7);
    EXPECT_EQ(readInteger(Json(3.0), "/x"), 3);
    EXPECT_EQ(readInteger(Json(-0.0), "/x"), 0);
    EXPECT_EQ(readInteger(Json(1e15), "/x"), 1000000000000000);
    const int64_t limit = int64_t(1) << 53;
    EXPECT_EQ(readInteger(Json(limit), "/x"), limit);
    EXPECT_EQ(readInteger(Json(-limit), "/x"), -limit);
    EXPECT_EQ(readInteger(Json(uint64_t(limit)), "/x"), limit);
    EXPECT_EQ(readInteger(Json(static_cast<double>(limit)), "/x"), limit);
}

TEST(JsonReaderInteger, RejectsFractionsAndOtherTypes) {
    EXPECT_INPUT_ERROR(readInteger(Json(2.5), "/w"), "/w", "expected an integer, got a fraction");
    EXPECT_INPUT_ERROR(readInteger(Json(-0.001), "/w"), "/w",
                       "expected an integer, got a fraction");
    EXPECT_INPUT_ERROR(readInteger(Json("3"), "/w"), "/w", "expected an integer, got a string");
    EXPECT_INPUT_ERROR(readInteger(Json(true), "/w"), "/w", "expected an integer, got a boolean");
    EXPECT_INPUT_ERROR(readInteger(Json(), "/w"), "/w", "expected an integer, got null");
    EXPECT_INPUT_ERROR(readInteger(Json::array(), "/w"), "/w", "expected an integer, got an array");
}

TEST(JsonReaderInteger, RejectsNonFiniteAndOutOfRange) {
    const std::string outOfRange = "is out of the range of an integer (|x| <= 2^53)";
    EXPECT_INPUT_ERROR(readInteger(Json(kInf), "/w"), "/w", "must be a finite number");
    EXPECT_INPUT_ERROR(readInteger(Json(kNaN), "/w"), "/w", "must be a finite number");
    EXPECT_INPUT_ERROR(readInteger(Json(1e20), "/w"), "/w", outOfRange);
    EXPECT_INPUT_ERROR(readInteger(Json(-1e300), "/w"), "/w", outOfRange);
    const int64_t limit = int64_t(1) << 53;
    EXPECT_INPUT_ERROR(readInteger(Json(limit + 1), "/w"), "/w", outOfRange);
    EXPECT_INPUT_ERROR(readInteger(Json(-limit - 1), "/w"), "/w", outOfRange);
    EXPECT_INPUT_ERROR(readInteger(Json(std::numeric_limits<int64_t>::min()), "/w"), "/w",
                       outOfRange);
    // The largest unsigned value must not wrap around to -1.
    EXPECT_INPUT_ERROR(readInteger(Json(std::numeric_limits<uint64_t>::max()), "/w"), "/w",
                       outOfRange);
    EXPECT_INPUT_ERROR(readInteger(Json::parse("18446744073709551615"), "/w"), "/w", outOfRange);
}

// --- vec3 ---

TEST(JsonReaderVec3, ReadsThreeNumbers) {
    EXPECT_EQ(readVec3(Json::array({1, -2.5, 3e10}), "/v"), Vec3(1.0f, -2.5f, 3e10f));
}

TEST(JsonReaderVec3, RejectsWrongShapes) {
    EXPECT_INPUT_ERROR(readVec3(Json::array({1, 2}), "/v"), "/v",
                       "expected an array of 3 numbers, got an array of 2");
    EXPECT_INPUT_ERROR(readVec3(Json::array({1, 2, 3, 4}), "/v"), "/v",
                       "expected an array of 3 numbers, got an array of 4");
    EXPECT_INPUT_ERROR(readVec3(Json::array(), "/v"), "/v",
                       "expected an array of 3 numbers, got an array of 0");
    EXPECT_INPUT_ERROR(readVec3(Json(1), "/v"), "/v",
                       "expected an array of 3 numbers, got a number");
    EXPECT_INPUT_ERROR(readVec3(Json{{"x", 1}, {"y", 2}, {"z", 3}}, "/v"), "/v",
                       "expected an array of 3 numbers, got an object");
}

TEST(JsonReaderVec3, ElementErrorsNameTheIndex) {
    EXPECT_INPUT_ERROR(readVec3(Json::array({0, "1", 0}), "/shapes/0/center"), "/shapes/0/center/1",
                       "expected a number, got a string");
    EXPECT_INPUT_ERROR(readVec3(Json::array({0, 0, kNaN}), "/v"), "/v/2",
                       "must be a finite number");
    EXPECT_INPUT_ERROR(readVec3(Json::array({Json::array({1}), 0, 0}), "/v"), "/v/0",
                       "expected a number, got an array");
}

// --- JsonObject ---

TEST(JsonReaderObject, RejectsNonObjects) {
    EXPECT_INPUT_ERROR(JsonObject(Json::array(), "/camera"), "/camera",
                       "expected an object, got an array");
    EXPECT_INPUT_ERROR(JsonObject(Json(), ""), "", "expected an object, got null");
}

TEST(JsonReaderObject, RequiredAndDefaultFields) {
    Json j{{"name", "x"}, {"n", 2}, {"v", {1, 2, 3}}};
    JsonObject o(j, "/obj");
    EXPECT_EQ(o.string("name"), "x");
    EXPECT_EQ(o.string("other", "fallback"), "fallback");
    EXPECT_EQ(o.number("n"), 2.0f);
    EXPECT_EQ(o.number("m", 7.0f), 7.0f);
    EXPECT_EQ(o.vec3("v"), Vec3(1, 2, 3));
    EXPECT_EQ(o.vec3("w", Vec3(4, 5, 6)), Vec3(4, 5, 6));
    EXPECT_EQ(o.color("c", Color(0.5f)), Color(0.5f));
    EXPECT_EQ(o.find("absent"), nullptr);
    EXPECT_EQ(o.pathOf("a/b"), "/obj/a~1b");
    EXPECT_NO_THROW(o.finish());
    EXPECT_INPUT_ERROR(o.require("missing"), "/obj/missing", "missing required field");
    EXPECT_INPUT_ERROR(o.number("name"), "/obj/name", "expected a number, got a string");
    EXPECT_INPUT_ERROR(o.string("n"), "/obj/n", "expected a string, got a number");
}

TEST(JsonReaderObject, PositiveAndColor) {
    Json j{{"zero", 0}, {"neg", -1}, {"one", 1}, {"c", {0.5, -0.25, 2}}};
    JsonObject o(j, "/m");
    EXPECT_EQ(o.positive("one"), 1.0f);
    EXPECT_INPUT_ERROR(o.positive("zero"), "/m/zero", "must be > 0");
    EXPECT_INPUT_ERROR(o.positive("neg"), "/m/neg", "must be > 0");
    EXPECT_INPUT_ERROR(o.color("c"), "/m/c/1", "must be >= 0");
}

TEST(JsonReaderObject, ChoiceListsValidValues) {
    Json j{{"mode", "fast"}, {"n", 1}};
    JsonObject o(j, "/s");
    EXPECT_INPUT_ERROR(o.choice("mode", {"exact", "schlick"}), "/s/mode",
                       "unknown value \"fast\"; valid: exact, schlick");
    EXPECT_INPUT_ERROR(o.choice("n", {"a"}), "/s/n", "expected a string, got a number");
    EXPECT_EQ(o.choice("absent", {"a", "b"}, "b"), "b");
    EXPECT_INPUT_ERROR(o.choice("absent2", {"a", "b"}), "/s/absent2", "missing required field");
    Json k{{"mode", "schlick"}};
    JsonObject p(k, "/s");
    EXPECT_EQ(p.choice("mode", {"exact", "schlick"}, "exact"), "schlick");
}

TEST(JsonReaderObject, FinishListsTheFieldsAskedFor) {
    Json j{{"type", "sphere"}, {"radius", 1}, {"colour", {1, 0, 0}}};
    JsonObject o(j, "/shapes/4");
    o.string("type");
    o.number("radius");
    o.vec3("center", Vec3(0.0f));  // absent fields asked for are valid too
    EXPECT_INPUT_ERROR(o.finish(), "/shapes/4/colour",
                       "unknown field; valid fields here: center, radius, type");
    Json k{{"a/b", 1}, {"b", 2}};
    JsonObject p(k, "");
    p.number("b");
    EXPECT_INPUT_ERROR(p.finish(), "/a~1b", "unknown field; valid fields here: b");
}

}  // namespace
}  // namespace caustic
