// Deterministic random numbers: PCG32, seeded by hashing (seed, pass, pixel, sample), so that an
// image is the same for any thread count and any split of its passes.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace caustic {

/// Stafford's Mix01 ("Better Bit Mixing", 2011; pbrt-v4's MixBits), a variant of MurmurHash3's
/// 64-bit finaliser with better constants; combines seed components.
inline uint64_t mixBits(uint64_t v) {
    v ^= v >> 31;
    v *= 0x7fb5d329728ea185ull;
    v ^= v >> 27;
    v *= 0x81dadef4bc2dd44dull;
    v ^= v >> 33;
    return v;
}

inline uint64_t hashCombine(uint64_t a, uint64_t b) {
    return mixBits(a ^ (b + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2)));
}

/// PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
/// Algorithms for Random Number Generation"), XSH RR variant. Not thread-safe: one per sample.
class Rng {
public:
    explicit Rng(uint64_t seed, uint64_t stream = 0x853c49e6748fea9bull) {
        inc_ = (stream << 1u) | 1u;
        state_ = 0;
        nextUint();
        state_ += seed;
        nextUint();
    }

    /// A generator for one sample of one pixel in one pass.
    static Rng forSample(uint64_t seed, uint64_t pass, uint64_t pixel, uint64_t sample) {
        uint64_t h = hashCombine(hashCombine(hashCombine(mixBits(seed), pass), pixel), sample);
        return Rng(h, mixBits(h ^ 0xda3e39cb94b95bdbull));
    }

    uint32_t nextUint() {
        uint64_t old = state_;
        state_ = old * 0x5851f42d4c957f2dull + inc_;
        auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        auto rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }

    /// A uniform float in [0, 1).
    float uniform() {
        // 24 random mantissa bits: exact and strictly below 1.
        return static_cast<float>(nextUint() >> 8) * 0x1p-24f;
    }
    Vec2 uniform2() {
        float a = uniform();
        return Vec2(a, uniform());
    }

private:
    uint64_t state_;
    uint64_t inc_;
};

}  // namespace caustic
