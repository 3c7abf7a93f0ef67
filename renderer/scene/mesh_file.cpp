#include "scene/mesh_file.h"

#include <algorithm>
#include <cctype>
#include <istream>
#include <streambuf>

#include "core/error.h"
#include "scene/mesh_file_parts.h"

namespace caustic {
namespace {

struct FormatRow {
    MeshFormat format;
    const char* name;
    const char* mediaType;
};
// The IANA media types: model/obj (2020), model/gltf-binary (glTF 2.0 spec, appendix) and
// application/zip.
constexpr FormatRow kFormats[] = {
    {.format = MeshFormat::Obj, .name = "obj", .mediaType = "model/obj"},
    {.format = MeshFormat::Glb, .name = "glb", .mediaType = "model/gltf-binary"},
    {.format = MeshFormat::GltfZip, .name = "zip", .mediaType = "application/zip"},
};

const FormatRow& rowOf(MeshFormat format) {
    return *std::find_if(std::begin(kFormats), std::end(kFormats),
                         [&](const FormatRow& row) { return row.format == format; });
}

std::string_view trimmed(std::string_view s) {
    size_t begin = s.find_first_not_of(" \t");
    if (begin == std::string_view::npos) return {};
    return s.substr(begin, s.find_last_not_of(" \t") + 1 - begin);
}

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

// An istream over bytes the caller owns: tinyobjloader reads a stream, and a copy of a large file
// into a std::istringstream would double its memory.
class ViewBuffer : public std::streambuf {
public:
    explicit ViewBuffer(std::string_view bytes) {
        char* begin = const_cast<char*>(bytes.data());  // read only: no put area is set
        setg(begin, begin, begin + bytes.size());
    }
};

}  // namespace

std::optional<MeshFormat> meshFormatOfMediaType(std::string_view mediaType) {
    std::string_view type = trimmed(mediaType.substr(0, mediaType.find(';')));
    for (const FormatRow& row : kFormats)
        if (equalsIgnoringCase(type, row.mediaType)) return row.format;
    return std::nullopt;
}

const char* mediaTypeOf(MeshFormat format) {
    return rowOf(format).mediaType;
}

const char* nameOf(MeshFormat format) {
    return rowOf(format).name;
}

std::optional<MeshFormat> meshFormatNamed(std::string_view name) {
    for (const FormatRow& row : kFormats)
        if (name == row.name) return row.format;
    return std::nullopt;
}

void MeshErrors::fail(const std::string& what) const {
    throw InputError(path, name.empty() ? what : name + ": " + what);
}

void MeshErrors::overLimit(const std::string& what) const {
    throw MeshOverLimit(path, name.empty() ? what : name + ": " + what);
}

TriangleMesh parseMeshBytes(std::string_view bytes, MeshFormat format,
                            const MeshTransform& transform, const std::string& name,
                            const std::string& path, uint64_t maxTriangles, bool texcoords) {
    MeshErrors errors{name, path};
    if (isGltfFormat(format))
        return parseGltf(bytes, format, transform, texcoords, errors, maxTriangles);
    // The line pass names the line at fault; then the loader every scene file goes through.
    checkObjLines(bytes, errors, maxTriangles);
    ViewBuffer buffer(bytes);
    std::istream in(&buffer);
    return parseObj(in, name, transform, path, texcoords);
}

MeshBounds boundsOf(const TriangleMesh& mesh) {
    MeshBounds b{Vec3(kInfinity), Vec3(-kInfinity)};
    for (const Vec3& p : mesh.positions) {
        b.min = glm::min(b.min, p);
        b.max = glm::max(b.max, p);
    }
    return b;
}

}  // namespace caustic
