// Each pass's image of a task, as a target-error job hands them in (store/task.h): the
// consolidation replays them in index order. A header (magic, width, height and layers as int32:
// 2 when each pass carries its bias, Film's bias layer), then per pass: int32 index, uint64 dropped
// samples, then layers x width x height RGB floats; native byte order (every node of one farm runs
// the same build). Format 002 (no layers, one) is read too.
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"

namespace caustic::server {

struct PassImage {
    int index = 0;
    uint64_t dropped = 0;
    std::vector<Color> image;
};

struct PassImages {
    int width = 0, height = 0;
    int layers = 1;  ///< 2: each pass's image is followed by its bias.
    std::vector<PassImage> passes;
};

inline constexpr char kPassImagesMagic[8] = {'C', 'P', 'A', 'S', 'S', '0', '0', '3'};
inline constexpr char kPassImagesMagicOneLayer[8] = {'C', 'P', 'A', 'S', 'S', '0', '0', '2'};

/// Appends one pass to `out`, which starts with the header when empty; `image` holds width x
/// height pixels, or twice that with its bias.
inline void appendPassImage(std::string& out, int width, int height, int index, uint64_t dropped,
                            const std::vector<Color>& image) {
    if (out.empty()) {
        out.append(kPassImagesMagic, sizeof kPassImagesMagic);
        const int32_t size[3] = {width, height, int32_t(image.size() / (size_t(width) * height))};
        out.append(reinterpret_cast<const char*>(size), sizeof size);
    }
    const int32_t i = index;
    out.append(reinterpret_cast<const char*>(&i), sizeof i);
    out.append(reinterpret_cast<const char*>(&dropped), sizeof dropped);
    out.append(reinterpret_cast<const char*>(image.data()), image.size() * sizeof(Color));
}

/// The passes of `bytes`; nothing when the bytes are not a header and whole passes.
inline std::optional<PassImages> readPassImages(const std::string& bytes) {
    const bool layered = bytes.size() >= sizeof kPassImagesMagic &&
                         std::memcmp(bytes.data(), kPassImagesMagic, sizeof kPassImagesMagic) == 0;
    if (!layered &&
        (bytes.size() < sizeof kPassImagesMagicOneLayer ||
         std::memcmp(bytes.data(), kPassImagesMagicOneLayer, sizeof kPassImagesMagicOneLayer) != 0))
        return std::nullopt;
    const size_t kHeader = sizeof kPassImagesMagic + (layered ? 3 : 2) * sizeof(int32_t);
    if (bytes.size() < kHeader) return std::nullopt;
    int32_t size[3] = {0, 0, 1};
    std::memcpy(size, bytes.data() + sizeof kPassImagesMagic, (layered ? 3 : 2) * sizeof(int32_t));
    if (size[0] <= 0 || size[1] <= 0 || size[2] < 1 || size[2] > 2) return std::nullopt;
    PassImages result{size[0], size[1], size[2], {}};
    const size_t pixels = size_t(size[0]) * size_t(size[1]) * size_t(size[2]);
    const size_t each = sizeof(int32_t) + sizeof(uint64_t) + pixels * sizeof(Color);
    if ((bytes.size() - kHeader) % each != 0) return std::nullopt;
    for (size_t at = kHeader; at < bytes.size(); at += each) {
        PassImage p;
        int32_t i = 0;
        std::memcpy(&i, bytes.data() + at, sizeof i);
        std::memcpy(&p.dropped, bytes.data() + at + sizeof i, sizeof p.dropped);
        p.index = i;
        p.image.resize(pixels);
        std::memcpy(static_cast<void*>(p.image.data()),
                    bytes.data() + at + sizeof i + sizeof p.dropped, pixels * sizeof(Color));
        result.passes.push_back(std::move(p));
    }
    return result;
}

}  // namespace caustic::server
