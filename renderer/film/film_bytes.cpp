// A film as bytes: a header, the pass ranges, then the accumulators, exactly: a film read back is
// bit-identical to the one written (the same machine type writes and reads them: x86-64,
// little-endian).
//
// Format 3 (written): the exact integers hold far fewer significant bits than their 128- and
// 192-bit slots. A pass value is a float times 2^50 (film/exact_sum.h), so a sum's low bits are
// zero below its smallest addend's last bit, and its high bits are zero above its magnitude. Each
// integer (sums zigzag-encoded, as protobuf's sint) is written as two bytes, its count of trailing
// zero bits and the count of bytes left (0 for zero), and those bytes, least significant first.
// The pairs come first, then the digits, and the whole is compressed with zstd (level 1: the
// pairs repeat, the digits hardly compress), with a checksum of the content. Format 2 (read only:
// checkpoints of earlier versions): the accumulators as they are in memory.
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include "film/film.h"

namespace caustic {
namespace {

constexpr char kMagic[8] = {'C', 'F', 'I', 'L', 'M', '0', '0', '3'};
constexpr char kMagicRaw[8] = {'C', 'F', 'I', 'L', 'M', '0', '0', '2'};
// At most two bytes of shift and length and 24 digit bytes an integer.
constexpr size_t kMaxBytesPerInteger = 2 + 24;

struct Header {
    char magic[8];
    int32_t width, height;
    uint64_t dropped, clamped;
    uint32_t ranges;
    uint32_t flags;  // kBiasLayer; 0 in films written before the bias layer
};

constexpr uint32_t kBiasLayer = 1;  // the film has the bias layer: twice the accumulators

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

// An unsigned integer of up to 192 bits, least significant limb first.
struct Limbs {
    uint64_t w[3] = {0, 0, 0};

