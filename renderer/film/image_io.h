// Image files through OpenImageIO: linear float EXR, and 8-bit PNG with exposure and sRGB encoding.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace caustic {

/// An interleaved RGB float image, row-major, top row first.
struct RgbImage {
    int width = 0, height = 0;
    std::vector<float> pixels;
};

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
float srgbEncode(float linear);

/// The bytes of `image` as a file of `format`, "exr" (linear, 32-bit float) or "png" (scaled by
/// 2^exposure, clamped, sRGB-encoded, 8-bit): for images kept in a database. Equal images give
/// equal bytes. Throws std::runtime_error for another format or when OpenImageIO fails.
std::string encodeImage(const RgbImage& image, const std::string& format, double exposure = 0.0);

/// Writes `image` to `file`, choosing the format by extension: ".exr" (linear, 32-bit float) or
/// ".png" (scaled by 2^exposure, clamped, sRGB-encoded, 8-bit). Writes a temporary file beside it
/// and renames it, so a reader never sees a partial image. Throws std::runtime_error on failure.
void writeImage(const std::filesystem::path& file, const RgbImage& image, double exposure = 0.0);

/// Reads an image's first three channels as float (linear for EXR and HDR; PNG values are decoded
/// as stored, 0..1). With maxPixels > 0, an image of more pixels is refused from its header,
/// before its pixels are read. Throws std::runtime_error on failure.
RgbImage readImage(const std::filesystem::path& file, int64_t maxPixels = 0);

struct ImageSize {
    int width = 0, height = 0;
};
/// An image's size from its header alone, refused as readImage does.
ImageSize readImageSize(const std::filesystem::path& file, int64_t maxPixels = 0);
/// The same from an image's bytes; `name` names it, its extension giving the format.
ImageSize readImageSize(std::string_view bytes, const std::string& name, int64_t maxPixels = 0);

}  // namespace caustic
