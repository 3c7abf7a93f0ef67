// The samplers: Sobol's generator matrices, Kensler's permutation, the (0, m, 2)-net property of
// every dimension pair of the padded Owen-scrambled Sobol' sampler (of each pass, and for
// sobol_sequence of every aligned run of passes), uniformity of scrambled points, their variance
// against independent numbers, and that `independent` is each sample's PCG32 stream (core/rng.h).
#include "core/sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace caustic {
namespace {

TEST(Sobol, FirstPointsOfBothDimensions) {
    // van der Corput: 0, 1/2, 1/4, 3/4, 1/8, 5/8, 3/8, 7/8.
    const double dim0[] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
    // Sobol's second dimension by index (not in Gray-code order): 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8,
    // 7/8.
    const double dim1[] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
    for (uint32_t i = 0; i < 8; ++i) {
        EXPECT_EQ(sobolSample(i, 0) * 0x1p-32, dim0[i]) << i;
        EXPECT_EQ(sobolSample(i, 1) * 0x1p-32, dim1[i]) << i;
    }
}

TEST(Sobol, PermutationElementIsAPermutationForEveryLength) {
    for (uint32_t n = 1; n <= 300; ++n) {
        for (uint32_t seed : {0u, 1u, 0xdeadbeefu}) {
            std::vector<bool> seen(n, false);
            for (uint32_t i = 0; i < n; ++i) {
                uint32_t p = permutationElement(i, n, seed);
                ASSERT_LT(p, n);
                ASSERT_FALSE(seen[p]) << "n=" << n << " seed=" << seed;
                seen[p] = true;
            }
        }
    }
}

TEST(Sobol, ScrambledPointsInTheReversedDomainAreTheSameBits) {
    // The sampler's shortcut: the scramble of Sobol's point, without the reversals that cancel.
    for (uint32_t seed : {0u, 7u, 0x9e3779b9u, 0xffffffffu}) {
        for (uint32_t i = 0; i < 4096; ++i) {
            for (uint32_t index : {i, i * 0x9e3779b9u}) {
                ASSERT_EQ(owenScrambledSobol(index, 0, seed),
                          owenScramble(sobolSample(index, 0), seed))
                    << index;
                ASSERT_EQ(owenScrambledSobol(index, 1, seed),
                          owenScramble(sobolSample(index, 1), seed))
                    << index;
            }
        }
    }
}

TEST(Sobol, OwenScrambleIsABijectionOnEachPrefix) {
    // Nested scrambling maps the 2^k intervals of length 2^-k onto each other: the top k bits of
    // the scrambled values of 0 .. 2^k - 1 (shifted up) are all different.
    for (uint32_t seed : {0u, 7u, 0x9e3779b9u}) {
        for (int k = 1; k <= 12; ++k) {
            std::set<uint32_t> tops;
            for (uint32_t v = 0; v < (1u << k); ++v)
                tops.insert(owenScramble(v << (32 - k), seed) >> (32 - k));
            EXPECT_EQ(tops.size(), size_t(1) << k) << "k=" << k << " seed=" << seed;
        }
    }
}

// The samples of `pixel` in pass `pass`, n of them, after `before` samples of the pixel.
std::vector<Sampler> pixelSamples(SamplerKind kind, uint64_t pixel, uint32_t n, uint64_t pass = 0,
                                  uint32_t before = 0) {
    std::vector<Sampler> samples;
    for (uint32_t s = 0; s < n; ++s)
        samples.push_back(Sampler::forSample(kind, 3, pass, pixel, s, n, before));
    return samples;
}

// Every pair of dimensions drawn by uniform2, after any mix of uniform and uniform2 calls, of the
// 2^m `samples` is a (0, m, 2)-net: each elementary box of area 2^-m (2^a by 2^(m-a) cells) holds
// exactly one point; and each dimension drawn by uniform is stratified in 2^m intervals.
void expectNetInEveryDimensionPair(std::vector<Sampler> samples, int m, const std::string& what) {
    ASSERT_EQ(samples.size(), size_t(1) << m);
    for (int draw = 0; draw < 6; ++draw) {
        const bool pair = draw % 3 != 1;
        std::vector<Vec2> points;
        for (Sampler& s : samples) points.push_back(pair ? s.uniform2() : Vec2(s.uniform(), 0.0f));
        for (int a = 0; a <= (pair ? m : 0); ++a) {
            const int b = pair ? m - a : m;
            std::set<uint64_t> boxes;
            for (Vec2 p : points) {
                auto x = uint64_t(std::floor(double(p.x) * double(1u << (pair ? a : m))));
                auto y = pair ? uint64_t(std::floor(double(p.y) * double(1u << b))) : 0;
                boxes.insert(x << 32 | y);
            }
            EXPECT_EQ(boxes.size(), samples.size())
                << what << " m=" << m << " draw=" << draw << " a=" << a;
        }
    }
}

TEST(Sobol, EveryDimensionPairOfAPixelsSamplesIsANet) {
    for (int m = 0; m <= 8; ++m)
        for (uint64_t pixel : {0ull, 12345ull})
            expectNetInEveryDimensionPair(pixelSamples(SamplerKind::Sobol, pixel, 1u << m), m,
                                          "pixel " + std::to_string(pixel));
}

// sobol_sequence: a pixel's passes of 2^m samples each are nets, and so is every aligned run of
// 2^j of them (the first 2^j passes, the next 2^j, ...): the whole render is one net.
TEST(SobolSequence, EachPassAndEveryAlignedRunOfPassesIsANet) {
    const int m = 2, passes = 16;
    const uint32_t n = 1u << m;
    for (uint64_t pixel : {0ull, 777ull}) {
        std::vector<Sampler> all;
        for (uint32_t pass = 0; pass < passes; ++pass) {
            std::vector<Sampler> one =
                pixelSamples(SamplerKind::SobolSequence, pixel, n, pass, pass * n);
            expectNetInEveryDimensionPair(one, m, "pass " + std::to_string(pass));
            all.insert(all.end(), one.begin(), one.end());
        }
        for (int j = 1; (1 << j) <= passes; ++j) {
            const size_t run = size_t(n) << j;
            for (size_t first = 0; first < all.size(); first += run)
                expectNetInEveryDimensionPair(
                    {all.begin() + long(first), all.begin() + long(first + run)}, m + j,
                    "passes from " + std::to_string(first / n));
        }
    }
}

TEST(Sobol, ScrambledPointsAreUniformOverPixels) {
    // One sample's first pair over 2^16 pixels: a chi-square test of 8 x 8 cells (63 degrees of
    // freedom; 120 is exceeded with probability 2e-5), and values in [0, 1).
    const int pixels = 1 << 16, cells = 8;
    std::vector<int> count(cells * cells, 0);
    for (int pixel = 0; pixel < pixels; ++pixel) {
        Vec2 u = Sampler::forSample(SamplerKind::Sobol, 0, 5, uint64_t(pixel), 3, 16, 0).uniform2();
        ASSERT_GE(u.x, 0.0f);
        ASSERT_LT(u.x, 1.0f);
        ASSERT_GE(u.y, 0.0f);
        ASSERT_LT(u.y, 1.0f);
        ++count[int(u.x * cells) * cells + int(u.y * cells)];
    }
    const double expected = double(pixels) / (cells * cells);
    double chi2 = 0;
    for (int c : count) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 120.0);
}

