// glTF materials as Caustic metallic_roughness materials (docs/gltf.md, "Materials"): the core
// model's factors and textures, KHR_materials_emissive_strength, KHR_texture_transform,
// KHR_materials_transmission, KHR_materials_ior and KHR_materials_volume as far as the renderer
// models them; what it cannot is a warning. The images a material uses become "embedded" images,
// each once, their size checked against the pixel limit from their header.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "gltf/gltf_model.h"
#include "gltf/gltf_scene.h"
#include "gltf/gltf_values.h"

namespace caustic {

class GltfMaterials {
public:
    GltfMaterials(const GltfFile& file, EmbeddedData& embedded, const GltfImportOptions& options,
                  const MeshErrors& errors, std::vector<std::string>& warnings);

    /// The scene's name of glTF material `index` (-1: glTF's default material, "default"),
    /// translated into `materials` on first use.
    std::string use(int index);

    Json materials = Json::object();  ///< The scene's "materials".
    Json textures = Json::array();    ///< The images used: index, name, type, width, height, bytes.

private:
    Json translate(const Json& m, const std::string& at);
    /// A texture field from a glTF textureInfo; null when the texture cannot be read (a warning).
    Json textureSlot(const Json& info, const std::string& at, bool normal);
    int embeddedImage(int image, const std::string& at);
    void warn(const std::string& what);

    const GltfFile& file_;
    EmbeddedData& embedded_;
    const GltfImportOptions& options_;
    GltfValues values_;
    std::vector<std::string>& warnings_;
    std::map<int, std::string> names_;   // glTF material -> scene name
    std::map<int, int> embeddedImages_;  // glTF image -> embedded image
};

}  // namespace caustic
