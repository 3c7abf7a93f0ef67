// Strict reading of one JSON object: every field is read through here so that a wrong type, a
// non-finite number, a value out of range or an unknown field becomes an InputError naming the JSON
// pointer of the value and what was expected.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/math.h"

namespace caustic {

using Json = nlohmann::json;

/// Appends a key or index to a JSON pointer, escaping '~' and '/' (RFC 6901).
std::string jsonPointer(const std::string& parent, const std::string& key);
std::string jsonPointer(const std::string& parent, size_t index);
/// "a number", "an array", ... for messages.
std::string jsonTypeName(const Json& j);

/// The deepest nesting of arrays and objects a scene may have (a scene needs 5:
/// /shapes/0/vertices/0/0). The server refuses request bodies deeper than its own limit (64 levels
/// by default) before they are parsed, so it never meets this one.
inline constexpr int kMaxJsonDepth = 64;
/// Throws InputError at the path of a value nested in more than `maxDepth` arrays and objects
/// (`j` itself, when an array or object, is level 1; `path` is its own path). Walks with a stack
/// of its own, so a document of any depth is refused before anything copies it: nlohmann::json's
/// copy and comparison recurse once per level and overflow the call stack at about 1e5 levels.
void checkJsonDepth(const Json& j, const std::string& path, int maxDepth = kMaxJsonDepth);

/// Parses JSON text of at most `maxDepth` levels of arrays and objects; nullopt when the text is
/// not JSON or nests deeper (found while parsing, before a deep document exists).
std::optional<Json> tryParseJson(const std::string& text, int maxDepth = kMaxJsonDepth);

/// Reads a scalar or vector value at `path`; throws InputError on a wrong type or non-finite value.
float readNumber(const Json& j, const std::string& path);
/// A finite number kept in double (positions, before they are made camera-relative).
double readDouble(const Json& j, const std::string& path);
DVec3 readDVec3(const Json& j, const std::string& path);
int64_t readInteger(const Json& j, const std::string& path);
Vec3 readVec3(const Json& j, const std::string& path);

class JsonObject {
public:
    /// Throws InputError unless j is an object.
    JsonObject(const Json& j, std::string path);

    /// The field, or nullptr when absent. Every key passed here becomes a valid key for finish().
    const Json* find(const std::string& key);
    /// The field; InputError "missing required field" when absent.
    const Json& require(const std::string& key);
    std::string pathOf(const std::string& key) const { return jsonPointer(path_, key); }
    const std::string& path() const { return path_; }

    std::string string(const std::string& key);
    std::string string(const std::string& key, const std::string& fallback);
    /// One of `choices`; InputError listing them otherwise.
    std::string choice(const std::string& key, const std::vector<std::string>& choices,
                       const std::optional<std::string>& fallback = std::nullopt);
    float number(const std::string& key);
    float number(const std::string& key, float fallback);
    /// A number with min < value (exclusive) or min <= value (inclusive).
    float positive(const std::string& key);
    Vec3 vec3(const std::string& key);
    Vec3 vec3(const std::string& key, const Vec3& fallback);
    /// A color: three finite numbers >= 0.
    Color color(const std::string& key);
    Color color(const std::string& key, const Color& fallback);

    bool boolean(const std::string& key, bool fallback);

    /// Throws InputError for the first field no accessor asked for, listing the valid ones.
    void finish() const;

private:
    const Json& j_;
    std::string path_;
    std::vector<std::string> known_;
};

}  // namespace caustic
