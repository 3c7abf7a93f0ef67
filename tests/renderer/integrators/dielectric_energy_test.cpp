// Energy conservation at dielectric interfaces under path tracing. A smooth dielectric reflects R
// and transmits T = 1 - R (exact Fresnel or Schlick alike), and transmitted radiance is scaled by
// 1 / eta^2 on entering a medium of relative index eta and by eta^2 on leaving it (Veach 1997,
// 5.2: L / eta^2 is invariant along a ray). So, in a uniform radiance field, a glass object is
// invisible: every path through it is weighted 1 in the end.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "furnace_support.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::checkUniform;
using testing::emissiveWallScene;
using testing::Enclosure;
using testing::expectUniform;
using testing::furnaceRadiance;
using testing::furnaceScene;
using testing::kEmissiveWallLe;
using testing::mergePatched;
using testing::pixelValueText;
using testing::Sampling;
using testing::samplingName;
using testing::samplingSettings;
using testing::sceneFromJson;
using testing::settingsFrom;

// ---------------------------------------------------------------------------------------------
// (a) Glass of IOR 1 is not there. With eta = 1 Snell's law leaves every direction unchanged, the
// exact Fresnel reflectance is 0 (cos theta_t = cos theta_i, so both amplitude ratios vanish) and
// the 1 / eta^2 scaling is 1: each camera ray crosses the sphere with weight exactly 1 and reaches
// the wall behind it. The scene is emissiveWallScene (support/test_scenes.h): its wall has albedo
// 0, which ends every path there (the diffuse sample has weight 0, and light samples there are 0),
// so each sample is exactly the wall's Le, with or without the sphere.

class GlassOfIorOne : public ::testing::TestWithParam<Sampling> {};

TEST_P(GlassOfIorOne, VanishesUnderPathTracing) {
    RenderSettings settings = settingsFrom(
        mergePatched({{"integrator", "path"},
                      {"spp", 8},
                      {"spp_per_pass", 2},
                      {"seed", 3},
                      {"max_depth", 100},
                      // Each sample's own ray sees the wall: where extra camera rays looked for it
                      // instead, they would see it beside the sphere, not through it, and a sample
                      // would no longer be exactly Le (only its expectation would).
                      {"emission_samples", 0}},
                     samplingSettings(GetParam())));
    RenderResult plain = render(*sceneFromJson(emissiveWallScene(false, 24)), settings);
    RenderResult r = render(*sceneFromJson(emissiveWallScene(true, 24)), settings);
    EXPECT_EQ(r.stats.droppedSamples, 0u);
    // Every sample of every pixel is the wall's Le: a float Le summed in double over the samples
    // of a pass and divided by their number is exact, so only the double-to-float conversions of
    // the sums round (relative 1e-7; 1e-6 allowed), and the passes do not vary.
    const Film &a = *plain.film, &b = *r.film;
    int failures = 0;
    std::string first;
    for (int y = 0; y < b.height(); ++y) {
        for (int x = 0; x < b.width(); ++x) {
            Color ma = a.mean(x, y), mb = b.mean(x, y), se = b.standardError(x, y);
            for (int c = 0; c < 3; ++c) {
                float le = float(kEmissiveWallLe[c]);
                bool ok = std::abs(mb[c] - le) <= 1e-6f * le &&
                          std::abs(mb[c] - ma[c]) <= 1e-6f * le && se[c] <= 1e-6f * le;
                if (!ok && failures++ == 0)
                    first = pixelValueText(x, y, c, mb[c], se[c]) + " with the sphere, " +
                            std::to_string(ma[c]) + " without, Le " + std::to_string(le);
            }
        }
    }
    EXPECT_EQ(failures, 0) << "first: " << first;
    // The sphere was really traced: each sample that meets it adds two rays.
    EXPECT_GT(r.stats.rays, plain.stats.rays);
}

