// The strict OBJ line pass (mesh_file_parts.h): what tinyobjloader would let through silently. Its
// number reader turns "nan", "1e39" and "abc" into a value or 0, and its face reader resolves
// indices without a range check; here each such line is an error that names its line.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/mesh_file.h"
#include "scene/mesh_file_parts.h"

namespace caustic {
namespace {

// Control bytes other than tab, CR and LF never occur in OBJ text (UTF-8 names may hold bytes
// above 0x7f, so those are left to the statements that read them).
std::optional<unsigned char> firstBinaryByte(std::string_view line) {
    for (char ch : line) {
        auto c = static_cast<unsigned char>(ch);
        if ((c < 0x20 && c != '\t') || c == 0x7f) return c;
    }
    return std::nullopt;
}

// Fields separated by spaces and tabs, as tinyobjloader splits them.
std::string hex(unsigned char c) {
    const char* digits = "0123456789abcdef";
    return std::string("0x") + digits[c >> 4] + digits[c & 15];
}

std::vector<std::string_view> fieldsOf(std::string_view line) {
    std::vector<std::string_view> fields;
    size_t i = 0;
    while (i < line.size()) {
        i = line.find_first_not_of(" \t", i);
        if (i == std::string_view::npos) break;
        size_t end = std::min(line.find_first_of(" \t", i), line.size());
        fields.push_back(line.substr(i, end - i));
        i = end;
    }
    return fields;
}

std::string quoted(std::string_view field) {
    constexpr size_t kShown = 40;
    std::string q = "\"";
    q.append(field.substr(0, kShown));
    q.append(field.size() > kShown ? "...\"" : "\"");
    return q;
}

// A number as tinyobjloader writes and reads them ("1", "-.5", "+2e3"), whole.
template <typename T>
std::optional<T> parseWhole(std::string_view s, std::from_chars_result* result = nullptr) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
    T value{};
    auto r = std::from_chars(s.data(), s.data() + s.size(), value);
    if (result) *result = r;
    if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
    return value;
}

// "" when the field is a float coordinate, else what is wrong with it.
std::string coordinateError(std::string_view field) {
    std::from_chars_result r;
    std::optional<double> x = parseWhole<double>(field, &r);
    if (!x && r.ec == std::errc::result_out_of_range) return quoted(field) + " is out of range";
    if (!x) return quoted(field) + " is not a number";
    if (!std::isfinite(*x)) return quoted(field) + " is not a finite number";
    if (std::abs(*x) > double(std::numeric_limits<float>::max()))
        return quoted(field) + " is out of the range of a float";
    return "";
}

class ObjLineChecker {
public:
    explicit ObjLineChecker(uint64_t maxTriangles) : maxTriangles_(maxTriangles) {}
    // "" when the line is fine, else what is wrong with it.
    std::string check(std::string_view line) {
        std::vector<std::string_view> f = fieldsOf(line);
        if (f.empty()) return "";
        if (f[0] == "v") return vertex(f);
        if (f[0] == "f") return face(f);
        if (f[0] == "vn") return attribute(normals_, "normals");
        if (f[0] == "vt") return attribute(texcoords_, "texture coordinates");
        return "";
    }
    uint64_t faces() const { return faces_; }
    bool overLimit() const { return triangles_ > maxTriangles_ || overVertices_; }

private:
    std::string vertex(const std::vector<std::string_view>& f) {
        // "v x y z", optionally followed by w or a color, which tinyobjloader reads leniently.
        if (f.size() < 4) return "a vertex needs 3 numbers, got " + std::to_string(f.size() - 1);
        for (size_t i = 1; i <= 3; ++i)
            if (std::string e = coordinateError(f[i]); !e.empty()) return "vertex " + e;
        return attribute(vertices_, "vertices");
    }

