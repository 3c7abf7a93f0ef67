// Progressive photon mapping converges to the path-traced image (issue 5, acceptance 3). Each ppm
// pass is an independent estimate whose radius shrinks with the pass index (Knaus & Zwicker 2011),
// so the mean of n passes has a bias that falls with the radius and a variance that falls about as
// n^-(2/3) (alpha = 2/3): its RMS error against a path-traced reference must fall from checkpoint
// to checkpoint and end below a stated threshold.
//
// Measured when this test was written (seeds 2, 3 and 4 for ppm): relative RMSE 0.26-0.28 after 4
// passes, 0.11-0.14 after 16, 0.040-0.070 after 64 and 0.024-0.033 after 256, against a reference
// whose own noise is 0.7% RMS. Most of what is left at 256 passes is the pixel-footprint noise of
// a few pixels on the lamp's edges (emission 18 beside a white ceiling), whose variance falls as
// 1/n.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "support/test_scenes.h"

namespace caustic {
namespace {

using testing::exampleScene;
using testing::sceneFromJson;
using testing::settingsFrom;

double rmse(const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += double(a[i] - b[i]) * double(a[i] - b[i]);
    return std::sqrt(sum / double(a.size()));
}

double rms(const std::vector<float>& a) {
    return rmse(a, std::vector<float>(a.size(), 0.0f));
}

TEST(PpmConvergence, CornellSpheresApproachesThePathReference) {
    const int size = 32;
    auto scene = sceneFromJson(exampleScene("cornell-spheres", size, size));
    RenderResult reference = render(
        *scene,
        settingsFrom({{"integrator", "path"}, {"spp", 8192}, {"spp_per_pass", 64}, {"seed", 1}}));
    const std::vector<float> ref = reference.film->meanRgb();
    const double scale = rms(ref);
    // The reference's own error must be small beside the threshold below.
    const double referenceNoise = rms(reference.film->standardErrorRgb()) / scale;
    EXPECT_LT(referenceNoise, 0.01);

    // 20000 photon paths a pass and a first radius of 0.05 (1/70 of the scene's diagonal, about
    // one pixel's footprint on the back wall at 32 x 32).
    const std::vector<int> checkpoints{4, 16, 64, 256};
    std::vector<double> errors;
    RenderCallbacks callbacks;
    callbacks.onPass = [&](const Film& film) {
        for (int c : checkpoints)
            if (film.passes() == c) errors.push_back(rmse(film.meanRgb(), ref) / scale);
    };
    render(*scene,
           settingsFrom({{"integrator", "ppm"},
                         {"spp", checkpoints.back()},
                         {"spp_per_pass", 1},
                         {"photons", 20000},
                         {"radius", 0.05},
                         {"seed", 2}}),
           callbacks);
    ASSERT_EQ(errors.size(), checkpoints.size());
    for (size_t i = 0; i < errors.size(); ++i) {
        RecordProperty("relative_rmse_after_" + std::to_string(checkpoints[i]) + "_passes",
                       std::to_string(errors[i]));
        if (i > 0) {
            EXPECT_LT(errors[i], errors[i - 1])
                << "after " << checkpoints[i] << " passes against " << checkpoints[i - 1];
        }
    }
    EXPECT_LT(errors.back(), 0.05) << "relative RMSE after " << checkpoints.back() << " passes";
}

}  // namespace
}  // namespace caustic