// The mean and the sample variance of `count` estimates.
template <typename Estimate>
std::pair<double, double> meanAndVariance(int count, Estimate estimate) {
    double sum = 0, sumSq = 0;
    for (int i = 0; i < count; ++i) {
        const double e = estimate(i);
        sum += e;
        sumSq += e * e;
    }
    return {sum / count, (sumSq - sum * sum / count) / (count - 1)};
}

// The integrand x y at a sample's second and third dimensions (one before, as the camera's is).
double xyOf(Sampler sampler) {
    sampler.uniform();
    const Vec2 u = sampler.uniform2();
    return double(u.x) * double(u.y);
}

// A pass's estimate of the integral of x y over the unit square (1/4) from 64 samples of one
// pixel: over 2000 independent passes, the mean is 1/4 within 5 standard errors (no bias), and the
// variance is far below independent sampling's (Owen-scrambled nets: O(n^-3) for smooth
// integrands against O(n^-1)).
TEST(Sobol, PassEstimatesAreUnbiasedAndFarLessVariableThanIndependentOnes) {
    const uint32_t n = 64;
    const int passes = 2000;
    auto overPasses = [&](SamplerKind kind) {
        return meanAndVariance(passes, [&](int pass) {
            double estimate = 0;
            for (uint32_t s = 0; s < n; ++s)
                estimate += xyOf(Sampler::forSample(kind, 1, uint64_t(pass), 42, s, n, 0)) / n;
            return estimate;
        });
    };
    const auto [meanSobol, varSobol] = overPasses(SamplerKind::Sobol);
    const auto [meanIndependent, varIndependent] = overPasses(SamplerKind::Independent);
    EXPECT_NEAR(meanSobol, 0.25, 5 * std::sqrt(varSobol / passes));
    EXPECT_NEAR(meanIndependent, 0.25, 5 * std::sqrt(varIndependent / passes));
    // Independent: (1/9 - 1/16) / 64 = 7.6e-4.
    EXPECT_NEAR(varIndependent, (1.0 / 9 - 1.0 / 16) / n, 0.1 * (1.0 / 9 - 1.0 / 16) / n);
    EXPECT_LT(varSobol, varIndependent / 100) << varSobol << " vs " << varIndependent;
}

