// The random numbers of one pixel sample. Two kinds, chosen by the `sampler` setting:
// - independent: PCG32 numbers, each sample seeded by hashing (seed, pass, pixel, sample);
// - sobol: randomized quasi-Monte Carlo, padded Owen-scrambled Sobol' points (core/sobol.h).
//   The samples of one pixel in one pass form a stratified set in every pair of dimensions.
//
// Both are functions of (seed, pass, pixel, sample, dimension) alone, so the image is the same for
// any thread count and any split of the passes. Each pass draws its own scrambles, so the passes
// are independent, identically distributed estimates of the image: the pass variance stays a valid
// error estimate with either kind (Owen 1997, "Monte Carlo variance of scrambled net quadrature";
// each scrambled point is uniform, so a pass's mean is unbiased).
#pragma once

#include <cstdint>

#include "core/rng.h"
#include "core/sobol.h"

namespace caustic {

enum class SamplerKind { Independent, Sobol };  // the `sampler` setting's order

class Sampler {
public:
    Sampler() = default;

    /// The numbers of sample `sample` (of `samplesPerPass`) of `pixel` in pass `pass`.
    static Sampler forSample(SamplerKind kind, uint64_t seed, uint64_t pass, uint64_t pixel,
                             uint32_t sample, uint32_t samplesPerPass) {
        Sampler s;
        s.kind_ = kind;
        if (kind == SamplerKind::Independent) {
            s.rng_ = Rng::forSample(seed, pass, pixel, sample);
        } else {
            // Distinct from the independent sampler's keys, so the two never share numbers.
            s.key_ = hashCombine(hashCombine(mixBits(seed ^ kSobolSalt), pass), pixel);
            s.sample_ = sample;
            s.count_ = samplesPerPass;
        }
        return s;
    }

    /// The next dimension: a uniform float in [0, 1).
    float uniform() {
        if (kind_ == SamplerKind::Independent) return rng_.uniform();
        uint64_t h = nextDimensionHash();
        return fractionToFloat(owenScrambledSobol(shuffled(h), 0, uint32_t(h >> 32)));
    }

    /// The next two dimensions, stratified jointly.
    Vec2 uniform2() {
        if (kind_ == SamplerKind::Independent) return rng_.uniform2();
        uint64_t h = nextDimensionHash();
        uint32_t index = shuffled(h);
        uint64_t h2 = mixBits(h);
        return Vec2(fractionToFloat(owenScrambledSobol(index, 0, uint32_t(h2))),
                    fractionToFloat(owenScrambledSobol(index, 1, uint32_t(h2 >> 32))));
    }

private:
    static constexpr uint64_t kSobolSalt = 0x5f0b01c0ffee5eedull;

    uint64_t nextDimensionHash() { return hashCombine(key_, dimension_++); }
    // This sample's place in the dimension's own order of the pass's samples.
    uint32_t shuffled(uint64_t h) const { return permutationElement(sample_, count_, uint32_t(h)); }

    SamplerKind kind_ = SamplerKind::Independent;
    Rng rng_{0};
    uint64_t key_ = 0;
    uint32_t sample_ = 0, count_ = 1, dimension_ = 0;
};

}  // namespace caustic
