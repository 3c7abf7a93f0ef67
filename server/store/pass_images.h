// Each pass's image of a task, as a target-error job hands them in (store/task.h): the merge
// replays them in index order. Per pass: int32 index, uint64 dropped samples, then width x height
// RGB floats; native byte order (every node of one farm runs the same build).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/math.h"

namespace caustic::server {

struct PassImage {
    int index = 0;
    uint64_t dropped = 0;
    std::vector<Color> image;
};

inline void appendPassImage(std::string& out, int index, uint64_t dropped,
                            const std::vector<Color>& image) {
    const int32_t i = index;
    out.append(reinterpret_cast<const char*>(&i), sizeof i);
    out.append(reinterpret_cast<const char*>(&dropped), sizeof dropped);
    out.append(reinterpret_cast<const char*>(image.data()), image.size() * sizeof(Color));
}

/// The passes of `bytes`, each of `pixels` pixels; empty when the bytes do not hold whole passes.
inline std::vector<PassImage> readPassImages(const std::string& bytes, size_t pixels) {
    const size_t each = sizeof(int32_t) + sizeof(uint64_t) + pixels * sizeof(Color);
    std::vector<PassImage> passes;
    if (each == 0 || bytes.size() % each != 0) return passes;
    for (size_t at = 0; at < bytes.size(); at += each) {
        PassImage p;
        int32_t i = 0;
        std::memcpy(&i, bytes.data() + at, sizeof i);
        std::memcpy(&p.dropped, bytes.data() + at + sizeof i, sizeof p.dropped);
        p.index = i;
        p.image.resize(pixels);
        std::memcpy(static_cast<void*>(p.image.data()),
                    bytes.data() + at + sizeof i + sizeof p.dropped, pixels * sizeof(Color));
        passes.push_back(std::move(p));
    }
    return passes;
}

}  // namespace caustic::server