    bool zero() const { return (w[0] | w[1] | w[2]) == 0; }
    int trailingZeros() const {
        for (int i = 0; i < 3; ++i)
            if (w[i]) return 64 * i + __builtin_ctzll(w[i]);
        return 192;
    }
    void shiftRight(int n) {
        for (; n >= 64; n -= 64) w[0] = w[1], w[1] = w[2], w[2] = 0;
        if (n == 0) return;
        w[0] = (w[0] >> n) | (w[1] << (64 - n));
        w[1] = (w[1] >> n) | (w[2] << (64 - n));
        w[2] >>= n;
    }
    void shiftLeft(int n) {
        for (; n >= 64; n -= 64) w[2] = w[1], w[1] = w[0], w[0] = 0;
        if (n == 0) return;
        w[2] = (w[2] << n) | (w[1] >> (64 - n));
        w[1] = (w[1] << n) | (w[0] >> (64 - n));
        w[0] <<= n;
    }
};

Limbs zigzag(exact::Int128 v) {
    const exact::UInt128 u = (exact::UInt128(v) << 1) ^ exact::UInt128(v >> 127);
    return Limbs{{uint64_t(u), uint64_t(u >> 64), 0}};
}

exact::Int128 unzigzag(const Limbs& l) {
    const exact::UInt128 u = (exact::UInt128(l.w[1]) << 64) | l.w[0];
    return exact::Int128(u >> 1) ^ -exact::Int128(u & 1);
}

// Appends `v`'s shift and length to `heads` and its significant bytes to `digits`.
void put(std::string& heads, std::string& digits, Limbs v) {
    if (v.zero()) {
        heads.append(2, '\0');
        return;
    }
    const int tz = v.trailingZeros();
    v.shiftRight(tz);
    const int top = v.w[2]   ? 128 + 63 - __builtin_clzll(v.w[2])
                    : v.w[1] ? 64 + 63 - __builtin_clzll(v.w[1])
                             : 63 - __builtin_clzll(v.w[0]);
    const int bytes = top / 8 + 1;
    heads.push_back(char(tz));
    heads.push_back(char(bytes));
    digits.append(reinterpret_cast<const char*>(v.w), size_t(bytes));  // little-endian limbs
}

// Reads the integer of head (`tz`, `bytes`) from `digits` at `at`; false when the digits run out
// or the value does not fit `bits` bits.
bool get(uint8_t tz, uint8_t bytes, std::string_view digits, size_t& at, int bits, Limbs& v) {
    v = Limbs{};
    if (bytes == 0) return true;
    if (bytes > bits / 8 || tz >= bits || digits.size() - at < bytes) return false;
    std::memcpy(v.w, digits.data() + at, bytes);
    at += bytes;
    if (tz == 0) return true;
    // The shifted value must still fit: its top bit below `bits`.
    Limbs back = v;
    v.shiftLeft(tz);
    Limbs check = v;
    check.shiftRight(tz);
    if (check.w[0] != back.w[0] || check.w[1] != back.w[1] || check.w[2] != back.w[2]) return false;
    return bits == 192 || v.w[2] == 0;
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
    h.flags = tracksBias() ? kBiasLayer : 0;
    std::string out;
    append(out, &h, 1);
    for (const PassSet::Range& r : passSet_.ranges()) {
        int32_t pair[2] = {r.first, r.second};
        append(out, pair, 2);
    }
    std::string plain, digits;
    plain.reserve(2 * (sum_.size() + sumSq_.size()));
    digits.reserve(8 * (sum_.size() + sumSq_.size()));
    for (exact::Int128 v : sum_) put(plain, digits, zigzag(v));
    for (const exact::Wide192& v : sumSq_)
        put(plain, digits, Limbs{{v.limb[0], v.limb[1], v.limb[2]}});
    plain += digits;
    const uint64_t plainBytes = plain.size();
    append(out, &plainBytes, 1);
    const size_t at = out.size();
    out.resize(at + ZSTD_compressBound(plain.size()));
    // With a checksum of the content: a damaged film is refused, never merged as another.
    static thread_local std::unique_ptr<ZSTD_CCtx, size_t (*)(ZSTD_CCtx*)> context(
        ZSTD_createCCtx(), ZSTD_freeCCtx);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, 1);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
    const size_t packed =
        ZSTD_compress2(context.get(), out.data() + at, out.size() - at, plain.data(), plain.size());
    if (ZSTD_isError(packed))
        throw std::runtime_error(std::string("compressing a film: ") + ZSTD_getErrorName(packed));
    out.resize(at + packed);
    return out;
}

std::unique_ptr<Film> Film::fromBytes(std::string_view bytes, int width, int height) {
    Header h{};
    size_t at = 0;
    if (!take(bytes, at, &h, 1) || h.width != width || h.height != height ||
        h.ranges > uint32_t(exact::kMaxPasses) || (h.flags & ~kBiasLayer) != 0)
        return nullptr;
    const bool raw = std::memcmp(h.magic, kMagicRaw, sizeof kMagicRaw) == 0;
    if (!raw && std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) return nullptr;
    auto film = std::make_unique<Film>(width, height, (h.flags & kBiasLayer) != 0);
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
    if (raw) {
        if (!take(bytes, at, film->sum_.data(), film->sum_.size()) ||
            !take(bytes, at, film->sumSq_.data(), film->sumSq_.size()) || at != bytes.size())
            return nullptr;
    } else if (!film->readCompact(bytes.substr(at))) {
        return nullptr;
    }
    film->dropped_ = h.dropped;
    film->clamped_ = h.clamped;
    film->updateRelativeError(0);
    return film;
}

std::optional<std::pair<int, int>> Film::sizeOf(std::string_view bytes) {
    Header h{};
    size_t at = 0;
    if (!take(bytes, at, &h, 1) || h.width <= 0 || h.height <= 0 ||
        (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 &&
         std::memcmp(h.magic, kMagicRaw, sizeof kMagicRaw) != 0))
        return std::nullopt;
    return std::pair<int, int>(h.width, h.height);
}

bool Film::readCompact(std::string_view bytes) {
    const size_t count = sum_.size() + sumSq_.size();
    uint64_t plainBytes = 0;
    size_t at = 0;
    if (!take(bytes, at, &plainBytes, 1) || plainBytes < 2 * count ||
        plainBytes > count * kMaxBytesPerInteger ||
        ZSTD_getFrameContentSize(bytes.data() + at, bytes.size() - at) != plainBytes)
        return false;
    std::string plain(plainBytes, '\0');
    const size_t n =
        ZSTD_decompress(plain.data(), plain.size(), bytes.data() + at, bytes.size() - at);
    if (ZSTD_isError(n) || n != plainBytes) return false;
    const auto* heads = reinterpret_cast<const uint8_t*>(plain.data());
    const std::string_view digits = std::string_view(plain).substr(2 * count);
    // Integer i's digits start at the sum of the lengths before it: found per block of integers
    // by one pass over the lengths, then the blocks are read in parallel.
    constexpr size_t kBlock = 1 << 14;
    const size_t blocks = (count + kBlock - 1) / kBlock;
    std::vector<size_t> starts(blocks + 1, 0);
    for (size_t b = 0; b < blocks; ++b) {
        size_t length = 0;
        for (size_t i = b * kBlock; i < std::min(count, (b + 1) * kBlock); ++i)
            length += heads[2 * i + 1];
        starts[b + 1] = starts[b] + length;
    }
    if (starts[blocks] != digits.size()) return false;
    const size_t sums = sum_.size();
    bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok)
    for (size_t b = 0; b < blocks; ++b) {
        size_t next = starts[b];
        Limbs v;
        for (size_t i = b * kBlock; i < std::min(count, (b + 1) * kBlock) && ok; ++i) {
            const uint8_t* head = heads + 2 * i;
            if (!get(head[0], head[1], digits, next, i < sums ? 128 : 192, v)) {
                ok = false;
            } else if (i < sums) {
                sum_[i] = unzigzag(v);
            } else {
                sumSq_[i - sums] = exact::Wide192{{v.w[0], v.w[1], v.w[2]}};
            }
        }
    }
    return ok;
}

}  // namespace caustic