TEST(Sampler, IndependentIsThePcg32StreamOfEachSample) {
    Sampler s = Sampler::forSample(SamplerKind::Independent, 7, 3, 1000, 2, 16, 0);
    Rng rng = Rng::forSample(7, 3, 1000, 2);
    for (int i = 0; i < 10; ++i) {
        EXPECT_EQ(s.uniform(), rng.uniform());
        Vec2 a = s.uniform2(), b = rng.uniform2();
        EXPECT_EQ(a.x, b.x);
        EXPECT_EQ(a.y, b.y);
    }
}

TEST(Sampler, SobolDependsOnSeedPassAndPixel) {
    auto first = [](uint64_t seed, uint64_t pass, uint64_t pixel) {
        return Sampler::forSample(SamplerKind::Sobol, seed, pass, pixel, 0, 4, 0).uniform2().x;
    };
    const float base = first(1, 2, 3);
    EXPECT_EQ(first(1, 2, 3), base);
    EXPECT_NE(first(2, 2, 3), base);
    EXPECT_NE(first(1, 3, 3), base);
    EXPECT_NE(first(1, 2, 4), base);
}

// The point of sobol_sequence: a pixel's 64 passes of 4 samples together estimate the integral of
// x y (1/4) without bias, and with far less variance than 64 independently scrambled passes
// (sobol), whose 4-point nets only stratify each pass. Pixels are the independent replicates.
TEST(SobolSequence, ItsPassesTogetherBeatIndependentlyScrambledPasses) {
    const uint32_t n = 4, passes = 64;
    const int pixels = 1000;
    auto overPixels = [&](SamplerKind kind) {
        return meanAndVariance(pixels, [&](int pixel) {
            double estimate = 0;
            for (uint32_t pass = 0; pass < passes; ++pass)
                for (uint32_t s = 0; s < n; ++s)
                    estimate +=
                        xyOf(Sampler::forSample(kind, 1, pass, uint64_t(pixel), s, n, pass * n)) /
                        (n * passes);
            return estimate;
        });
    };
    const auto [meanSequence, varSequence] = overPixels(SamplerKind::SobolSequence);
    const auto [meanSobol, varSobol] = overPixels(SamplerKind::Sobol);
    EXPECT_NEAR(meanSequence, 0.25, 5 * std::sqrt(varSequence / pixels));
    EXPECT_NEAR(meanSobol, 0.25, 5 * std::sqrt(varSobol / pixels));
    EXPECT_LT(varSequence, varSobol / 20) << varSequence << " vs " << varSobol;
}

TEST(Sampler, SobolSequenceDependsOnSeedPixelAndIndexButNotOnThePass) {
    auto first = [](uint64_t seed, uint64_t pass, uint64_t pixel, uint32_t before) {
        return Sampler::forSample(SamplerKind::SobolSequence, seed, pass, pixel, 0, 4, before)
            .uniform2()
            .x;
    };
    const float base = first(1, 2, 3, 8);
    EXPECT_EQ(first(1, 5, 3, 8), base);
    EXPECT_NE(first(2, 2, 3, 8), base);
    EXPECT_NE(first(1, 2, 4, 8), base);
    EXPECT_NE(first(1, 2, 3, 12), base);
    // Never the sobol sampler's numbers.
    EXPECT_NE(Sampler::forSample(SamplerKind::Sobol, 1, 2, 3, 0, 4, 8).uniform2().x, base);
}

}  // namespace
}  // namespace caustic
