// Owen-scrambled, shuffled Sobol' points in two dimensions: the building block of the padded
// Sobol' sampler (core/sampler.h). Only Sobol's first two dimensions are used; every pair of
// sample dimensions gets its own scramble and its own shuffle of the sample order (Burley 2020,
// "Practical Hash-based Owen Scrambling", JCGT 9(4); pbrt-v4's PaddedSobolSampler), so that each
// pair is a (0, m, 2)-net for 2^m samples and no two pairs are correlated.
#pragma once

#include <cstdint>

namespace caustic {

/// Sobol's first dimension (the van der Corput sequence) or second (generator matrix: Pascal's
/// triangle mod 2), for sample `index`, as a 32-bit fixed-point fraction.
inline uint32_t sobolSample(uint32_t index, int dimension) {
    uint32_t v = 0;
    uint32_t column = 0x80000000u;  // column 0 of both generator matrices
    for (; index != 0; index >>= 1) {
        if (index & 1u) v ^= column;
        // Next column: van der Corput halves it; the second dimension also keeps the previous.
        column = dimension == 0 ? column >> 1 : column ^ (column >> 1);
    }
    return v;
}

inline uint32_t reverseBits(uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
    return (v >> 16) | (v << 16);
}

/// Burley's hash, after Laine and Karras, on a bit-reversed 32-bit fraction: each step changes a
/// bit only from the bits below it (the bits above it, once reversed back).
inline uint32_t laineKarrasPermutation(uint32_t v, uint32_t seed) {
    v += seed;
    v ^= v * 0x6c50b47cu;
    v ^= v * 0xb82f1e52u;
    v ^= v * 0xc7afe638u;
    v ^= v * 0x8d22f6e6u;
    return v;
}

/// Nested uniform (Owen) scrambling of a 32-bit fraction: each bit is flipped by a hash of the
/// bits above it.
inline uint32_t owenScramble(uint32_t v, uint32_t seed) {
    return reverseBits(laineKarrasPermutation(reverseBits(v), seed));
}

/// owenScramble(sobolSample(index, dimension), seed) for dimension 0 or 1, computed in the
/// bit-reversed domain the scramble works in: Sobol's first dimension reversed is the index
/// itself. The second's reversed column k is (1 + x)^k over GF(2), whose bit j is C(k, j) mod 2,
/// which is 1 exactly when j's bits are a subset of k's (Lucas' theorem). So bit j of the point is
/// the XOR of the index bits k that are supersets of j: a superset transform in five shift-and-XOR
/// steps, one per bit of j, in place of a loop over the index's (up to 32, shuffled) bits whose
/// branches cannot be predicted. The same bits, two or three bit reversals fewer.
inline uint32_t owenScrambledSobol(uint32_t index, int dimension, uint32_t seed) {
    uint32_t reversed = index;
    if (dimension == 1) {
        reversed ^= (reversed >> 1) & 0x55555555u;
        reversed ^= (reversed >> 2) & 0x33333333u;
        reversed ^= (reversed >> 4) & 0x0f0f0f0fu;
        reversed ^= (reversed >> 8) & 0x00ff00ffu;
        reversed ^= (reversed >> 16) & 0x0000ffffu;
    }
    return reverseBits(laineKarrasPermutation(reversed, seed));
}

/// Element i of a random permutation of [0, n) chosen by `seed` (Kensler 2013, "Correlated
/// Multi-Jittered Sampling", listing 3): a bijection on the enclosing power of two, walked until
/// it lands below n.
inline uint32_t permutationElement(uint32_t i, uint32_t n, uint32_t seed) {
    uint32_t w = n - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    do {
        i ^= seed;
        i *= 0xe170893du;
        i ^= seed >> 16;
        i ^= (i & w) >> 4;
        i ^= seed >> 8;
        i *= 0x0929eb3fu;
        i ^= seed >> 23;
        i ^= (i & w) >> 1;
        i *= 1u | seed >> 27;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= n);
    // A power of two (the usual samples per pass) needs no division: the same value.
    return (n & (n - 1)) == 0 ? (i + seed) & (n - 1) : (i + seed) % n;
}

/// A 32-bit fraction as a float in [0, 1): its top 24 bits, exact and below 1.
inline float fractionToFloat(uint32_t v) {
    return static_cast<float>(v >> 8) * 0x1p-24f;
}

}  // namespace caustic
