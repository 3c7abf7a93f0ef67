#include "scene/mesh_loader.h"

#include <tiny_obj_loader.h>

#include <fstream>
#include <map>
#include <tuple>
#include <utility>

#include "core/error.h"

namespace caustic {

namespace fs = std::filesystem;

namespace {
void addObjVertexAttributes(const tinyobj::attrib_t& attrib,
                            const std::vector<tinyobj::shape_t>& shapes,
                            const MeshTransform& transform, const std::string& name,
                            const std::string& path, TriangleMesh& mesh);
}  // namespace

namespace {

// Rotations about x, then y, then z by r radians (right-handed, counter-clockwise looking down the
// axis).
Vec3 rotateXyz(Vec3 q, const Vec3& r) {
    q = Vec3(q.x, q.y * std::cos(r.x) - q.z * std::sin(r.x),
             q.y * std::sin(r.x) + q.z * std::cos(r.x));
    q = Vec3(q.x * std::cos(r.y) + q.z * std::sin(r.y), q.y,
             -q.x * std::sin(r.y) + q.z * std::cos(r.y));
    q = Vec3(q.x * std::cos(r.z) - q.y * std::sin(r.z), q.x * std::sin(r.z) + q.y * std::cos(r.z),
             q.z);
    return q;
}

}  // namespace

Vec3 MeshTransform::apply(const Vec3& p) const {
    return rotateXyz(p * scale, radians(rotateDegrees)) + translate;
}

Vec3 MeshTransform::applyToNormal(const Vec3& n) const {
    const Vec3 q = rotateXyz(n / scale, radians(rotateDegrees));
    const float length = glm::length(q);
    return length > 0.0f && std::isfinite(length) ? q / length : Vec3(0.0f);
}

fs::path resolveAsset(const fs::path& assetsDir, const std::string& name, const std::string& path) {
    fs::path rel(name);
    if (name.empty()) throw InputError(path, "must name a file in the assets folder");
    // The file system would read the name only up to a NUL byte.
    if (name.find('\0') != std::string::npos)
        throw InputError(path, "a file name must not contain a NUL byte");
    // An empty folder would resolve names against the working directory.
    if (assetsDir.empty()) throw InputError(path, "no assets folder is configured");
    if (rel.is_absolute() || rel.has_root_name() || rel.has_root_directory())
        throw InputError(path, "\"" + name + "\" must be a path relative to the assets folder");
    for (const fs::path& part : rel)
        if (part == "..")
            throw InputError(path, "\"" + name + "\" must not leave the assets folder (\"..\")");
    std::error_code ec;
    fs::path root = fs::weakly_canonical(assetsDir, ec);
    fs::path full = fs::weakly_canonical(assetsDir / rel, ec);
    // A link inside the folder must not lead out of it either.
    auto [rootEnd, fullIt] = std::mismatch(root.begin(), root.end(), full.begin(), full.end());
    if (ec || rootEnd != root.end())
        throw InputError(path, "\"" + name + "\" must not leave the assets folder");
    if (!fs::is_regular_file(full, ec))
        throw InputError(path, "no file \"" + name + "\" in the assets folder");
    return full;
}

TriangleMesh loadObj(const fs::path& file, const MeshTransform& transform, const std::string& path,
                     bool texcoords) {
    std::ifstream in(file, std::ios::binary);
    std::string name = file.filename().string();
    if (!in) throw InputError(path, "cannot read OBJ file " + name + ": cannot open it");
    return parseObj(in, name, transform, path, texcoords);
}

TriangleMesh parseObj(std::istream& in, const std::string& name, const MeshTransform& transform,
                      const std::string& path, bool texcoords) {
    // Without a material reader tinyobjloader skips `mtllib`; its file API would open the named
    // libraries relative to the OBJ's folder, anywhere ("../../../dev/zero"; issue 12, bug 4).
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warning, err;
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &err, &in,
                          /*readMatFn=*/nullptr, /*triangulate=*/true,
                          /*default_vcols_fallback=*/false)) {
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
        throw InputError(path, "cannot read OBJ file " + name + ": " + err);
    }
    TriangleMesh mesh;
    size_t vertexCount = attrib.vertices.size() / 3;
    mesh.positions.reserve(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) {
        Vec3 p(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
        p = transform.apply(p);
        if (!isFinite(p))
            throw InputError(path,
                             "vertex " + std::to_string(i + 1) + " of " + name + " is not finite");
        mesh.positions.push_back(p);
    }
    if (!texcoords) attrib.texcoords.clear();
    const bool perCorner = !attrib.normals.empty() || !attrib.texcoords.empty();
    for (const tinyobj::shape_t& shape : shapes) {
        const std::vector<tinyobj::index_t>& idx = shape.mesh.indices;
        for (size_t f = 0; f + 2 < idx.size(); f += 3) {
            glm::uvec3 t(idx[f].vertex_index, idx[f + 1].vertex_index, idx[f + 2].vertex_index);
            if (t.x >= vertexCount || t.y >= vertexCount || t.z >= vertexCount)
                throw InputError(path, name + " has a face index out of range");
            mesh.triangles.push_back(t);
        }
    }
    if (mesh.triangles.empty()) throw InputError(path, name + " has no faces");
    if (perCorner) addObjVertexAttributes(attrib, shapes, transform, name, path, mesh);
    return mesh;
}

