#include "gltf/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "film/image_io.h"
#include "gltf/gltf_nodes.h"

namespace caustic {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kRepeat = 10497;  // glTF sampler wrap modes: REPEAT; 33071 CLAMP_TO_EDGE,
                                // 33648 MIRRORED_REPEAT

double degrees(double radians) {
    return radians * 180.0 / 3.14159265358979323846;
}

// The file extension OpenImageIO picks a reader by, from the image's first bytes: glTF's images
// are PNG and JPEG (WebP through an extension); anything else is refused rather than handed to
// whichever of OpenImageIO's readers a URI's extension names.
const char* extensionOf(std::string_view bytes) {
    if (bytes.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) return ".png";
    if (bytes.substr(0, 3) == std::string_view("\xFF\xD8\xFF", 3)) return ".jpg";
    if (bytes.size() >= 12 && bytes.substr(0, 4) == "RIFF" && bytes.substr(8, 4) == "WEBP")
        return ".webp";
    return nullptr;
}

}  // namespace

GltfMaterials::GltfMaterials(const GltfFile& file, EmbeddedData& embedded,
                             const GltfImportOptions& options, const MeshErrors& errors,
                             std::vector<std::string>& warnings)
    : file_(file), embedded_(embedded), options_(options), values_(errors), warnings_(warnings) {}

void GltfMaterials::warn(const std::string& what) {
    if (std::find(warnings_.begin(), warnings_.end(), what) == warnings_.end())
        warnings_.push_back(what);
}

std::string GltfMaterials::use(int index) {
    if (auto it = names_.find(index); it != names_.end()) return it->second;
    const Json& all = values_.array(file_.doc, "materials", "the file");
    std::string name;
    Json material;
    if (index < 0) {
        // glTF 2.0, "Default Material": metallic-roughness with every property at its default.
        name = "default";
        material = translate(Json::object(), "the default material");
    } else {
        const Json& m = all[size_t(index)];
        if (!m.is_object()) values_.fail("material " + std::to_string(index) + " is not an object");
        const std::string at = gltfObjectName("material", size_t(index), textOf(m, "name"));
        material = translate(m, at);
        name = textOf(m, "name");
        if (name.empty() || name == "default" || materials.contains(name))
            name = "material " + std::to_string(index);
        // "material 3" may be another material's own name: number on until the name is free.
        for (int n = 2; materials.contains(name); ++n)
            name = "material " + std::to_string(index) + " (" + std::to_string(n) + ")";
    }
    materials[name] = std::move(material);
    names_[index] = name;
    return name;
}

Json GltfMaterials::translate(const Json& m, const std::string& at) {
    const Json& pbr = values_.object(m, "pbrMetallicRoughness", at);
    const std::string pbrAt = at + ": pbrMetallicRoughness";
    Json out{{"type", "metallic_roughness"}};
    const std::vector<double> base =
        values_.numbers(pbr, "baseColorFactor", 4, {1, 1, 1, 1}, 0.0, 1.0, pbrAt);
    out["base_color"] = {base[0], base[1], base[2]};
    out["metallic"] = values_.number(pbr, "metallicFactor", 1.0, 0.0, 1.0, pbrAt);
    out["roughness"] = values_.number(pbr, "roughnessFactor", 1.0, 0.0, 1.0, pbrAt);

    bool textured = false;
    auto slot = [&](const Json& owner, const char* key, const char* field, bool normal) {
        const Json& info = values_.object(owner, key, at);
        if (info.empty()) return;
        Json t = textureSlot(info, at + ": " + key, normal);
        if (t.is_null()) return;
        out[field] = std::move(t);
        textured = true;
    };
    slot(pbr, "baseColorTexture", "base_color_texture", false);
    slot(pbr, "metallicRoughnessTexture", "metallic_roughness_texture", false);
    slot(m, "normalTexture", "normal_texture", true);
    slot(m, "emissiveTexture", "emissive_texture", false);

    const Json& extensions = values_.object(m, "extensions", at);
    const Json& strength = values_.object(extensions, "KHR_materials_emissive_strength", at);
    const double emissiveStrength = values_.number(strength, "emissiveStrength", 1.0, 0.0, 1e30,
                                                   at + ": KHR_materials_emissive_strength");
    const std::vector<double> emissive =
        values_.numbers(m, "emissiveFactor", 3, {0, 0, 0}, 0.0, 1.0, at);
    if (emissiveStrength > 0.0 && *std::max_element(emissive.begin(), emissive.end()) > 0.0)
        out["emission"] = {emissive[0] * emissiveStrength, emissive[1] * emissiveStrength,
                           emissive[2] * emissiveStrength};
    else
        out.erase("emissive_texture");  // emits nothing: the texture multiplies zero

    const std::string mode = values_.string(m, "alphaMode", "OPAQUE", at);
    if (mode == "MASK" || mode == "BLEND") {
        out["alpha_mode"] = mode == "MASK" ? "mask" : "blend";
        out["alpha"] = base[3];
        if (mode == "MASK")
            out["alpha_cutoff"] = values_.number(m, "alphaCutoff", 0.5, 0.0, 1.0, at);
    } else if (mode != "OPAQUE") {
        values_.fail(at + ": alphaMode \"" + mode.substr(0, 40) +
                     "\" is none of OPAQUE, MASK, BLEND");
    }

    const Json& transmission = values_.object(extensions, "KHR_materials_transmission", at);
    const double transmitted = values_.number(transmission, "transmissionFactor", 0.0, 0.0, 1.0,
                                              at + ": KHR_materials_transmission");
    if (transmission.contains("transmissionTexture"))
        warn(at + ": KHR_materials_transmission's transmissionTexture is not read (its factor is)");
    const Json& ior = values_.object(extensions, "KHR_materials_ior", at);
    double eta = values_.number(ior, "ior", 1.5, 0.0, kInf, at + ": KHR_materials_ior");
    if (eta != 0.0 && eta < 1.0)
        values_.fail(at + ": KHR_materials_ior: ior is " + std::to_string(eta) +
                     ", not 0 or at least 1");
    if (eta == 0.0 || eta > 10.0) {
        warn(at + ": KHR_materials_ior: ior " + std::to_string(eta) + " is read as 10");
        eta = 10.0;
    }
    if (eta != 1.5) out["ior"] = eta;
    if (transmitted > 0.0) {
        if (textured || out.contains("alpha_mode"))
            warn(at +
                 ": transmission is left out: the renderer does not combine it with "
                 "textures or alpha yet");
        else
            out["transmission"] = transmitted;
    }
    const Json& volume = values_.object(extensions, "KHR_materials_volume", at);
    if (!volume.empty() && volume.contains("attenuationDistance"))
        warn(at + ": KHR_materials_volume's attenuation is not modelled (the volume is clear)");
    return out;
}

