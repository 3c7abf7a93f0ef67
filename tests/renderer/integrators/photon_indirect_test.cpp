// Path tracing with photon-mapped indirect light (indirect = photon_map, issue 17): the path ends
// at its second non-specular vertex, where a light sample gives the direct light and a
// progressive map of the photons that scattered before they landed gives the rest.
//
// The known answer is the furnace of furnace_support.h in the analytic sphere, where the density
// estimate is exact in expectation whatever its radius: the spherical cap of chord radius s has
// area pi s^2 (Archimedes), so the area within chord distance s of a point grows as on a plane,
// and a kernel normalized over a flat disk integrates to 1 over the cap too. Photons land
// uniformly on the sphere, so every pass (its own photons and camera samples) is an unbiased,
// independent estimate of Le / (1 - rho), and the pixel t-test of the furnace holds. The pixels of
// one pass share its photons, so the image mean is tested across the passes' image means.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "furnace_support.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::Enclosure;
using testing::furnaceRadiance;
using testing::furnaceScene;
using testing::mergePatched;
using testing::Sampling;
using testing::samplingName;
using testing::samplingSettings;
using testing::sceneFromJson;
using testing::settingsFrom;

constexpr std::array<double, 3> kLe = {1.0, 0.5, 2.0};
constexpr int kSize = 8;
constexpr int kPasses = 64;

struct IndirectCase {
    double rho;
    Sampling sampling;
};

std::vector<IndirectCase> indirectCases() {
    std::vector<IndirectCase> cases;
    for (double rho : {0.5, 0.9})
        for (Sampling s : {Sampling::Bsdf, Sampling::Light, Sampling::Mis})
            cases.push_back({rho, s});
    return cases;
}

// False alarms 1e-3 for the file, split over every pixel value and image mean of every case.
const double kThreshold = testing::studentThreshold(
    1e-3 / (double(indirectCases().size()) * (kSize * kSize + 1) * 3), kPasses - 1);

class PhotonIndirectFurnace : public ::testing::TestWithParam<IndirectCase> {};

TEST_P(PhotonIndirectFurnace, EveryPixelIsLeOverOneMinusAlbedo) {
    const IndirectCase& c = GetParam();
    auto scene = sceneFromJson(furnaceScene(Enclosure::Sphere, c.rho, kLe, kSize));
    // Few photons a pass and a radius of a fifth of the sphere's: an estimate holds about 200 of
    // them, and the passes' noise, not their photons' bias (there is none), is what is tested.
    const int sppPerPass = 16;
    std::vector<std::array<double, 3>> passMeans;
    std::array<double, 3> before{};
    RenderCallbacks callbacks;
    callbacks.onPass = [&](const Film& film) {
        // The image mean of the latest pass, from the mean of all passes so far.
        std::vector<float> mean = film.meanRgb();
        std::array<double, 3> now{};
        for (size_t i = 0; i < mean.size(); ++i) now[i % 3] += mean[i] / double(mean.size() / 3);
        const double n = film.passes();
        std::array<double, 3> pass{};
        for (int ch = 0; ch < 3; ++ch) pass[ch] = n * now[ch] - (n - 1) * before[ch];
        passMeans.push_back(pass);
        before = now;
    };
    RenderResult r = render(*scene,
                            settingsFrom(mergePatched({{"integrator", "path"},
                                                       {"indirect", "photon_map"},
                                                       {"indirect_photons", 4000},
                                                       {"indirect_radius", 0.2},
                                                       {"max_depth", 100000},
                                                       {"spp", kPasses * sppPerPass},
                                                       {"spp_per_pass", sppPerPass},
                                                       {"seed", 5}},
                                                      samplingSettings(c.sampling))),
                            callbacks);
    ASSERT_EQ(r.film->passes(), kPasses);
    ASSERT_EQ(passMeans.size(), size_t(kPasses));
    const std::array<double, 3> expected = furnaceRadiance(c.rho, kLe);
    testing::UniformCheck pixels = testing::checkUniform(*r.film, expected, kThreshold);
    EXPECT_EQ(pixels.failures, 0) << "threshold " << kThreshold << "; worst: " << pixels.worst
                                  << "; largest |t| " << pixels.worstT;
    for (int ch = 0; ch < 3; ++ch) {
        double mean = 0, var = 0;
        for (const auto& p : passMeans) mean += p[ch] / kPasses;
        for (const auto& p : passMeans) var += (p[ch] - mean) * (p[ch] - mean) / (kPasses - 1);
        const double se = std::sqrt(var / kPasses);
        EXPECT_LE(std::abs(mean - expected[ch]), kThreshold * se + 1e-5 * expected[ch])
            << "channel " << ch << ": image mean " << mean << " +- " << se << ", expected "
            << expected[ch];
        ::testing::Test::RecordProperty("relative_se_channel_" + std::to_string(ch),
                                        std::to_string(se / expected[ch]));
    }
}

INSTANTIATE_TEST_SUITE_P(PathTracer, PhotonIndirectFurnace, ::testing::ValuesIn(indirectCases()),
                         [](const ::testing::TestParamInfo<IndirectCase>& p) {
                             return std::string(p.param.rho < 0.6 ? "Albedo0_5" : "Albedo0_9") +
                                    samplingName(p.param.sampling);
                         });

TEST(PhotonIndirect, DirectLightOnlyIsThePathTracedImageBitForBit) {
    // With max_depth 1 a path ends before its second vertex could read the map, and the camera
    // paths draw the same random numbers: the path-traced image, bit for bit.
    auto scene = sceneFromJson(testing::exampleScene("cornell-spheres", 24, 16));
    const json base{{"max_depth", 1}, {"spp", 8}, {"spp_per_pass", 4}, {"indirect_photons", 2000}};
    std::vector<float> a = render(*scene, settingsFrom(base)).film->meanRgb();
    RenderResult mapped =
        render(*scene, settingsFrom(mergePatched(base, {{"indirect", "photon_map"}})));
    std::vector<float> b = mapped.film->meanRgb();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
    EXPECT_GT(mapped.stats.rays, render(*scene, settingsFrom(base)).stats.rays);
}

TEST(PhotonIndirect, TracesFewerRaysASampleThanPathsAlone) {
    // What it is for: a camera path ends at its second diffuse vertex (4 rays at most in the
    // cornell-box, whose surfaces are all diffuse: camera, light sample, gather, light sample).
    auto scene = sceneFromJson(testing::exampleScene("cornell-box", 32, 32));
    const json base{{"spp", 16}, {"spp_per_pass", 16}, {"max_depth", 16}};
    RenderResult paths = render(*scene, settingsFrom(base));
    RenderResult mapped = render(
        *scene,
        settingsFrom(mergePatched(base, {{"indirect", "photon_map"}, {"indirect_photons", 1000}})));
    // One pass: 1000 photon paths of at most 16 rays each.
    const double samples = 32.0 * 32.0 * 16.0;
    EXPECT_LE(double(mapped.stats.rays), 4.0 * samples + 1000.0 * 16.0);
    EXPECT_LT(double(mapped.stats.rays), double(paths.stats.rays));
}

}  // namespace
}  // namespace caustic
