// What a scene made from a model file (a glTF import) holds outside its JSON: meshes already in
// the file's world space and encoded images, which its "embedded" shapes and texture fields name
// by index.
#pragma once

#include <string>
#include <vector>

#include "scene/mesh_counts.h"
#include "scene/mesh_loader.h"

namespace caustic {

struct EmbeddedData {
    struct Mesh {
        std::string name;  ///< "node 4 (Wheel) mesh 1 primitive 0", for messages
        MeshCounts counts;
        TriangleMesh mesh;  ///< Empty when the import only counted (admission).
    };
    struct Image {
        std::string name;   ///< "image 2 (albedo).png": its extension tells the format
        std::string bytes;  ///< encoded: PNG, JPEG, ...
    };
    std::vector<Mesh> meshes;
    std::vector<Image> images;
};

}  // namespace caustic
