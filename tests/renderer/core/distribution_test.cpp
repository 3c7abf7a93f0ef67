// The piecewise-constant densities: what they sample is what their pdf says.
#include "core/distribution.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/rng.h"

namespace caustic {
namespace {

TEST(Distribution1D, SamplesEachIntervalInProportionToItsValue) {
    const std::vector<float> values{0.0f, 1.0f, 3.0f, 0.0f, 4.0f};
    Distribution1D d(values);
    EXPECT_DOUBLE_EQ(d.integral(), 8.0 / 5.0);
    std::vector<int> counts(values.size(), 0);
    Rng rng = Rng::forSample(1, 0, 0, 0);
    const int n = 800000;
    for (int i = 0; i < n; ++i) {
        float pdf = 0.0f;
        size_t index = 0;
        const float x = d.sample(rng.uniform(), pdf, index);
        ASSERT_GE(x, 0.0f);
        ASSERT_LT(x, 1.0f);
        ASSERT_EQ(index, size_t(x * 5.0f));
        ASSERT_FLOAT_EQ(pdf, d.pdf(x));
        ++counts[index];
    }
    for (size_t i = 0; i < values.size(); ++i) {
        const double p = values[i] / 8.0;
        // Five standard deviations of a binomial count.
        EXPECT_NEAR(counts[i], n * p, 5.0 * std::sqrt(n * p * (1 - p)) + 1e-9) << "interval " << i;
    }
    // Density: value / integral.
    EXPECT_FLOAT_EQ(d.pdf(0.5f), 3.0f / 1.6f);
    EXPECT_EQ(d.pdf(0.1f), 0.0f);
}

TEST(Distribution1D, AllZeroValuesSampleUniformly) {
    Distribution1D d(std::vector<float>(4, 0.0f));
    float pdf = 0.0f;
    size_t index = 0;
    EXPECT_FLOAT_EQ(d.sample(0.6f, pdf, index), 0.6f);
    EXPECT_EQ(index, 2u);
    EXPECT_FLOAT_EQ(pdf, 1.0f);
}

// The centre of cell (x, y) of a w x h grid on [0,1)^2.
Vec2 cellCentre(int x, int y, int w, int h) {
    return Vec2((float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h));
}

TEST(Distribution2D, DensityIntegratesToOneAndMatchesSampling) {
    const int w = 6, h = 4;
    std::vector<float> values(w * h);
    for (int i = 0; i < w * h; ++i) values[size_t(i)] = float((i * 7) % 5);
    Distribution2D d(values, w, h);
    double integral = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) integral += d.pdf(cellCentre(x, y, w, h)) / double(w * h);
    EXPECT_NEAR(integral, 1.0, 1e-6);
    std::vector<int> counts(size_t(w * h), 0);
    Rng rng = Rng::forSample(2, 0, 0, 0);
    const int n = 600000;
    for (int i = 0; i < n; ++i) {
        float pdf = 0.0f;
        const Vec2 p = d.sample(rng.uniform2(), pdf);
        ASSERT_FLOAT_EQ(pdf, d.pdf(p));
        ++counts[size_t(int(p.y * float(h)) * w + int(p.x * float(w)))];
    }
    for (int i = 0; i < w * h; ++i) {
        const double p = d.pdf(cellCentre(i % w, i / w, w, h)) / double(w * h);
        EXPECT_NEAR(counts[size_t(i)], n * p, 5.0 * std::sqrt(n * p * (1 - p)) + 1e-9)
            << "cell " << i;
    }
}

}  // namespace
}  // namespace caustic