namespace {

void addObjVertexAttributes(const tinyobj::attrib_t& attrib,
                            const std::vector<tinyobj::shape_t>& shapes,
                            const MeshTransform& transform, const std::string& name,
                            const std::string& path, TriangleMesh& mesh) {
    // OBJ indexes positions, normals and texture coordinates apart ("f 1/7/4"); a vertex here is
    // each distinct triple, in order of first use. A corner without a normal gets zero (flat
    // shading there), one without texture coordinates (0, 0).
    const size_t normalCount = attrib.normals.size() / 3;
    const size_t texcoordCount = attrib.texcoords.size() / 2;
    const bool hasNormals = normalCount > 0, hasTexcoords = texcoordCount > 0;
    std::map<std::tuple<int, int, int>, uint32_t> vertexOf;
    std::vector<Vec3> positions;
    std::vector<glm::uvec3> triangles;
    auto vertex = [&](const tinyobj::index_t& i) {
        // Texture coordinates not asked for are not read, nor do they split vertices.
        const int texcoordIndex = hasTexcoords ? i.texcoord_index : -1;
        if ((i.normal_index >= 0 && size_t(i.normal_index) >= normalCount) ||
            (texcoordIndex >= 0 && size_t(texcoordIndex) >= texcoordCount))
            throw InputError(path, name + " has a face index out of range");
        auto [it, added] = vertexOf.try_emplace({i.vertex_index, i.normal_index, texcoordIndex},
                                                uint32_t(positions.size()));
        if (!added) return it->second;
        positions.push_back(mesh.positions[size_t(i.vertex_index)]);
        if (hasNormals) {
            Vec3 n(0.0f);
            if (i.normal_index >= 0) {
                const float* a = &attrib.normals[3 * size_t(i.normal_index)];
                n = transform.applyToNormal(Vec3(a[0], a[1], a[2]));
            }
            if (!isFinite(n)) throw InputError(path, "a normal of " + name + " is not finite");
            mesh.normals.push_back(n);
        }
        if (hasTexcoords) {
            Vec2 st(0.0f);
            if (texcoordIndex >= 0) {
                const float* a = &attrib.texcoords[2 * size_t(texcoordIndex)];
                // OBJ's v runs up the image; glTF's and OpenImageIO's t runs down it.
                st = Vec2(a[0], 1.0f - a[1]);
            }
            if (!std::isfinite(st.x) || !std::isfinite(st.y))
                throw InputError(path, "a texture coordinate of " + name + " is not finite");
            mesh.texcoords.push_back(st);
        }
        return it->second;
    };
    for (const tinyobj::shape_t& shape : shapes) {
        const std::vector<tinyobj::index_t>& idx = shape.mesh.indices;
        for (size_t f = 0; f + 2 < idx.size(); f += 3) {
            // One statement a corner: the order of first use numbers the vertices.
            glm::uvec3 t;
            for (int c = 0; c < 3; ++c) t[c] = vertex(idx[f + size_t(c)]);
            triangles.push_back(t);
        }
    }
    mesh.positions = std::move(positions);
    mesh.triangles = std::move(triangles);
}

}  // namespace

}  // namespace caustic
