// What a scene made from a model file (a glTF import) holds outside its JSON: meshes already in
// the file's world space and encoded images, which its "embedded" shapes and texture fields name
// by index.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/json_reader.h"
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

/// The item field "embedded" of `o` names in data's `list` (`kind`: "mesh", "image"): InputError
/// at the field's path when the scene comes from no model file or the index is out of range.
template <typename T>
const T& embeddedItem(JsonObject& o, const std::shared_ptr<const EmbeddedData>& data,
                      std::vector<T> EmbeddedData::*list, const std::string& kind) {
    const std::string at = o.pathOf("embedded");
    if (!data)
        throw InputError(
            at, "names a model file's " + kind + ", and this scene comes from no model file");
    const std::vector<T>& items = (*data).*list;
    const int64_t index = readInteger(o.require("embedded"), at);
    if (index < 0 || size_t(index) >= items.size())
        throw InputError(at, "no " + kind + " " + std::to_string(index) + " in the model (it has " +
                                 std::to_string(items.size()) + ")");
    return items[size_t(index)];
}

}  // namespace caustic
