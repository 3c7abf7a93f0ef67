// Image textures through OpenImageIO's TextureSystem: each image is read once (a file in the
// assets folder, or bytes embedded in a model), checked, decoded to linear values, and written as
// a tiled, MIP-mapped half-float OpenEXR file (what OIIO's maketx makes) in a folder of prepared
// textures keyed by the image's content. Lookups then page tiles through one bounded cache, which
// every render that shares the store shares: an image larger than the cache is still filtered
// correctly, its tiles read again as they are needed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include <OpenImageIO/oiioversion.h>

#include "core/math.h"

namespace OIIO_NAMESPACE {
class TextureSystem;
}

namespace caustic {

/// How an image's values are read: colour images (base colour, emission) are sRGB-encoded as glTF
/// and PNG/JPEG define them and are decoded to linear; data (metallic-roughness, normals, alpha
/// alone) is read as stored. Floating-point images (EXR, HDR) are linear either way.
enum class TextureEncoding { Srgb, Linear };

/// How a lookup filters: by the footprint, anisotropically over two MIP levels (OIIO's default,
/// after Heckbert's EWA), trilinearly over two levels, or the nearest texel of the full image (no
/// filtering: for comparisons).
enum class TextureFilter { Anisotropic, Trilinear, Nearest };

/// A texture lookup: coordinates and their screen-space derivatives (the footprint).
struct TextureQuery {
    Vec2 st{0.0f};
    Vec2 dstdx{0.0f}, dstdy{0.0f};
};

class TextureStore {
public:
    struct Options {
        /// The bound of the tile cache: what the textures of every render sharing the store may
        /// hold in memory at once.
        size_t cacheBytes = size_t(256) << 20;
        /// Where prepared textures are written; empty: a folder under the system's temporary one.
        std::filesystem::path directory;
        /// The largest image accepted, in pixels.
        int64_t maxPixels = int64_t(16384) * 16384;
    };

    explicit TextureStore(const Options& options);
    ~TextureStore();
    TextureStore(const TextureStore&) = delete;
    TextureStore& operator=(const TextureStore&) = delete;

    /// A prepared image; it lives as long as the store.
    struct Image {
        std::string key;   ///< Content hash and encoding.
        std::string file;  ///< The prepared texture.
        int channels = 0, width = 0, height = 0;
        void* handle = nullptr;  ///< OIIO::TextureSystem::TextureHandle
    };

    /// Prepares an image from its bytes (any format OpenImageIO reads: PNG, JPEG, EXR, HDR, TIFF)
    /// and returns it; the same bytes and encoding give the same image. `name` names the image
    /// in messages. Throws InputError at `path` when the image cannot be read, has no pixels,
    /// more than maxPixels or more than 4 channels, or a texel that is negative or not finite.
    /// Thread-safe.
    const Image& add(std::string_view bytes, TextureEncoding encoding, const std::string& name,
                     const std::string& path);
    /// The same from a file; InputError at `path` when it cannot be read.
    const Image& addFile(const std::filesystem::path& file, TextureEncoding encoding,
                         const std::string& path);

    /// Filtered values of `count` channels from `first` at the query, wrapping periodically (glTF's
    /// default REPEAT), into out[0 .. count). Channels past the image's are 0 (1 for alpha, the
    /// fourth). Thread-safe.
    void lookup(const Image& image, const TextureQuery& q, TextureFilter filter, int first,
                int count, float* out) const;

    /// The cache's bound, in bytes.
    size_t cacheBytes() const { return options_.cacheBytes; }

    /// What the cache has done so far.
    struct Stats {
        int64_t memoryUsed = 0;  ///< Bytes of tiles now held.
        int64_t bytesRead = 0;   ///< Bytes of pixels read from prepared files, all told.
        int tilesCreated = 0;    ///< Tiles read into the cache, all told.
        int tilesPeak = 0;       ///< Most tiles held at once.
    };
    Stats stats() const;

private:
    std::string prepare(std::string_view bytes, TextureEncoding encoding, const std::string& name,
                        const std::string& path, const std::string& key, Image& image) const;

    Options options_;
    std::shared_ptr<OIIO::TextureSystem> system_;
    mutable std::mutex mutex_;
    std::vector<std::unique_ptr<Image>> images_;  // stable addresses
};

}  // namespace caustic