Json GltfMaterials::textureSlot(const Json& info, const std::string& at, bool normal) {
    const Json& all = values_.array(file_.doc, "textures", "the file");
    const int index = values_.index(info, "index", all.size(), at);
    if (index < 0) values_.fail(at + ": has no index");
    const Json& texture = all[size_t(index)];
    const std::string textureAt = gltfObjectName("texture", size_t(index), textOf(texture, "name"));
    if (!texture.is_object()) values_.fail(textureAt + " is not an object");
    const Json& images = values_.array(file_.doc, "images", "the file");
    const int source = values_.index(texture, "source", images.size(), textureAt);
    if (source < 0) {
        warn(textureAt +
             ": has no source image the renderer reads (an image of an extension "
             "such as KHR_texture_basisu or EXT_texture_webp); left out");
        return nullptr;
    }
    Json out{{"embedded",
              embeddedImage(source, gltfObjectName("image", size_t(source),
                                                   textOf(images[size_t(source)], "name")))}};
    int texCoord = int(values_.number(info, "texCoord", 0, 0, 16, at));
    const Json& transform =
        values_.object(values_.object(info, "extensions", at), "KHR_texture_transform", at);
    if (!transform.empty()) {
        const std::string tAt = at + ": KHR_texture_transform";
        const std::vector<double> offset =
            values_.numbers(transform, "offset", 2, {0, 0}, -1e30, 1e30, tAt);
        const std::vector<double> scale =
            values_.numbers(transform, "scale", 2, {1, 1}, -1e30, 1e30, tAt);
        const double rotation = values_.number(transform, "rotation", 0.0, -1e30, 1e30, tAt);
        out["transform"] = {{"offset", offset}, {"scale", scale}, {"rotation", degrees(rotation)}};
        texCoord = int(values_.number(transform, "texCoord", texCoord, 0, 16, tAt));
    }
    if (texCoord != 0)
        warn(at + ": TEXCOORD_" + std::to_string(texCoord) +
             " is read as TEXCOORD_0 (one set of texture coordinates is read)");
    const Json& samplers = values_.array(file_.doc, "samplers", "the file");
    if (const int s = values_.index(texture, "sampler", samplers.size(), textureAt); s >= 0) {
        const Json& sampler = samplers[size_t(s)];
        for (const char* wrap : {"wrapS", "wrapT"}) {
            const Json mode =
                sampler.is_object() ? sampler.value(wrap, Json(kRepeat)) : Json(kRepeat);
            if (mode != Json(kRepeat))
                warn(gltfObjectName("sampler", size_t(s), textOf(sampler, "name")) + ": " + wrap +
                     " " + mode.dump().substr(0, 20) + " is read as REPEAT");
        }
    }
    if (normal) out["scale"] = values_.number(info, "scale", 1.0, 0.0, 1e30, at);
    return out;
}

int GltfMaterials::embeddedImage(int image, const std::string& at) {
    if (auto it = embeddedImages_.find(image); it != embeddedImages_.end()) return it->second;
    const Json& json = file_.doc.at("images").at(size_t(image));
    EmbeddedData::Image out;
    out.bytes = std::string(imageBytes(file_.model, image, values_.errors()));
    const char* extension = extensionOf(out.bytes);
    if (!extension) values_.fail(at + ": not a PNG, JPEG or WebP image");
    out.name = at + extension;
    ImageSize size;
    try {
        size = readImageSize(out.bytes, out.name, options_.maxPixels);
    } catch (const std::runtime_error& e) {
        values_.fail(at + ": " + e.what());
    }
    textures.push_back({{"image", image},
                        {"name", textOf(json, "name")},
                        {"mime_type", textOf(json, "mimeType")},
                        {"width", size.width},
                        {"height", size.height},
                        {"bytes", out.bytes.size()}});
    embedded_.images.push_back(std::move(out));
    const int index = int(embedded_.images.size() - 1);
    embeddedImages_[image] = index;
    return index;
}

}  // namespace caustic