INSTANTIATE_TEST_SUITE_P(PathTracer, GlassOfIorOne,
                         ::testing::Values(Sampling::Bsdf, Sampling::Light, Sampling::Mis),
                         [](const auto& p) { return std::string(samplingName(p.param)); });

// ---------------------------------------------------------------------------------------------
// (b, c) The white furnace: no geometry but a glass sphere, and a background of radiance 1 in
// every direction. A path that meets the sphere is reflected (probability R, weight R / R = 1) or
// transmitted (probability T = 1 - R, weight (T / eta^2) / T = 1 / eta^2 on entering and
// (T eta^2) / T = eta^2 on leaving); a sphere has no total internal reflection from inside (a
// chord meets the surface at both ends at the same angle, the refracted one, below the critical
// angle), so every path leaves it, having entered and left as often, and its weight is 1 up to
// float rounding: every pixel is exactly 1.
//
// (c) GlassSphereIsInvisible fails if the radiance scaling does not cancel: with 1 / eta^2 on
// entering but no eta^2 on leaving, pixels through the glass would be 1 / eta^2 = 0.444 for
// eta = 1.5 (0.01 for eta = 10); with the eta^2 but not the 1 / eta^2, eta^2 = 2.25 (100); with
// T = 1 - R not divided by its probability, T < 1. Scalings that cancel but are wrong (none at all,
// as if the path carried importance, or eta^2 on entering and 1 / eta^2 on leaving) pass it, and
// CameraInsideGlassSeesEtaSquared fails on them (1 and 1 / eta^2 instead of eta^2).

struct Glass {
    const char* name;
    double ior;
    const char* fresnel;
};

constexpr Glass kGlasses[] = {
    {"Ior1_0001", 1.0001, "exact"},    {"Ior1_5", 1.5, "exact"},          {"Ior10", 10.0, "exact"},
    {"Ior1_5Schlick", 1.5, "schlick"}, {"Ior10Schlick", 10.0, "schlick"},
};

json whiteFurnace(const Glass& g, const json& cameraPosition) {
    return {
        {"camera",
         {{"position", cameraPosition},
          {"look_at", {0.1, -0.1, 0.2}},
          {"fov", 40},
          {"width", 24},
          {"height", 24}}},
        {"materials",
         {{"glass", {{"type", "dielectric"}, {"ior", g.ior}, {"fresnel", g.fresnel}}}}},
        {"shapes",
         {{{"type", "sphere"},
           {"center", {0.0, 0.0, 0.0}},
           {"radius", 1.0},
           {"material", "glass"}}}},
        {"background", {1, 1, 1}},
    };
}

// Russian roulette off (rr_depth = max_depth), so that each sample is its path's exact weight
// rather than 0 or weight / q; max_depth 100000 leaves a path inside the sphere with probability
// R^100000 = 0 for any of these (R < 1 at every angle that enters: from inside it is the same R).
const json kExactPaths = {
    {"integrator", "path"}, {"max_depth", 100000}, {"rr_depth", 100000}, {"seed", 5}};

// Float rounding: each interaction multiplies the weight by a ratio computed with a few roundings
// (R / R, T / eta^2 / T, T eta^2 / T: a few ulp of 6e-8 each) over a handful of interactions, then
// the film's double sums round to float. Measured: at most 1.2e-7 (one ulp of 1) off, over every
// pixel of every case; 2e-6 leaves room for a path of ~10 interactions more.
constexpr double kRounding = 2e-6;

// The white furnace of `g` seen from `cameraPosition` with exact path weights, `spp` samples in
// passes of 4.
RenderResult renderExactPaths(const Glass& g, const json& cameraPosition, int spp) {
    return render(*sceneFromJson(whiteFurnace(g, cameraPosition)),
                  settingsFrom(mergePatched(kExactPaths, {{"spp", spp}, {"spp_per_pass", 4}})));
}

class WhiteFurnace : public ::testing::TestWithParam<Glass> {};

