// Convergence tests: estimators of the same image must agree within their own noise. Naive, light
// sampling and MIS path tracing converge to one image (for one max_depth); Whitted and path tracing
// converge to one image where Whitted misses no light.
//
// Statistics (support/region_stats.h): the image is split into regions, a hierarchy of square
// blocks from a few pixels (local errors) up to the whole image (small errors everywhere). Each
// pass is an independent estimate of the image, so a region's mean in each pass is an independent
// sample, and their spread over the passes gives the standard error of the region's mean. Renders
// with different seeds are independent, so for every region and channel
//     z = (m1 - m2) / sqrt(se1^2 + se2^2)
// is close to standard normal when both converge to the same image.
//
// Significance: a false-alarm rate of 1e-3 per test case, family-wise. Bonferroni over every
// region, channel and pair compared gives each check's two-sided threshold (4.84 for the 765 checks
// of the Cornell box, 5.12 for the 3279 of the mirror scene). The standard errors are themselves
// estimated from N = 128 passes per render: Student's t with about 2(N - 1) degrees of freedom has
// 1.7 times the normal tail beyond such thresholds, and the naive estimator's skewed samples (rare
// lamp hits) add a little more, so the real rate is a few times 1e-3. Measured with other seeds:
// 65 runs of the Cornell comparison and 40 of the mirror scene, no false alarm; largest |z| 4.40
// and 4.92.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "support/region_stats.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::blockHierarchy;
using testing::compare;
using testing::Comparison;
using testing::exampleScene;
using testing::Region;
using testing::RegionStats;
using testing::sceneFromJson;
using testing::settingsFrom;
using testing::twoSidedNormalQuantile;

constexpr double kFamilyWiseFalseAlarm = 1e-3;

struct RegionRender {
    RegionStats stats;
    RenderStats render;
};

RegionRender renderRegions(const Scene& scene, const json& settings,
                           const std::vector<Region>& regions) {
    RegionStats stats(scene.camera.width(), scene.camera.height(), regions);
    RenderResult r = render(scene, settingsFrom(settings), stats.callbacks());
    return {std::move(stats), r.stats};
}

// ---------------------------------------------------------------------------------------------
// Naive, light-sampling and MIS path tracing of the Cornell box with spheres.

// Small, with many samples per pixel: what the regions need is samples. At 2048 spp the whole
// image's standard error is 0.4% of its mean for naive sampling and 0.2% for the other two, so a
// 2% error in one estimator is usually seen (z = 5 to 7), the difference between max_depth 3 and 4
// always (z = 27).
constexpr int kCornellSize = 32;
constexpr int kCornellPasses = 128;
constexpr int kCornellSppPerPass = 16;

// The three estimators differ only in how they find emitters: naive by BSDF sampling alone, light
// sampling by a shadow ray at every non-specular vertex, MIS by both, weighted. They add up the
// same paths (those of at most max_depth scattering events; Russian roulette is unbiased), so
// with one max_depth they converge to one image. The scene has every hard case: a small lamp that
// naive sampling rarely hits, caustics through the glass sphere and off the mirror sphere (found by
// BSDF sampling in all three), and lamp light seen through both.
json cornellSettings(bool lightSampling, bool mis, uint64_t seed) {
    return {{"integrator", "path"},
            {"spp", kCornellPasses * kCornellSppPerPass},
            {"spp_per_pass", kCornellSppPerPass},
            {"max_depth", 8},
            {"light_sampling", lightSampling},
            {"mis", mis},
            {"seed", seed}};
}

TEST(ConvergenceCornellSpheres, NaiveLightSamplingAndMisAgreePerRegion) {
    auto scene = sceneFromJson(exampleScene("cornell-spheres", kCornellSize, kCornellSize));
    const std::vector<Region> regions =
        blockHierarchy(kCornellSize, kCornellSize, {4, 8, 16, kCornellSize});
    // Different seeds: the renders must be independent for their variances to add.
    RegionRender naive = renderRegions(*scene, cornellSettings(false, false, 1), regions);
    RegionRender light = renderRegions(*scene, cornellSettings(true, false, 2), regions);
    RegionRender mis = renderRegions(*scene, cornellSettings(true, true, 3), regions);
    for (const RegionRender* r : {&naive, &light, &mis}) {
        ASSERT_EQ(r->stats.passes(), kCornellPasses);
        EXPECT_EQ(r->render.droppedSamples, 0u);
    }

    const int pairs = 3;
    const double threshold =
        twoSidedNormalQuantile(kFamilyWiseFalseAlarm / double(regions.size() * 3 * pairs));
    Comparison c1 = compare(naive.stats, light.stats);
    Comparison c2 = compare(naive.stats, mis.stats);
    Comparison c3 = compare(light.stats, mis.stats);
    EXPECT_LE(c1.worstZ, threshold) << "naive vs light sampling: " << c1.describe(regions);
    EXPECT_LE(c2.worstZ, threshold) << "naive vs MIS: " << c2.describe(regions);
    EXPECT_LE(c3.worstZ, threshold) << "light sampling vs MIS: " << c3.describe(regions);
}

