// A .glb or a .zip of a .gltf as one mesh (mesh_file_parts.h): read by gltf/gltf_model.h or
// gltf/gltf_zip.h, then the draws of the default scene's nodes joined (gltf/gltf_meshes.h).
#include "gltf/gltf_meshes.h"
#include "gltf/gltf_zip.h"
#include "scene/mesh_file_parts.h"

namespace caustic {

TriangleMesh parseGltf(std::string_view bytes, MeshFormat format, const MeshTransform& transform,
                       bool texcoords, const MeshErrors& errors, uint64_t maxTriangles) {
    return joinedMesh(loadGltfUpload(bytes, format, errors).model, transform, texcoords, errors,
                      maxTriangles);
}

}  // namespace caustic
