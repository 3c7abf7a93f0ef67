#include "scene/json_reader.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace caustic {

std::string jsonPointer(const std::string& parent, const std::string& key) {
    std::string escaped;
    for (char c : key) {
        if (c == '~')
            escaped += "~0";
        else if (c == '/')
            escaped += "~1";
        else
            escaped += c;
    }
    return parent + "/" + escaped;
}

std::string jsonPointer(const std::string& parent, size_t index) {
    return parent + "/" + std::to_string(index);
}

std::string jsonTypeName(const Json& j) {
    switch (j.type()) {
        case Json::value_t::null:
            return "null";
        case Json::value_t::object:
            return "an object";
        case Json::value_t::array:
            return "an array";
        case Json::value_t::string:
            return "a string";
        case Json::value_t::boolean:
            return "a boolean";
        case Json::value_t::binary:
            return "binary data";
        case Json::value_t::discarded:
            return "nothing";
        default:
            return "a number";
    }
}

void checkJsonDepth(const Json& j, const std::string& path, int maxDepth) {
    struct Pending {
        const Json* value;
        std::string path;
        int depth;
    };
    std::vector<Pending> stack;
    // Only arrays and objects go on the stack: scalars cannot nest.
    if (j.is_structured()) stack.push_back({&j, path, 1});
    while (!stack.empty()) {
        Pending p = std::move(stack.back());
        stack.pop_back();
        if (p.depth > maxDepth)
            throw InputError(p.path, "nested deeper than " + std::to_string(maxDepth) +
                                         " levels of arrays and objects");
        if (p.value->is_object()) {
            for (auto it = p.value->begin(); it != p.value->end(); ++it)
                if (it.value().is_structured())
                    stack.push_back({&it.value(), jsonPointer(p.path, it.key()), p.depth + 1});
        } else if (p.value->is_array()) {
            for (size_t i = 0; i < p.value->size(); ++i)
                if ((*p.value)[i].is_structured())
                    stack.push_back({&(*p.value)[i], jsonPointer(p.path, i), p.depth + 1});
        }
    }
}

std::optional<Json> tryParseJson(const std::string& text, int maxDepth) {
    struct TooDeep {};
    try {
        // The callback's depth counts the arrays and objects around an event: an array or object
        // starting at depth d is level d + 1.
        Json doc = Json::parse(
            text,
            [maxDepth](int depth, Json::parse_event_t event, Json&) {
                bool opens = event == Json::parse_event_t::object_start ||
                             event == Json::parse_event_t::array_start;
                if (opens && depth >= maxDepth) throw TooDeep{};
                return true;
            },
            /*allow_exceptions=*/false);
        if (!doc.is_discarded()) return doc;
    } catch (const TooDeep&) {
    }
    return std::nullopt;
}

