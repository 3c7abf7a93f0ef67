#include "core/rng.h"

#include <gtest/gtest.h>

namespace caustic {

TEST(Rng, SameSeedSameSequence) {
    Rng a = Rng::forSample(7, 3, 1000, 2), b = Rng::forSample(7, 3, 1000, 2);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(a.nextUint(), b.nextUint());
}

TEST(Rng, NeighbouringSamplesDiffer) {
    Rng a = Rng::forSample(0, 0, 0, 0), b = Rng::forSample(0, 0, 0, 1),
        c = Rng::forSample(0, 1, 0, 0);
    EXPECT_NE(a.nextUint(), b.nextUint());
    EXPECT_NE(Rng::forSample(0, 0, 0, 0).nextUint(), c.nextUint());
}

TEST(Rng, UniformIsInUnitIntervalWithMeanOneHalf) {
    Rng rng(42);
    double sum = 0;
    const int n = 1 << 20;
    for (int i = 0; i < n; ++i) {
        float u = rng.uniform();
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        sum += u;
    }
    // Standard error of the mean of U(0,1) is sqrt(1/12/n) ~ 2.8e-4; allow 5 sigma.
    EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / 12.0 / n));
}

}  // namespace caustic
