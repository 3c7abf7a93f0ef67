// A film as bytes: a header, the pass ranges, then the accumulators as they are in memory (the
// same machine type writes and reads them: x86-64, little-endian). The exact integers travel
// unchanged, so a film read back is bit-identical to the one written.
#include <cstring>

#include "film/film.h"

namespace caustic {
namespace {

constexpr char kMagic[8] = {'C', 'F', 'I', 'L', 'M', '0', '0', '2'};

struct Header {
    char magic[8];
    int32_t width, height;
    uint64_t dropped, clamped;
    uint32_t ranges;
    uint32_t reserved;
};

template <typename T>
void append(std::string& out, const T* data, size_t count) {
    out.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

// Reads `count` values from `in` at `at`, advancing it; false when the bytes run out.
template <typename T>
bool take(std::string_view in, size_t& at, T* data, size_t count) {
    size_t n = count * sizeof(T);
    if (in.size() - at < n) return false;
    std::memcpy(static_cast<void*>(data), in.data() + at, n);
    at += n;
    return true;
}

}  // namespace

std::string Film::toBytes() const {
    Header h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.width = width_;
    h.height = height_;
    h.dropped = dropped_;
    h.clamped = clamped_;
    h.ranges = uint32_t(passSet_.ranges().size());
    std::string out;
    out.reserve(sizeof h + 8 * h.ranges + bytesFor(width_, height_));
    append(out, &h, 1);
    for (const PassSet::Range& r : passSet_.ranges()) {
        int32_t pair[2] = {r.first, r.second};
        append(out, pair, 2);
    }
    append(out, sum_.data(), sum_.size());
    append(out, sumSq_.data(), sumSq_.size());
    return out;
}

std::unique_ptr<Film> Film::fromBytes(std::string_view bytes, int width, int height) {
    Header h{};
    size_t at = 0;
    if (!take(bytes, at, &h, 1) || std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 ||
        h.width != width || h.height != height || h.ranges > uint32_t(exact::kMaxPasses))
        return nullptr;
    auto film = std::make_unique<Film>(width, height);
    // Ranges as this code writes them: sorted, apart, not empty, below kMaxPasses.
    int32_t previousEnd = -1;
    for (uint32_t i = 0; i < h.ranges; ++i) {
        int32_t pair[2];
        if (!take(bytes, at, pair, 2) || pair[0] <= previousEnd || pair[0] >= pair[1] ||
            pair[1] > exact::kMaxPasses)
            return nullptr;
        film->passSet_.insert(pair[0], pair[1]);
        previousEnd = pair[1];
    }
    if (!take(bytes, at, film->sum_.data(), film->sum_.size()) ||
        !take(bytes, at, film->sumSq_.data(), film->sumSq_.size()) || at != bytes.size())
        return nullptr;
    film->dropped_ = h.dropped;
    film->clamped_ = h.clamped;
    film->updateRelativeError(0);
    return film;
}

}  // namespace caustic
