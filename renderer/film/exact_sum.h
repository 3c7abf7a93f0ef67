// Exact, order-independent sums of pass values in fixed point, so that a film merged from pass
// ranges rendered anywhere, in any order, holds the very bits of one process adding every pass.
// (Double addition is not associative: the same passes added in another order give other bits.)
//
// A pass value v (a float) is rounded to a multiple of 2^-50 and clamped below 2^35 in magnitude:
// q = round(v * 2^50), an integer below 2^85. Integer sums are exact and associative:
//   - the sum of q over at most 2^20 passes (spp <= 1e6) fits a signed 128-bit integer;
//   - q^2 is at most 2^170, the sum of squares at most 2^190: three 64-bit limbs.
// Precision: every float of magnitude at least 2^-27 (7.5e-9) is held exactly (its last bit is
// at least 2^-50); smaller values are rounded to 2^-50 (8.9e-16) absolute. Values beyond 2^35
// (3.4e10) in one pass are clamped there, and counted. Memory: 40 bytes a channel, against 16 for
// two doubles.
#pragma once

#include <cstdint>

#if defined(__x86_64__)
#include <emmintrin.h>
#endif

namespace caustic::exact {

__extension__ typedef __int128 Int128;
__extension__ typedef unsigned __int128 UInt128;

constexpr int kFractionBits = 50;
/// Passes a film may hold (spp is at most 1e6): the sums' range above needs at most 2^20.
constexpr int kMaxPasses = 1 << 20;
/// Pass values are clamped to (-kLimit, kLimit).
constexpr float kLimit = 0x1p35f;

/// The sum of squares: an unsigned 192-bit integer in three limbs, least significant first.
struct Wide192 {
    uint64_t limb[3] = {0, 0, 0};

    /// Adds x * 2^shift, 0 <= shift < 64; the total must stay below 2^192 (it does for the
    /// values and pass counts above).
    void add(UInt128 x, int shift) {
        uint64_t w0 = uint64_t(x << shift);
        uint64_t w1 = uint64_t((x << shift) >> 64);
        uint64_t w2 = shift > 0 ? uint64_t(x >> (128 - shift)) : 0;
        UInt128 s = UInt128(limb[0]) + w0;
        limb[0] = uint64_t(s);
        s = UInt128(limb[1]) + w1 + uint64_t(s >> 64);
        limb[1] = uint64_t(s);
        limb[2] += w2 + uint64_t(s >> 64);
    }
    /// Adds x (the common case: a square of a value below 2^13 in magnitude).
    void add(UInt128 x) {
        UInt128 s = UInt128(limb[0]) + uint64_t(x);
        limb[0] = uint64_t(s);
        s = UInt128(limb[1]) + uint64_t(x >> 64) + uint64_t(s >> 64);
        limb[1] = uint64_t(s);
        limb[2] += uint64_t(s >> 64);
    }
    void add(const Wide192& o) {
        UInt128 s = UInt128(limb[0]) + o.limb[0];
        limb[0] = uint64_t(s);
        s = UInt128(limb[1]) + o.limb[1] + uint64_t(s >> 64);
        limb[1] = uint64_t(s);
        limb[2] += o.limb[2] + uint64_t(s >> 64);
    }
    /// The value rounded to double (the same bits for the same limbs).
    double toDouble() const {
        if ((limb[1] | limb[2]) == 0) return double(limb[0]);
        return double(limb[2]) * 0x1p128 + double(limb[1]) * 0x1p64 + double(limb[0]);
    }
    bool operator==(const Wide192&) const = default;
};

/// Whether |v| reaches the limit (the value is clamped) or v is not a number (it counts as 0).
inline bool outOfRange(float v) {
    return !(v > -kLimit && v < kLimit);
}

/// round(v * 2^50) of v clamped into range; NaN gives 0. The result has at most 24 significant
/// bits (those of the float), which addSquare relies on.
inline Int128 quantize(float v) {
    if (v != v) return 0;
    constexpr float kMax = 0x1.fffffep34f;  // the largest float below kLimit
    float c = v < -kMax ? -kMax : (v > kMax ? kMax : v);
    // Exact: a float times a power of two. Only values below 2^-27 have bits under 2^-50.
    double scaled = double(c) * 0x1p50;
    double rounded = __builtin_nearbyint(scaled);
    return Int128(rounded);
}

/// Adds q^2 to `acc`.
inline void addSquare(Wide192& acc, Int128 q) {
    UInt128 m = q < 0 ? UInt128(-q) : UInt128(q);
    if ((m >> 64) == 0) {
        uint64_t m64 = uint64_t(m);
        acc.add(UInt128(m64) * m64, 0);
        return;
    }
    // m < 2^85 has at most 24 significant bits, so its low `s` bits are zero when its top bit is
    // at 63 + s: m = (m >> s) * 2^s exactly, and m^2 = (m >> s)^2 * 2^(2s) with 2s < 64.
    int top = 127 - __builtin_clzll(uint64_t(m >> 64));
    int s = top - 63;
    uint64_t low = uint64_t(m >> s);
    acc.add(UInt128(low) * low, 2 * s);
}

/// Adds pass value v to a channel's sum and sum of squares (as quantize and addSquare do); returns
/// whether v was out of range. Values below 2^13 in magnitude, nearly all, take a fast path whose
/// integers fit 64 bits; both paths give the same bits for the same v.
inline bool accumulate(float v, Int128& sum, Wide192& squares) {
#if defined(__x86_64__)
    if (v > -0x1p13f && v < 0x1p13f) {
        // round(v * 2^50) < 2^63, by cvtsd2si in the default round-to-nearest-even mode (the mode
        // nearbyint uses in quantize); x86-64's SSE2 has it, unlike SSE4.1's roundsd.
        int64_t q = _mm_cvtsd_si64(_mm_set_sd(double(v) * 0x1p50));
        sum += q;
        uint64_t m = q < 0 ? uint64_t(-q) : uint64_t(q);
        squares.add(UInt128(m) * m);
        return false;
    }
#endif
    Int128 q = quantize(v);
    sum += q;
    addSquare(squares, q);
    return outOfRange(v);
}

/// The sum in pass-value units, rounded to double.
inline double sumToDouble(Int128 sum) {
    // The same rounding either way; the 64-bit conversion is one instruction.
    if (sum == Int128(int64_t(sum))) return double(int64_t(sum)) * 0x1p-50;
    return double(sum) * 0x1p-50;
}
/// The sum of squares in squared pass-value units, rounded to double.
inline double squaresToDouble(const Wide192& squares) {
    return squares.toDouble() * 0x1p-100;
}

}  // namespace caustic::exact
