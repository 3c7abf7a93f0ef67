// The photon look-up behind photon mapping does not change the image: the kd-tree and brute force
// return the same neighbours in the same order (photons/neighbor_index.h), so the images of both
// are bit-identical. This is what makes the seed's Table 1 (bench/photon_table1.cpp) a comparison
// of speed alone.
#include <gtest/gtest.h>

#include "support/test_scenes.h"

namespace caustic {
namespace {

using testing::exampleScene;
using testing::sceneFromJson;
using testing::settingsFrom;

TEST(PhotonLookup, BruteForceRendersTheSameImage) {
    auto scene = sceneFromJson(exampleScene("cornell-spheres", 16, 12));
    for (const char* integrator : {"photon", "ppm"}) {
        for (int finalGather : {0, 2}) {
            if (finalGather > 0 && std::string(integrator) == "ppm") continue;
            auto image = [&](const char* lookup) {
                return render(*scene, settingsFrom({{"integrator", integrator},
                                                    {"photons", 5000},
                                                    {"caustic_photons", 5000},
                                                    {"final_gather", finalGather},
                                                    {"spp", 2},
                                                    {"photon_lookup", lookup}}))
                    .film->meanRgb();
            };
            EXPECT_EQ(image("kdtree"), image("brute_force"))
                << integrator << ", final_gather " << finalGather;
        }
    }
}

}  // namespace
}  // namespace caustic
