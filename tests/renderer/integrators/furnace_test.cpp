// The furnace test of the path tracer: inside a closed diffuse enclosure of albedo rho emitting Le
// on its inside, every pixel converges to Le / (1 - rho) (see furnace_support.h), with every
// combination of light sampling and MIS, for an analytic sphere (sampled by area from inside) and
// for enclosures of quads and of triangles (their area lights chosen by power among many).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "furnace_support.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::Enclosure;
using testing::expectUniform;
using testing::furnaceRadiance;
using testing::furnaceScene;
using testing::mergePatched;
using testing::Sampling;
using testing::samplingName;
using testing::samplingSettings;
using testing::sceneFromJson;
using testing::settingsFrom;

// A different emission per channel, so that a bug mixing channels (or using one channel's value
// for all) moves the answer.
constexpr std::array<double, 3> kLe = {1.0, 0.5, 2.0};

struct FurnaceCase {
    Enclosure enclosure;
    double rho;
    Sampling sampling;
    std::string sampler = "independent";  ///< The `sampler` setting.
};

// Every albedo and sampling mode in the sphere, whose light sampling from inside is by area (and
// has zero variance: from a point on a sphere, cos_i = cos_l = d / 2r, so the estimate
// (rho / pi) Le cos_i cos_l / d^2 * area is rho Le for every sample). The quads and triangles are
// there for their light sampling (area sampling, the choice among many lights by power, and for
// MIS their pdfLi), at rho = 0.9:
//  - Not with BSDF sampling alone: then the enclosure's shape cannot matter (every ray meets the
//    wall and collects the same Le; only Russian roulette decides a path's value), and the image
//    is the sphere's bit for bit (measured), so those cases would add nothing.
//  - The box not with light sampling alone: at its concave edges that estimator has infinite
//    variance (a shading point at distance a from an edge, sampling the adjacent wall at distance
//    b from it: cos_i cos_l / d^2 = a b / d^4, whose second moment is ~1 / a^2, and the integral
//    of da / a^2 over the shading points diverges), so no pass-variance test has a known
//    false-alarm rate: measured over 40 seeds, |t| > 4 came 13 times in 2560 pixels where Student
//    t expects 0.43. MIS bounds the weight (BSDF sampling takes over there): |t| > 4 0 times,
//    |t| > 3 8 times (t: 10). The icosphere's dihedral angles are near 180 degrees, the same
//    singularity is negligible there, and its light-sampling-only t values follow Student t
//    (|t| > 3 9 times, > 4 once).
std::vector<FurnaceCase> furnaceCases() {
    std::vector<FurnaceCase> cases;
    for (Sampling s : {Sampling::Bsdf, Sampling::Light, Sampling::Mis})
        for (double rho : {0.5, 0.9, 0.99}) cases.push_back({Enclosure::Sphere, rho, s});
    cases.push_back({Enclosure::Box, 0.9, Sampling::Mis});
    cases.push_back({Enclosure::Icosphere, 0.9, Sampling::Light});
    cases.push_back({Enclosure::Icosphere, 0.9, Sampling::Mis});
    // The RQMC sampler converges to the same answer, and its pass variance is as trustworthy.
    cases.push_back({Enclosure::Sphere, 0.9, Sampling::Mis, "sobol"});
    cases.push_back({Enclosure::Box, 0.9, Sampling::Mis, "sobol"});
    cases.push_back({Enclosure::Icosphere, 0.9, Sampling::Light, "sobol"});
    // So does one sequence through the passes (whose pass variance only overestimates).
    cases.push_back({Enclosure::Sphere, 0.9, Sampling::Mis, "sobol_sequence"});
    cases.push_back({Enclosure::Box, 0.9, Sampling::Mis, "sobol_sequence"});
    return cases;
}

constexpr int kSize = 8;     // pixels per side
constexpr int kPasses = 64;  // pass estimates per pixel: the standard error has 63 dof

// The false-alarm rate of the whole file, 1e-3, split evenly (Bonferroni) over every check: each
// case tests every pixel and the image mean, per channel. (The channels of a pixel are in fact
// perfectly correlated here, every sample being a grey weight times Le, and the image mean's t
// has far more than 63 degrees of freedom; both only make the bound more conservative.)
constexpr double kFalseAlarmRate = 1e-3;
const double kChecks = double(furnaceCases().size()) * (kSize * kSize + 1) * 3;
const double kThreshold = testing::studentThreshold(kFalseAlarmRate / kChecks, kPasses - 1);

class Furnace : public ::testing::TestWithParam<FurnaceCase> {};

TEST_P(Furnace, EveryPixelIsLeOverOneMinusAlbedo) {
    const FurnaceCase& fc = GetParam();
    auto scene = sceneFromJson(furnaceScene(fc.enclosure, fc.rho, kLe, kSize));
    // A path of n bounces has expected weight rho^n (Russian roulette keeps it unbiased), so
    // max_depth N cuts off the share rho^(N+1) / (1 - rho) of the answer; with N = 100000 that is
    // 0.99^100001 = 1e-437: nothing. Paths end by roulette, after ~1 / (1 - rho) bounces.
    // The samples per pass scale with 1 - rho, so that each case costs about the same: the
    // relative standard deviation of a sample is ~sqrt(rho) whatever rho (the number of bounces
    // is geometric), so the cheap cases get the tighter image-mean test.
    const int sppPerPass = fc.rho < 0.6 ? 128 : fc.rho < 0.95 ? 32 : 4;
    RenderResult r = render(*scene, settingsFrom(mergePatched({{"integrator", "path"},
                                                               {"max_depth", 100000},
                                                               {"spp", kPasses * sppPerPass},
                                                               {"spp_per_pass", sppPerPass},
                                                               {"seed", 11},
                                                               {"sampler", fc.sampler}},
                                                              samplingSettings(fc.sampling))));
    ASSERT_EQ(r.film->passes(), kPasses);
    EXPECT_EQ(r.stats.droppedSamples, 0u);

    // Every pixel, and the image mean: the same test on the mean of the 64 independent pixels,
    // whose standard error is sqrt(sum se^2) / 64, 8 times tighter than a pixel's: measured 0.06%,
    // 0.25% and 0.8% of the answer for rho = 0.5, 0.9 and 0.99 (BSDF sampling), so that a bias of
    // 0.3%, 1.4% and 4.5% fails. A bias too small to show in one pixel shows there.
    expectUniform(*r.film, furnaceRadiance(fc.rho, kLe), kThreshold);
}

INSTANTIATE_TEST_SUITE_P(PathTracer, Furnace, ::testing::ValuesIn(furnaceCases()),
                         [](const ::testing::TestParamInfo<FurnaceCase>& p) {
                             // Albedo0_5, Albedo0_9, Albedo0_99.
                             char rho[16];
                             std::snprintf(rho, sizeof rho, "%g", p.param.rho);
                             std::string name = std::string(rho);
                             std::replace(name.begin(), name.end(), '.', '_');
                             return std::string(testing::enclosureName(p.param.enclosure)) +
                                    "_Albedo" + name + "_" + samplingName(p.param.sampling) +
                                    (p.param.sampler == "sobol"            ? "_Sobol"
                                     : p.param.sampler == "sobol_sequence" ? "_SobolSequence"
                                                                           : "");
                         });

}  // namespace
}  // namespace caustic
