#include "gltf/gltf_meshes.h"

#include <glm/mat3x3.hpp>

#include <cmath>
#include <limits>
#include <utility>

#include "gltf/gltf_accessors.h"
#include "gltf/gltf_draco.h"
#include "scene/mesh_file.h"

namespace caustic {
namespace {

constexpr double kFloatMax = std::numeric_limits<float>::max();

const char* modeName(int mode) {
    constexpr const char* kNames[] = {"points",    "lines",          "line loop",   "line strip",
                                      "triangles", "triangle strip", "triangle fan"};
    return mode >= 0 && mode < 7 ? kNames[mode] : "unknown";
}

int modeOf(const tinygltf::Primitive& prim) {
    return prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
}

bool isTriangles(int mode) {
    return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

std::string primitiveName(const tinygltf::Model& m, size_t mesh, size_t p) {
    return gltfObjectName("mesh", mesh, m.meshes[mesh].name) + " primitive " + std::to_string(p);
}

int attribute(const tinygltf::Primitive& prim, const char* name) {
    auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
}

// Triangles from a primitive's vertex sequence (its indices, or 0, 1, 2, ...): glTF 2.0,
// "Meshes": strips take (i, i + 1 + i % 2, i + 2 - i % 2), fans (i + 1, i + 2, 0).
std::vector<glm::uvec3> trianglesOf(const std::vector<uint32_t>& v, int mode) {
    std::vector<glm::uvec3> out;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        for (size_t i = 0; i + 2 < v.size(); i += 3) out.emplace_back(v[i], v[i + 1], v[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < v.size(); ++i)
            out.emplace_back(v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]);
    } else {
        for (size_t i = 0; i + 2 < v.size(); ++i) out.emplace_back(v[i + 1], v[i + 2], v[0]);
    }
    return out;
}

uint64_t triangleCount(uint64_t corners, int mode) {
    if (mode == TINYGLTF_MODE_TRIANGLES) return corners / 3;
    return corners >= 3 ? corners - 2 : 0;
}

// Appends `part` to `mesh`; an attribute one of them lacks is zero there (a zero normal is flat).
void append(TriangleMesh& mesh, TriangleMesh part) {
    const size_t base = mesh.positions.size(), added = part.positions.size();
    auto join = [&](auto& into, auto& from) {
        using V = typename std::decay_t<decltype(into)>::value_type;
        if (into.empty() && from.empty()) return;
        into.resize(base, V(0.0f));
        if (from.empty()) from.resize(added, V(0.0f));
        into.insert(into.end(), from.begin(), from.end());
    };
    join(mesh.normals, part.normals);
    join(mesh.texcoords, part.texcoords);
    mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
    for (const glm::uvec3& t : part.triangles) mesh.triangles.push_back(t + uint32_t(base));
}

}  // namespace

GltfDraws gltfDraws(const tinygltf::Model& m, const std::vector<NodeInstance>& nodes,
                    const MeshErrors& errors, uint64_t maxTriangles) {
    GltfDraws out;
    constexpr size_t kSkippedListed = 8;
    size_t skipped = 0;
    for (const NodeInstance& instance : nodes) {
        const int meshIndex = m.nodes[instance.node].mesh;
        if (meshIndex < 0) continue;
        if (size_t(meshIndex) >= m.meshes.size())
            errors.fail(gltfObjectName("node", instance.node, m.nodes[instance.node].name) +
                        ": mesh " + std::to_string(meshIndex) + " does not exist (" +
                        std::to_string(m.meshes.size()) + " meshes)");
        const tinygltf::Mesh& mesh = m.meshes[size_t(meshIndex)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            const std::string at = primitiveName(m, size_t(meshIndex), p) + ": ";
            const int mode = modeOf(prim);
            if (!isTriangles(mode)) {
                // One line for the first few; then a count (a file may instance thousands).
                if (++skipped <= kSkippedListed)
                    out.skipped.push_back(at + "mode " + std::to_string(mode) + " (" +
                                          modeName(mode) + ") is not drawn; only triangles are");
                continue;
            }
            if (out.draws.size() >= kMaxGlbObjects)
                errors.fail(gltfObjectName("node", instance.node, m.nodes[instance.node].name) +
                            ": the nodes draw more than " + std::to_string(kMaxGlbObjects) +
                            " primitives, the most a glTF file may draw");
            const int position = attribute(prim, "POSITION");
            if (position < 0) errors.fail(at + "has no POSITION attribute");
            GltfDraw draw{instance, size_t(meshIndex), p, prim.material};
            // A Draco primitive's accessors hold counts and types only; its data is decoded later.
            const bool draco = dracoExtension(prim) != nullptr;
            if (draco && mode != TINYGLTF_MODE_TRIANGLES)
                errors.fail(at + "KHR_draco_mesh_compression holds triangles (mode 4), not mode " +
                            std::to_string(mode));
            auto count = [&](int accessor, AccessorUse use) {
                return draco ? checkAccessorType(m, accessor, use, errors)
                             : checkAccessor(m, accessor, use, errors);
            };
            if (prim.material >= 0 && size_t(prim.material) >= m.materials.size())
                errors.fail(at + "material " + std::to_string(prim.material) + " does not exist (" +
                            std::to_string(m.materials.size()) + " materials)");
            draw.vertices = count(position, AccessorUse::Positions);
            if (draco && prim.indices < 0)
                errors.fail(at + "KHR_draco_mesh_compression needs an indices accessor");
            const uint64_t corners =
                prim.indices >= 0 ? count(prim.indices, AccessorUse::Indices) : draw.vertices;
            if (mode == TINYGLTF_MODE_TRIANGLES && corners % 3 != 0)
                errors.fail(prim.indices >= 0
                                ? "accessor " + std::to_string(prim.indices) + ": " +
                                      std::to_string(corners) +
                                      " indices are not whole triangles (a multiple of 3)"
                                : at + std::to_string(corners) +
                                      " unindexed vertices are not whole triangles (a multiple "
                                      "of 3)");
            draw.triangles = triangleCount(corners, mode);
            const int normal = attribute(prim, "NORMAL"), uv = attribute(prim, "TEXCOORD_0");
            for (auto [accessor, use] :
                 {std::pair{normal, AccessorUse::Normals}, std::pair{uv, AccessorUse::Texcoords}}) {
                if (accessor < 0) continue;
                if (count(accessor, use) != draw.vertices)
                    errors.fail(at + "accessor " + std::to_string(accessor) +
                                " has a count other than POSITION's " +
                                std::to_string(draw.vertices));
            }
            draw.normals = normal >= 0;
            draw.texcoords = uv >= 0;
            // Each count is held to the room left before it is added: none can wrap the sum.
            const uint64_t room = kMaxGlbElements - (out.vertices + out.triangles);
            const bool fits = draw.vertices <= room && draw.triangles <= room - draw.vertices;
            out.vertices += fits ? draw.vertices : 0;
            out.triangles += fits ? draw.triangles : 0;
            const std::string node =
                gltfObjectName("node", instance.node, m.nodes[instance.node].name);
            if (!fits)
                errors.fail(node + ": the nodes' meshes make more than " +
                            std::to_string(kMaxGlbElements) +
                            " vertices and triangles together, the most a glTF file may make");
            // The caller's limit, held as the nodes are counted: no instance is built beyond it.
            if (out.triangles > maxTriangles ||
                out.vertices > kMaxVerticesPerTriangle * maxTriangles)
                errors.overLimit(node + ": the nodes' meshes make " +
                                 std::to_string(out.triangles) + " triangles and " +
                                 std::to_string(out.vertices) +
                                 " vertices so far, over the limit of " +
                                 std::to_string(maxTriangles) + " triangles (and " +
                                 std::to_string(kMaxVerticesPerTriangle) + " vertices each)");
            out.draws.push_back(draw);
        }
    }
    if (skipped > kSkippedListed)
        out.skipped.push_back("and " + std::to_string(skipped - kSkippedListed) +
                              " more primitives of points or lines, not drawn");
    return out;
}

TriangleMesh readDraw(const tinygltf::Model& m, const GltfDraw& draw,
                      const MeshTransform& transform, bool texcoords, const MeshErrors& errors) {
    const tinygltf::Primitive& prim = m.meshes[draw.mesh].primitives[draw.primitive];
    const int position = attribute(prim, "POSITION");
    std::vector<Vec3> points, normals;
    std::vector<Vec2> uvs;
    std::vector<uint32_t> sequence;
    if (dracoExtension(prim)) {
        DracoPrimitive d = decodeDraco(m, prim, texcoords && draw.texcoords,
                                       primitiveName(m, draw.mesh, draw.primitive) + ": ", errors);
        points = std::move(d.positions);
        normals = std::move(d.normals);
        uvs = std::move(d.texcoords);
        sequence = std::move(d.indices);
    } else {
        points = readVec3s(m, position, AccessorUse::Positions, errors);
        if (draw.normals)
            normals = readVec3s(m, attribute(prim, "NORMAL"), AccessorUse::Normals, errors);
        if (texcoords && draw.texcoords)
            uvs = readTexcoords(m, attribute(prim, "TEXCOORD_0"), errors);
        if (prim.indices >= 0) {
            sequence = readIndices(m, prim.indices, points.size(), errors);
        } else {
            sequence.resize(points.size());
            for (uint32_t v = 0; v < points.size(); ++v) sequence[v] = v;
        }
    }
    TriangleMesh mesh;
    const glm::dmat4& world = draw.instance.world;
    mesh.positions.reserve(points.size());
    for (size_t v = 0; v < points.size(); ++v) {
        // In double until the point is known to fit a float (a larger double has no float).
        glm::dvec3 q(world * glm::dvec4(glm::dvec3(points[v]), 1.0));
        bool fits =
            std::abs(q.x) <= kFloatMax && std::abs(q.y) <= kFloatMax && std::abs(q.z) <= kFloatMax;
        Vec3 p = fits ? transform.apply(Vec3(q)) : Vec3(kInfinity);
        if (!isFinite(p))
            errors.fail(
                gltfObjectName("node", draw.instance.node, m.nodes[draw.instance.node].name) +
                ": vertex " + std::to_string(v) + " of accessor " + std::to_string(position) +
                " is not finite once transformed");
        mesh.positions.push_back(p);
    }
    if (!normals.empty()) {
        // Normals transform by the inverse transpose; a singular transform flattens them.
        const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(world)));
        mesh.normals = std::move(normals);
        for (Vec3& n : mesh.normals) {
            glm::dvec3 w = normalMatrix * glm::dvec3(n);
            const double length = glm::length(w);
            n = length > 0.0 && std::isfinite(length) ? transform.applyToNormal(Vec3(w / length))
                                                      : Vec3(0.0f);
        }
    }
    mesh.texcoords = std::move(uvs);
    mesh.triangles = trianglesOf(sequence, modeOf(prim));
    // A mirroring transform turns counter-clockwise faces clockwise; swapping two corners keeps
    // the front side where the file meant it (glTF 2.0, "Meshes": a negative determinant of the
    // node's global transform reverses the winding order).
    if (glm::determinant(glm::dmat3(world)) < 0.0)
        for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
    return mesh;
}

TriangleMesh joinedMesh(const tinygltf::Model& model, const MeshTransform& transform,
                        bool texcoords, const MeshErrors& errors, uint64_t maxTriangles) {
    GltfDraws draws = gltfDraws(model, walkNodes(model, errors), errors, maxTriangles);
    TriangleMesh mesh;
    for (const GltfDraw& draw : draws.draws)
        append(mesh, readDraw(model, draw, transform, texcoords, errors));
    if (mesh.triangles.empty())
        errors.fail("has no triangles (no node of the scene has a triangle mesh)" +
                    (draws.skipped.empty() ? std::string() : "; " + draws.skipped.front()));
    return mesh;
}

}  // namespace caustic