// Adaptive sampling moves samples to the noisy pixels (the caustics, the lamp's edges) after its
// pilot; each pass stays an unbiased estimate of every pixel, so it converges to the uniform
// render's image. The same statistics, one pair; with the sobol sampler too, whose points adapt
// to each pixel's count.
TEST(ConvergenceCornellSpheres, AdaptiveAndUniformSamplingAgreePerRegion) {
    auto scene = sceneFromJson(exampleScene("cornell-spheres", kCornellSize, kCornellSize));
    const std::vector<Region> regions =
        blockHierarchy(kCornellSize, kCornellSize, {4, 8, 16, kCornellSize});
    RegionRender uniform = renderRegions(*scene, cornellSettings(true, true, 4), regions);
    json adaptive = cornellSettings(true, true, 5);
    adaptive["adaptive"] = true;
    adaptive["sampler"] = "sobol";
    RegionRender adapted = renderRegions(*scene, adaptive, regions);
    ASSERT_EQ(adapted.stats.passes(), kCornellPasses);
    EXPECT_EQ(adapted.render.droppedSamples, 0u);
    const double threshold =
        twoSidedNormalQuantile(kFamilyWiseFalseAlarm / double(regions.size() * 3));
    Comparison c = compare(uniform.stats, adapted.stats);
    EXPECT_LE(c.worstZ, threshold) << "uniform vs adaptive: " << c.describe(regions);
}

// ---------------------------------------------------------------------------------------------
// Whitted and path tracing where Whitted is exact.
//
// Whitted tracing ends every path at the first diffuse surface with the point light's direct
// light; path tracing adds the light arriving there by any other path. They agree only where no
// diffuse point receives light other than directly from the point light. The layout (z up):
//   - a diffuse floor z = 0, x in [-3, 1], y in [-1.5, 1.5], front side up;
//   - a point light at (0, 0, 2);
//   - a mirror (1.5 + s, y, s), s in [0, 1], y in [-1.5, 1.5]: the plane x - z = 1.5 tilted 45
//     degrees beyond the floor's edge, front side n = (-1, 0, 1) / sqrt 2 facing the floor;
//   - a black background, and a camera above and to the right (in front of the mirror) that sees
//     the floor both directly and in the mirror.
// Why no diffuse point receives indirect light:
//   - The floor's top side sees only the mirror and the sky. Every floor point has x - z <= 1 <
//     1.5, so it is in front of the mirror and sees only its front side. Reflection in n maps a
//     direction (dx, dy, dz) to (dz, dy, dx); a ray from the floor that reaches the mirror goes up
//     (dz > 0) and towards +x (dx > 0), so it leaves the mirror going up and towards +x again:
//     away from the floor, and a plane mirror is never hit twice. It reaches the black sky.
//   - The floor's underside is never lit (the light is above) and never seen: the camera is above
//     the floor, and rays reflected by the mirror start at z >= 0 and reach z = 0 from above.
//   - The mirror's back side (x - z > 1.5) faces nothing in the scene: the floor, the light and
//     the camera are all in front of it.
//   - Light -> mirror -> floor is a caustic from a point light: Whitted does not trace it, and
//     path tracing could only find it by a BSDF-sampled ray from the floor hitting the point light,
//     which has probability zero.
// So at every floor point both integrators add up exactly the point light's direct light, seen
// directly or through one mirror bounce, and their images converge to the same one.
constexpr int kMirrorSize = 32;
constexpr int kMirrorPasses = 128;
constexpr int kMirrorSppPerPass = 4;
const Vec3 kMirrorCamera(2.6f, 0.0f, 4.0f);  // as in floorAndMirror()

json floorAndMirror() {
    return json::parse(R"({
      "camera": {"position": [2.6, 0, 4], "look_at": [1.0, 0, 0.4], "up": [0, 0, 1], "fov": 40,
                 "width": 32, "height": 32},
      "materials": {
        "floor": {"type": "diffuse", "albedo": [0.7, 0.5, 0.3]},
        "mirror": {"type": "mirror", "reflectance": [0.9, 0.8, 0.95]}
      },
      "shapes": [
        {"type": "quad", "origin": [-3, -1.5, 0], "u": [4, 0, 0], "v": [0, 3, 0],
         "material": "floor"},
        {"type": "quad", "origin": [1.5, -1.5, 0], "u": [1, 0, 1], "v": [0, 3, 0],
         "material": "mirror"}
      ],
      "lights": [{"type": "point", "position": [0, 0, 2], "intensity": [10, 10, 10]}],
      "background": [0, 0, 0]
    })");
}