TEST_P(WhiteFurnace, GlassSphereIsInvisible) {
    const Glass& g = GetParam();
    RenderResult r = renderExactPaths(g, {0.5, 0.7, 3.5}, 16);
    EXPECT_EQ(r.stats.droppedSamples, 0u);
    // Every sample is 1, so every pass of every pixel is: the standard error is ~0, and the
    // check is |mean - 1| <= kRounding.
    testing::UniformCheck c = checkUniform(*r.film, {1, 1, 1}, 0.0, kRounding);
    EXPECT_EQ(c.failures, 0) << "worst: " << c.worst;
    // The sphere is in view: about half of the 24 x 24 x 16 camera rays meet it (measured: 1.99
    // rays per sample), and a path that meets it traces one or two rays more.
    EXPECT_GT(r.stats.rays, uint64_t(1.5 * 24 * 24 * 16));
}

// The camera at the centre of the glass sphere sees radiance eta^2 in every direction: the
// radiance inside a medium of index eta in equilibrium with radiance 1 outside (L / eta^2 is
// invariant). From the centre every ray meets the surface at normal incidence and leaves with
// probability T and weight eta^2, or is reflected back through the centre (weight 1), so every
// sample is exactly eta^2. Without the radiance scaling it would be 1.
TEST_P(WhiteFurnace, CameraInsideGlassSeesEtaSquared) {
    const Glass& g = GetParam();
    RenderResult r = renderExactPaths(g, {0.0, 0.0, 0.0}, 8);
    EXPECT_EQ(r.stats.droppedSamples, 0u);
    const double e2 = g.ior * g.ior;
    testing::UniformCheck c = checkUniform(*r.film, {e2, e2, e2}, 0.0, kRounding);
    EXPECT_EQ(c.failures, 0) << "worst: " << c.worst;
}

INSTANTIATE_TEST_SUITE_P(PathTracer, WhiteFurnace, ::testing::ValuesIn(kGlasses),
                         [](const auto& p) { return std::string(p.param.name); });

// ---------------------------------------------------------------------------------------------
// The statistical tests of this file (the two below) share a false-alarm rate of 1e-3, split
// evenly (Bonferroni) over every pixel value and image mean they check; the pass estimates'
// standard errors have 63 degrees of freedom (Student t, see furnace_support.h).
constexpr int kPasses = 64;
constexpr int kFurnaceSize = 8;
constexpr int kFurnaceCases = 5;   // GlassInFurnace
constexpr int kRouletteSize = 24;  // WhiteFurnaceRoulette
constexpr double kFalseAlarmRate = 1e-3;
const double kChecks =
    3.0 * (kFurnaceCases * (kFurnaceSize * kFurnaceSize + 1) + (kRouletteSize * kRouletteSize + 1));
const double kThreshold = testing::studentThreshold(kFalseAlarmRate / kChecks, kPasses - 1);

// With Russian roulette from the third bounce (the default). Inside the glass the throughput beta
// carries the radiance scaling 1 / eta^2, which roulette must not take for lost energy: it decides
// on beta * etaScale (pbrt-v4 13.4.3), which is exactly 1 in this scene, so no path is cut and
// every sample is exactly 1. A roulette on beta alone would cut 56% of the paths inside the glass
// and weight the survivors by 2.25: right in expectation, but noisy (fireflies in glass).
TEST(WhiteFurnaceRoulette, GlassSphereIsInvisibleAndRouletteIgnoresRadianceScaling) {
    const Glass g{"Ior1_5", 1.5, "exact"};
    json doc = whiteFurnace(g, {0.5, 0.7, 3.5});
    RenderResult r = render(*sceneFromJson(doc), settingsFrom({{"integrator", "path"},
                                                               {"max_depth", 100000},
                                                               {"rr_depth", 3},
                                                               {"spp", kPasses * 2},
                                                               {"spp_per_pass", 2},
                                                               {"seed", 9}}));
    ASSERT_EQ(r.film->passes(), kPasses);
    EXPECT_EQ(r.stats.droppedSamples, 0u);
    // Every pixel and the image mean: |mean - 1| <= kThreshold se + kRounding.
    expectUniform(*r.film, {1, 1, 1}, kThreshold, kRounding);
    // No path was cut: the passes of every pixel agree to rounding.
    double largestSe = 0;
    for (int y = 0; y < r.film->height(); ++y)
        for (int x = 0; x < r.film->width(); ++x)
            largestSe = std::max(largestSe, double(r.film->standardError(x, y)[0]));
    EXPECT_LT(largestSe, 1e-6);
}

