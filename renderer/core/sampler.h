// The random numbers of one pixel sample. Three kinds, chosen by the `sampler` setting:
// - independent: PCG32 numbers, each sample seeded by hashing (seed, pass, pixel, sample);
// - sobol: randomized quasi-Monte Carlo, padded Owen-scrambled Sobol' points (core/sobol.h).
//   The samples of one pixel in one pass form a stratified set in every pair of dimensions.
//   Each pass draws its own scrambles, so the passes are independent, identically distributed
//   estimates of the image: the pass variance stays a valid error estimate (Owen 1997, "Monte
//   Carlo variance of scrambled net quadrature"; each scrambled point is uniform, so a pass's mean
//   is unbiased).
// - sobol_sequence: one scrambled Sobol' sequence per pixel runs through all its passes, as
//   Cycles' Sobol-Burley sampler runs through all of a pixel's samples. The sample order is
//   shuffled by a nested uniform scramble of the index (Burley 2020, section 4), which maps every
//   aligned block of 2^k indices onto an aligned block: each pass of 2^k samples is a net, and so
//   is every run of 2^j such passes, and the error falls faster than 1/sqrt(spp). Each pass's mean
//   stays unbiased, but the passes are no longer independent: they are negatively correlated (they
//   fill each other's gaps), so the error estimated from their variance overestimates the error.
//
// All are functions of (seed, pass, pixel, sample, dimension) alone (the sequence's index is the
// pixel's samples in the passes before, fixed by the settings and the adaptive map), so the image
// is the same for any thread count and any split of the passes.
#pragma once

#include <cstdint>

#include "core/rng.h"
#include "core/sobol.h"

namespace caustic {

enum class SamplerKind { Independent, Sobol, SobolSequence };  // the setting's order

class Sampler {
public:
    Sampler() = default;

    /// The numbers of sample `sample` (of `samplesPerPass`) of `pixel` in pass `pass`;
    /// `samplesBefore`: the pixel's samples in the preceding passes, sobol_sequence's index.
    static Sampler forSample(SamplerKind kind, uint64_t seed, uint64_t pass, uint64_t pixel,
                             uint32_t sample, uint32_t samplesPerPass, uint32_t samplesBefore) {
        Sampler s;
        s.kind_ = kind;
        if (kind == SamplerKind::Independent) {
            s.rng_ = Rng::forSample(seed, pass, pixel, sample);
            s.key_ = hashCombine(hashCombine(hashCombine(mixBits(seed ^ kSplitSalt), pass), pixel),
                                 sample);
        } else if (kind == SamplerKind::Sobol) {
            // Distinct from the independent sampler's keys, so the two never share numbers.
            s.key_ = hashCombine(hashCombine(mixBits(seed ^ kSobolSalt), pass), pixel);
            s.sample_ = sample;
            s.count_ = samplesPerPass;
        } else {
            s.key_ = hashCombine(mixBits(seed ^ kSequenceSalt), pixel);
            s.sample_ = samplesBefore + sample;
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

    /// Point j of k in the pixel's own 2-D set of k points per sample, apart from the sample's
    /// dimensions (the camera rays that look for emission seen directly, render/seen_emission.h).
    /// sobol: the pass's samples' k points together are the first count * k points of a
    /// scrambled Sobol' (0,2)-sequence, a net when that is a power of two; sobol_sequence: the
    /// pixel's one sequence runs on through its passes, as its samples do; independent: PCG32.
    Vec2 pixelPoint(uint32_t j, uint32_t k) const {
        uint64_t h = mixBits(key_ ^ kSplitSalt);
        if (kind_ == SamplerKind::Independent) return Rng(hashCombine(h, j)).uniform2();
        // Unshuffled: the set's points pair with no other dimension.
        uint32_t index = sample_ * k + j;
        return Vec2(fractionToFloat(owenScrambledSobol(index, 0, uint32_t(h))),
                    fractionToFloat(owenScrambledSobol(index, 1, uint32_t(h >> 32))));
    }

private:
    static constexpr uint64_t kSplitSalt = 0x5e1f5ee9e7115ca7ull;
    static constexpr uint64_t kSobolSalt = 0x5f0b01c0ffee5eedull;
    static constexpr uint64_t kSequenceSalt = 0x5e9e7ce5b0b01c0full;

    uint64_t nextDimensionHash() { return hashCombine(key_, dimension_++); }
    // This sample's place in the dimension's own order of the pass's samples (sobol), or of the
    // pixel's sequence (sobol_sequence: aligned blocks stay aligned blocks).
    uint32_t shuffled(uint64_t h) const {
        return kind_ == SamplerKind::Sobol ? permutationElement(sample_, count_, uint32_t(h))
                                           : owenScramble(sample_, uint32_t(h));
    }

    SamplerKind kind_ = SamplerKind::Independent;
    Rng rng_{0};
    uint64_t key_ = 0;
    uint32_t sample_ = 0, count_ = 1, dimension_ = 0;
};

}  // namespace caustic
