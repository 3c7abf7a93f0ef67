// Values of a glTF document read with errors that name the glTF object and the property ("material
// 2 (Paint): pbrMetallicRoughness.metallicFactor is 1.5, not in [0, 1]").
#pragma once

#include <string>
#include <vector>

#include "scene/json_reader.h"
#include "scene/mesh_file_parts.h"

namespace caustic {

/// o[key] when o is an object and that is a string; `fallback` otherwise (names, MIME types and
/// URIs are read this way where a wrong type only loses information, never as an error).
inline std::string textOf(const Json& o, const char* key, const std::string& fallback = "") {
    if (!o.is_object()) return fallback;
    auto it = o.find(key);
    return it != o.end() && it->is_string() ? it->get<std::string>() : fallback;
}

/// RFC 3986 percent-decoding, as tinygltf decodes a URI before it asks for the file.
std::string percentDecoded(const std::string& uri);

class GltfValues {
public:
    explicit GltfValues(const MeshErrors& errors) : errors_(errors) {}

    /// o[key] when it is an object; an empty object when absent; fails when it is another type.
    const Json& object(const Json& o, const std::string& key, const std::string& at) const;
    /// o[key] when it is an array; an empty array when absent.
    const Json& array(const Json& o, const std::string& key, const std::string& at) const;
    /// A number in [lo, hi]; `fallback` when absent.
    double number(const Json& o, const std::string& key, double fallback, double lo, double hi,
                  const std::string& at) const;
    /// n numbers, each in [lo, hi]; `fallback` when absent.
    std::vector<double> numbers(const Json& o, const std::string& key, size_t n,
                                std::vector<double> fallback, double lo, double hi,
                                const std::string& at) const;
    /// An index into an array of `count`; -1 when absent.
    int index(const Json& o, const std::string& key, size_t count, const std::string& at) const;
    std::string string(const Json& o, const std::string& key, const std::string& fallback,
                       const std::string& at) const;

    [[noreturn]] void fail(const std::string& what) const { errors_.fail(what); }
    const MeshErrors& errors() const { return errors_; }

private:
    double checked(const Json& v, const std::string& what, double lo, double hi) const;
    const MeshErrors& errors_;
};

}  // namespace caustic