// A glass sphere inside the diffuse furnace of furnace_test.cpp: the radiance field is uniform,
// Le / (1 - rho), so the glass is invisible there too, and every pixel (through the glass or not)
// is Le / (1 - rho). Here paths mix diffuse and specular vertices: a light sample from the wall
// towards wall points behind the glass is occluded, so that light arrives only along BSDF-sampled
// paths through the glass, and the emission they find after the glass's specular vertex must
// count with weight 1 whether light sampling and MIS are on or not.
struct GlassInFurnaceCase {
    Enclosure enclosure;
    Sampling sampling;
};

// The sphere in every sampling mode; quads with MIS and triangles with light sampling alone (the
// light-sampled cases that furnace_test.cpp can test: not the box without MIS, whose estimator has
// infinite variance at its edges).
constexpr GlassInFurnaceCase kGlassInFurnaceCases[] = {
    {Enclosure::Sphere, Sampling::Bsdf},     {Enclosure::Sphere, Sampling::Light},
    {Enclosure::Sphere, Sampling::Mis},      {Enclosure::Box, Sampling::Mis},
    {Enclosure::Icosphere, Sampling::Light},
};
static_assert(std::size(kGlassInFurnaceCases) == kFurnaceCases);

class GlassInFurnace : public ::testing::TestWithParam<GlassInFurnaceCase> {};

TEST_P(GlassInFurnace, EveryPixelIsLeOverOneMinusAlbedo) {
    const auto [enclosure, sampling] = GetParam();
    const double rho = 0.9;
    const std::array<double, 3> Le = {1.0, 0.5, 2.0};
    json doc = furnaceScene(enclosure, rho, Le, kFurnaceSize);
    doc["materials"]["glass"] = {{"type", "dielectric"}, {"ior", 1.5}};
    // Halfway along the view direction, so that it covers much of the image; radius 0.2 keeps it
    // inside both enclosures.
    std::array<double, 3> center;
    for (int i = 0; i < 3; ++i)
        center[i] = testing::kFurnaceCamera[i] +
                    0.5 * (testing::kFurnaceLookAt[i] - testing::kFurnaceCamera[i]);
    doc["shapes"].push_back(
        {{"type", "sphere"}, {"center", center}, {"radius", 0.2}, {"material", "glass"}});
    // max_depth 100000: the cut-off share rho^100001 / (1 - rho) of the answer is nothing.
    RenderResult r =
        render(*sceneFromJson(doc), settingsFrom(mergePatched({{"integrator", "path"},
                                                               {"max_depth", 100000},
                                                               {"spp", kPasses * 16},
                                                               {"spp_per_pass", 16},
                                                               {"seed", 13}},
                                                              samplingSettings(sampling))));
    ASSERT_EQ(r.film->passes(), kPasses);
    EXPECT_EQ(r.stats.droppedSamples, 0u);
    expectUniform(*r.film, furnaceRadiance(rho, Le), kThreshold);
}

INSTANTIATE_TEST_SUITE_P(PathTracer, GlassInFurnace, ::testing::ValuesIn(kGlassInFurnaceCases),
                         [](const auto& p) {
                             return std::string(testing::enclosureName(p.param.enclosure)) + "_" +
                                    samplingName(p.param.sampling);
                         });

}  // namespace
}  // namespace caustic
