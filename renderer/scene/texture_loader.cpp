#include "scene/texture_loader.h"

#include <cmath>

#include "core/error.h"
#include "core/interrupt.h"
#include "film/image_io.h"
#include "scene/mesh_loader.h"

namespace caustic {

namespace {

const std::vector<std::string> kFilters{"anisotropic", "trilinear", "nearest"};

Vec2 readVec2(JsonObject& o, const std::string& key, Vec2 fallback) {
    const Json* j = o.find(key);
    if (!j) return fallback;
    const std::string at = o.pathOf(key);
    if (!j->is_array() || j->size() != 2) throw InputError(at, "must be an array of 2 numbers");
    return Vec2(float(readDouble((*j)[0], jsonPointer(at, size_t(0)))),
                float(readDouble((*j)[1], jsonPointer(at, size_t(1)))));
}

// KHR_texture_transform: offset, rotation (degrees here, counter-clockwise in the image as the
// extension's radians are), scale; the matrix T R S.
void readTransform(const Json& j, const std::string& path, TextureSlot& slot) {
    JsonObject o(j, path);
    const Vec2 offset = readVec2(o, "offset", Vec2(0.0f));
    const Vec2 scale = readVec2(o, "scale", Vec2(1.0f));
    const float rotation = radians(o.number("rotation", 0.0f));
    o.finish();
    const float c = std::cos(rotation), s = std::sin(rotation);
    // glm is column-major: columns (c, -s) and (s, c) are KHR_texture_transform's rows (c, s)
    // and (-s, c).
    slot.linear = glm::mat2(c, -s, s, c) * glm::mat2(scale.x, 0.0f, 0.0f, scale.y);
    slot.offset = offset;
}

}  // namespace

TextureSlot readTexture(JsonObject& o, const std::string& key, TextureEncoding encoding,
                        const SceneOptions& options, Scene& scene, float* normalScale) {
    TextureSlot slot;
    const Json* j = o.find(key);
    if (!j) return slot;
    const std::string path = o.pathOf(key);
    slot.named = true;
    std::string name, at;
    const EmbeddedData::Image* embedded = nullptr;
    if (j->is_string()) {
        name = o.string(key);
        at = path;
    } else {
        JsonObject t(*j, path);
        if (t.find("embedded")) {
            embedded = &embeddedItem(t, options.embedded, &EmbeddedData::images, "image");
            if (t.find("file"))
                throw InputError(t.pathOf("file"), "a texture has \"file\" or \"embedded\"");
        } else {
            name = t.string("file");
            at = t.pathOf("file");
        }
        const std::string filter = t.choice("filter", kFilters, "anisotropic");
        slot.filter = filter == "anisotropic" ? TextureFilter::Anisotropic
                      : filter == "trilinear" ? TextureFilter::Trilinear
                                              : TextureFilter::Nearest;
        if (const Json* transform = t.find("transform"))
            readTransform(*transform, t.pathOf("transform"), slot);
        if (normalScale) {
            *normalScale = t.number("scale", 1.0f);
            if (!(*normalScale >= 0.0f)) throw InputError(t.pathOf("scale"), "must be >= 0");
        }
        t.finish();
        if (embedded) at = t.pathOf("embedded");
    }
    const std::filesystem::path file =
        embedded ? std::filesystem::path() : resolveAsset(options.assetsDir, name, at);
    if (options.countMeshesOnly) {
        // Admission: the image must open and fit; its texels are checked when a render loads it.
        try {
            if (embedded)
                (void)readImageSize(embedded->bytes, embedded->name, options.maxPixels);
            else
                (void)readImageSize(file, options.maxPixels);
        } catch (const std::runtime_error& e) {
            throw InputError(at, e.what());
        }
        scene.textureBytes =
            options.textures ? options.textures->cacheBytes() : TextureStore::Options{}.cacheBytes;
        return slot;
    }
    const auto start = Interrupt::Clock::now();
    size_t bytes = 0;  // the cache's bound, counted once
    if (!scene.textures) {
        scene.textures = options.textures;
        if (!scene.textures) {
            TextureStore::Options storeOptions;
            storeOptions.maxPixels = options.maxPixels;
            scene.textures = std::make_shared<TextureStore>(storeOptions);
        }
        scene.textureBytes = bytes = scene.textures->cacheBytes();
    }
    slot.image = embedded ? &scene.textures->add(embedded->bytes, encoding, embedded->name, at)
                          : &scene.textures->addFile(file, encoding, at);
    // Per texture: its image prepared (once per content: tiled, MIP-mapped) and opened.
    scene.built.add("texture system", secondsSince(start), bytes);
    return slot;
}

}  // namespace caustic
