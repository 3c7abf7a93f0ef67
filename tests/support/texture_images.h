// Images for texture tests, written with OpenImageIO: PNG (8-bit, sRGB by convention) and EXR.
#pragma once

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "support/temp_dir.h"

namespace caustic::testing {

/// A scene from JSON text with material `name` set to `material`.
inline nlohmann::json withMaterial(const char* sceneJson, const std::string& name,
                                   const nlohmann::json& material) {
    nlohmann::json doc = nlohmann::json::parse(sceneJson);
    doc["materials"][name] = material;
    return doc;
}

/// Loads a scene whose files (textures, meshes) are in `dir`.
inline std::unique_ptr<Scene> loadWithAssets(const TempDir& dir, const nlohmann::json& doc) {
    SceneOptions options;
    options.assetsDir = dir.path();
    return loadScene(doc, options);
}

/// Writes a width x height image of `channels` channels whose texel (x, y) channel c is
/// value(x, y, c), in the file's own format (PNG: rounded to 8 bits; EXR: float).
inline void writeTextureImage(const std::filesystem::path& file, int width, int height,
                              int channels, const std::function<float(int, int, int)>& value) {
    std::vector<float> pixels(size_t(width) * size_t(height) * size_t(channels));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                pixels[(size_t(y) * size_t(width) + size_t(x)) * size_t(channels) + size_t(c)] =
                    value(x, y, c);
    const bool exr = file.extension() == ".exr";
    OIIO::ImageSpec spec(width, height, channels,
                         exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->open(file.string(), spec)) << OIIO::geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    out->close();
}

/// A checkerboard of `cells` x `cells` squares, black (0) and white (1), in every channel.
inline void writeChecker(const std::filesystem::path& file, int size, int cells) {
    writeTextureImage(file, size, size, 3, [&](int x, int y, int) {
        return float(((x * cells / size) + (y * cells / size)) % 2);
    });
}

}  // namespace caustic::testing