    // Counts a "v", "vn" or "vt" line, held to kMaxVerticesPerTriangle a triangle of the limit:
    // tinyobjloader keeps every one, used or not.
    std::string attribute(uint64_t& count, const char* what) {
        if (++count <= kMaxVerticesPerTriangle * maxTriangles_) return "";
        overVertices_ = true;
        return std::to_string(count) + " " + what + ", over the limit of " +
               std::to_string(kMaxVerticesPerTriangle * maxTriangles_) + " (" +
               std::to_string(kMaxVerticesPerTriangle) + " for each of the " +
               std::to_string(maxTriangles_) + " triangles allowed)";
    }

    std::string face(const std::vector<std::string_view>& f) {
        if (f.size() < 4) return "a face needs 3 corners, got " + std::to_string(f.size() - 1);
        if (f.size() - 1 > kMaxObjFaceCorners)
            return "a face of " + std::to_string(f.size() - 1) + " corners; at most " +
                   std::to_string(kMaxObjFaceCorners) + " are read (split the polygon)";
        triangles_ += f.size() - 3;
        if (triangles_ > maxTriangles_)
            return "the faces so far make " + std::to_string(triangles_) +
                   " triangles, over the limit of " + std::to_string(maxTriangles_);
        for (size_t i = 1; i < f.size(); ++i)
            if (std::string e = corner(f[i]); !e.empty()) return e;
        ++faces_;
        return "";
    }

    // "v", "v/vt", "v//vn" or "v/vt/vn" with indices counted from 1, or back from -1.
    std::string corner(std::string_view c) {
        std::vector<std::string_view> parts;
        for (size_t start = 0;;) {
            size_t slash = c.find('/', start);
            parts.push_back(
                c.substr(start, slash == std::string_view::npos ? slash : slash - start));
            if (slash == std::string_view::npos) break;
            start = slash + 1;
        }
        bool shape = parts.size() <= 3 && !parts[0].empty() &&
                     (parts.size() < 2 || !parts[1].empty() || parts.size() == 3) &&
                     (parts.size() < 3 || !parts[2].empty());
        std::optional<int64_t> v = parseWhole<int64_t>(parts[0]);
        for (size_t i = 1; shape && i < parts.size(); ++i)
            shape = parts[i].empty() || parseWhole<int64_t>(parts[i]).value_or(0) != 0;
        if (!shape || !v) return "face corner " + quoted(c) + " is not v, v/vt, v//vn or v/vt/vn";
        if (*v == 0) return "vertex index 0 in a face (OBJ counts vertices from 1)";
        int64_t resolved = *v > 0 ? *v - 1 : int64_t(vertices_) + *v;
        if (resolved < 0 || uint64_t(resolved) >= vertices_)
            return "vertex index " + std::to_string(*v) + " is out of range (" +
                   std::to_string(vertices_) + " vertices above it)";
        return "";
    }

    uint64_t maxTriangles_;
    uint64_t vertices_ = 0, normals_ = 0, texcoords_ = 0;
    bool overVertices_ = false;
    uint64_t faces_ = 0;
    uint64_t triangles_ = 0;
};

}  // namespace

void checkObjLines(std::string_view bytes, const MeshErrors& errors, uint64_t maxTriangles) {
    if (bytes.find_first_not_of(" \t\r\n") == std::string_view::npos)
        errors.fail("the file is empty");
    ObjLineChecker checker(maxTriangles);
    uint64_t number = 0;
    for (size_t start = 0; start < bytes.size();) {
        size_t end = std::min(bytes.find_first_of("\r\n", start), bytes.size());
        std::string_view line = bytes.substr(start, end - start);
        ++number;
        auto fail = [&](const std::string& what) {
            errors.fail("line " + std::to_string(number) + ": " + what);
        };
        if (auto c = firstBinaryByte(line)) fail("binary data (byte " + hex(*c) + ")");
        if (std::string e = checker.check(line); !e.empty() && checker.overLimit())
            errors.overLimit("line " + std::to_string(number) + ": " + e);
        else if (!e.empty())
            // A statement is complete only at its end of line.
            fail(end == bytes.size()
                     ? "the file ends in the middle of a statement (truncated): " + e
                     : e);
        start = end + (bytes.compare(end, 2, "\r\n") == 0 ? 2 : 1);
    }
    if (checker.faces() == 0) errors.fail("has no faces (no triangles)");
}

}  // namespace caustic
