// A .glb or a .zip of a .gltf as one mesh (mesh_file_parts.h): read by gltf/gltf_model.h or
// gltf/gltf_zip.h, then the draws of the default scene's nodes joined.
#include <string>
#include <vector>

#include "gltf/gltf_meshes.h"
#include "gltf/gltf_model.h"
#include "gltf/gltf_nodes.h"
#include "gltf/gltf_zip.h"
#include "scene/mesh_file.h"
#include "scene/mesh_file_parts.h"

namespace caustic {
namespace {

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

TriangleMesh parseGltf(std::string_view bytes, MeshFormat format, const MeshTransform& transform,
                       bool texcoords, const MeshErrors& errors) {
    const tinygltf::Model model = loadGltfUpload(bytes, format, errors).model;
    GltfDraws draws = gltfDraws(model, walkNodes(model, errors), errors);
    TriangleMesh mesh;
    for (const GltfDraw& draw : draws.draws)
        append(mesh, readDraw(model, draw, transform, texcoords, errors));
    if (mesh.triangles.empty())
        errors.fail("has no triangles (no node of the scene has a triangle mesh)" +
                    (draws.skipped.empty() ? std::string() : "; " + draws.skipped.front()));
    return mesh;
}

}  // namespace caustic
