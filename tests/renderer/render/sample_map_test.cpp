// The adaptive sample map: samples follow the pilot's noise, within bounds, for the same total,
// the same on every call; a noiseless pilot keeps the uniform count.
#include "render/sample_map.h"

#include <gtest/gtest.h>

#include <numeric>

namespace caustic {
namespace {

// A pilot whose left half is noisy (pass values alternate between 0 and 2) and right half is not.
Film halfNoisyPilot(int width, int height, float rightNoise) {
    Film film(width, height);
    for (int p = 0; p < kAdaptivePilotPasses; ++p) {
        std::vector<Color> pass(size_t(width) * size_t(height));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                pass[size_t(y) * size_t(width) + size_t(x)] =
                    Color(x < width / 2 ? float(2 * (p % 2)) : 1.0f + rightNoise * float(p % 2));
        film.addPass(pass);
    }
    return film;
}

TEST(AdaptiveSampleMap, SamplesFollowTheNoiseForTheSameTotal) {
    const int width = 32, height = 8, spp = 16;
    std::vector<uint16_t> map = adaptiveSampleMap(halfNoisyPilot(width, height, 0.1f), spp);
    ASSERT_EQ(map.size(), size_t(width * height));
    const double total = std::accumulate(map.begin(), map.end(), 0.0);
    EXPECT_NEAR(total / double(map.size()), spp, 0.05 * spp);
    for (uint16_t n : map) {
        EXPECT_GE(n, spp / 4);
        EXPECT_LE(n, 8 * spp);
    }
    // Far from the boundary the noisy side has 20 times the standard deviation: capped by the
    // budget, it takes what the quiet side's floor leaves.
    EXPECT_GT(map[2], 4 * map[width - 3]);
    EXPECT_EQ(map, adaptiveSampleMap(halfNoisyPilot(width, height, 0.1f), spp));
}

TEST(AdaptiveSampleMap, ANoiselessPilotKeepsTheUniformCount) {
    Film film(4, 4);
    for (int p = 0; p < kAdaptivePilotPasses; ++p)
        film.addPass(std::vector<Color>(16, Color(0.5f)));
    for (uint16_t n : adaptiveSampleMap(film, 8)) EXPECT_EQ(n, 8);
}

TEST(AdaptiveSampleMap, OneSamplePerPassHasNothingToMove) {
    for (uint16_t n : adaptiveSampleMap(halfNoisyPilot(8, 4, 0.0f), 1)) EXPECT_EQ(n, 1);
}

}  // namespace
}  // namespace caustic