// What a camera ray through raster point (x, y) of floorAndMirror() sees, traced analytically.
enum class Seen { Sky, Floor, MirrorSky, MirrorFloor };

bool onFloor(const Vec3& p) {
    return p.x >= -3 && p.x <= 1 && std::abs(p.y) <= 1.5f;
}

Seen whatIsSeen(const Camera& camera, float x, float y) {
    Ray r = camera.generateRay(x, y);
    Vec3 o = r.o + kMirrorCamera, d = r.d;  // the loader stores positions relative to the camera
    float tFloor = d.z < 0 ? -o.z / d.z : kInfinity;
    bool floor = tFloor < kInfinity && onFloor(o + tFloor * d);
    // The mirror plane x - z = 1.5.
    float tMirror = d.x != d.z ? (1.5f - (o.x - o.z)) / (d.x - d.z) : -1.0f;
    Vec3 m = o + tMirror * d;
    if (tMirror > 0 && m.z >= 0 && m.z <= 1 && std::abs(m.y) <= 1.5f && tMirror < tFloor) {
        Vec3 reflected(d.z, d.y, d.x);
        float t = reflected.z < 0 ? -m.z / reflected.z : kInfinity;
        return t < kInfinity && onFloor(m + t * reflected) ? Seen::MirrorFloor : Seen::MirrorSky;
    }
    return floor ? Seen::Floor : Seen::Sky;
}

// What the whole of pixel (x, y) sees, if it is one thing: its centre and corners agree (each
// region seen is convex in the image: a projected quad, or one clipped by another).
std::optional<Seen> pixelSees(const Camera& camera, int x, int y) {
    const float e = 1e-3f;
    Seen centre = whatIsSeen(camera, float(x) + 0.5f, float(y) + 0.5f);
    for (float dx : {e, 1 - e})
        for (float dy : {e, 1 - e})
            if (whatIsSeen(camera, float(x) + dx, float(y) + dy) != centre) return std::nullopt;
    return centre;
}

json mirrorSettings(const std::string& integrator, uint64_t seed) {
    return {{"integrator", integrator},
            {"spp", kMirrorPasses * kMirrorSppPerPass},
            {"spp_per_pass", kMirrorSppPerPass},
            {"max_depth", 8},
            {"seed", seed}};
}

TEST(ConvergenceWhittedAndPath, AgreePerPixelWhereWhittedIsExact) {
    auto scene = sceneFromJson(floorAndMirror());
    const Camera& camera = scene->camera;
    // Every pixel, and blocks up to the whole image for small errors everywhere. Single pixels
    // suffice here: a sample's value depends only on its position in the pixel (the light is a
    // point, and every other random choice of the path tracer adds zero), so they have no heavy
    // tails.
    const std::vector<Region> regions =
        blockHierarchy(kMirrorSize, kMirrorSize, {1, 4, 16, kMirrorSize});
    RegionRender whitted = renderRegions(*scene, mirrorSettings("whitted", 1), regions);
    RegionRender path = renderRegions(*scene, mirrorSettings("path", 2), regions);
    for (const RegionRender* r : {&whitted, &path}) {
        ASSERT_EQ(r->stats.passes(), kMirrorPasses);
        EXPECT_EQ(r->render.droppedSamples, 0u);
    }

    const double threshold =
        twoSidedNormalQuantile(kFamilyWiseFalseAlarm / double(regions.size() * 3));
    Comparison c = compare(whitted.stats, path.stats);
    EXPECT_LE(c.worstZ, threshold) << "whitted vs path: " << c.describe(regions);

    // The comparison means something only if the floor is in view both directly and in the
    // mirror: every pixel that sees only floor, either way, is lit in both images (the layout has
    // 452 of the one and 102 of the other).
    int direct = 0, reflected = 0, dark = 0;
    std::string firstDark;
    for (int y = 0; y < kMirrorSize; ++y) {
        for (int x = 0; x < kMirrorSize; ++x) {
            std::optional<Seen> seen = pixelSees(camera, x, y);
            if (seen != Seen::Floor && seen != Seen::MirrorFloor) continue;
            ++(seen == Seen::Floor ? direct : reflected);
            size_t pixel = size_t(y) * kMirrorSize + size_t(x);  // the first level: single pixels
            for (int ch = 0; ch < 3; ++ch) {
                if (whitted.stats.mean(pixel, ch) > 0.0 && path.stats.mean(pixel, ch) > 0.0)
                    continue;
                if (dark++ == 0)
                    firstDark = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
            }
        }
    }
    EXPECT_GE(direct, 400);
    EXPECT_GE(reflected, 80);
    EXPECT_EQ(dark, 0) << "black floor pixels and channels, the first at " << firstDark;
}

}  // namespace
}  // namespace caustic