namespace {

std::string joinNames(std::vector<std::string> names) {
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

}  // namespace

float readNumber(const Json& j, const std::string& path) {
    if (!j.is_number()) throw InputError(path, "expected a number, got " + jsonTypeName(j));
    double v = j.get<double>();
    if (!std::isfinite(v)) throw InputError(path, "must be a finite number");
    if (std::abs(v) > 3.0e38)
        throw InputError(path, "is out of the range of a float (|x| <= 3e38)");
    return static_cast<float>(v);
}

double readDouble(const Json& j, const std::string& path) {
    if (!j.is_number()) throw InputError(path, "expected a number, got " + jsonTypeName(j));
    double v = j.get<double>();
    if (!std::isfinite(v)) throw InputError(path, "must be a finite number");
    return v;
}

// Throws unless j is an array of exactly three elements.
static void requireTriple(const Json& j, const std::string& path) {
    if (!j.is_array() || j.size() != 3)
        throw InputError(
            path, "expected an array of 3 numbers, got " +
                      (j.is_array() ? "an array of " + std::to_string(j.size()) : jsonTypeName(j)));
}

DVec3 readDVec3(const Json& j, const std::string& path) {
    requireTriple(j, path);
    return DVec3(readDouble(j[0], jsonPointer(path, 0)), readDouble(j[1], jsonPointer(path, 1)),
                 readDouble(j[2], jsonPointer(path, 2)));
}

int64_t readInteger(const Json& j, const std::string& path) {
    // Integers up to 2^53 in magnitude: the ones a double (JSON's number) holds exactly.
    constexpr int64_t kLimit = int64_t(1) << 53;
    const char* outOfRange = "is out of the range of an integer (|x| <= 2^53)";
    if (j.is_number_unsigned()) {
        if (j.get<uint64_t>() > uint64_t(kLimit)) throw InputError(path, outOfRange);
        return static_cast<int64_t>(j.get<uint64_t>());
    }
    if (j.is_number_integer()) {
        int64_t v = j.get<int64_t>();
        if (v < -kLimit || v > kLimit) throw InputError(path, outOfRange);
        return v;
    }
    if (j.is_number_float()) {
        double v = j.get<double>();
        if (!std::isfinite(v)) throw InputError(path, "must be a finite number");
        if (v != std::floor(v)) throw InputError(path, "expected an integer, got a fraction");
        if (std::abs(v) > static_cast<double>(kLimit)) throw InputError(path, outOfRange);
        return static_cast<int64_t>(v);
    }
    throw InputError(path, "expected an integer, got " + jsonTypeName(j));
}

Vec3 readVec3(const Json& j, const std::string& path) {
    requireTriple(j, path);
    return Vec3(readNumber(j[0], jsonPointer(path, 0)), readNumber(j[1], jsonPointer(path, 1)),
                readNumber(j[2], jsonPointer(path, 2)));
}

JsonObject::JsonObject(const Json& j, std::string path) : j_(j), path_(std::move(path)) {
    if (!j.is_object()) throw InputError(path_, "expected an object, got " + jsonTypeName(j));
}

const Json* JsonObject::find(const std::string& key) {
    known_.push_back(key);
    auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
}

const Json& JsonObject::require(const std::string& key) {
    const Json* v = find(key);
    if (!v) throw InputError(pathOf(key), "missing required field");
    return *v;
}

std::string JsonObject::string(const std::string& key) {
    const Json& v = require(key);
    if (!v.is_string()) throw InputError(pathOf(key), "expected a string, got " + jsonTypeName(v));
    return v.get<std::string>();
}

std::string JsonObject::string(const std::string& key, const std::string& fallback) {
    return j_.contains(key) ? string(key) : (find(key), fallback);
}

std::string JsonObject::choice(const std::string& key, const std::vector<std::string>& choices,
                               const std::optional<std::string>& fallback) {
    std::string v = fallback && !j_.contains(key) ? (find(key), *fallback) : string(key);
    if (std::find(choices.begin(), choices.end(), v) == choices.end())
        throw InputError(pathOf(key), "unknown value \"" + v + "\"; valid: " + joinNames(choices));
    return v;
}

float JsonObject::number(const std::string& key) {
    return readNumber(require(key), pathOf(key));
}

float JsonObject::number(const std::string& key, float fallback) {
    const Json* v = find(key);
    return v ? readNumber(*v, pathOf(key)) : fallback;
}

float JsonObject::positive(const std::string& key) {
    float v = number(key);
    if (!(v > 0.0f)) throw InputError(pathOf(key), "must be > 0");
    return v;
}

Vec3 JsonObject::vec3(const std::string& key) {
    return readVec3(require(key), pathOf(key));
}

Vec3 JsonObject::vec3(const std::string& key, const Vec3& fallback) {
    const Json* v = find(key);
    return v ? readVec3(*v, pathOf(key)) : fallback;
}

Color JsonObject::color(const std::string& key) {
    Color c = vec3(key);
    for (int i = 0; i < 3; ++i)
        if (c[i] < 0.0f) throw InputError(jsonPointer(pathOf(key), size_t(i)), "must be >= 0");
    return c;
}

Color JsonObject::color(const std::string& key, const Color& fallback) {
    return j_.contains(key) ? color(key) : (find(key), fallback);
}

bool JsonObject::boolean(const std::string& key, bool fallback) {
    const Json* v = find(key);
    if (!v) return fallback;
    if (!v->is_boolean())
        throw InputError(pathOf(key), "expected a boolean, got " + jsonTypeName(*v));
    return v->get<bool>();
}

void JsonObject::finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
        if (std::find(known_.begin(), known_.end(), it.key()) == known_.end())
            throw InputError(pathOf(it.key()),
                             "unknown field; valid fields here: " + joinNames(known_));
    }
}

}  // namespace caustic
