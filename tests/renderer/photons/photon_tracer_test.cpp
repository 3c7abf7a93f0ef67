// Photon tracing: the flux leaving the lights is their power, photons are tagged by their path,
// the list does not depend on the thread count, and stored flux follows the scattering albedo.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "accel/accelerator.h"
#include "photons/photon_tracer.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::exampleScene;
using testing::sceneFromJson;

DVec3 totalLightPower(const Scene& scene) {
    DVec3 sum(0.0);
    for (const auto& light : scene.lights) sum += DVec3(light->power());
    return sum;
}

PhotonTracing trace(const Scene& scene, uint64_t photons, uint64_t seed = 1) {
    auto accel = createAccelerator("embree", scene.geometry);
    PhotonTracingOptions o;
    o.photons = photons;
    o.seed = seed;
    return tracePhotons(scene, *accel, o);
}

void expectRelativelyNear(const DVec3& got, const DVec3& expected, double tolerance) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], expected[c], tolerance * std::abs(expected[c])) << "channel " << c;
}

TEST(PhotonTracer, EmittedFluxIsTheLightsPower) {
    // Every emitted path carries power / (pmf N) = total / N: the sum is the total exactly, up to
    // float rounding of the weights (~1e-7 relative each).
    auto cornell = sceneFromJson(exampleScene("cornell-spheres"));
    PhotonTracing t = trace(*cornell, 20000);
    EXPECT_EQ(t.emitted, 20000u);
    expectRelativelyNear(t.emittedPower, totalLightPower(*cornell), 1e-5);

    // Lights of different kinds and colors, one of them dark. Lights are chosen by luminance, so
    // the luminance of the emitted flux is exact; each channel is right in expectation, with the
    // spread of a sum of N independent choices: per path, channel c carries P_lc / (pmf_l N) with
    // probability pmf_l.
    json doc = exampleScene("cornell-spheres");
    doc["lights"] = json::parse(R"([
        {"type": "point", "position": [0.5, 0.5, 0], "intensity": [3, 1, 2]},
        {"type": "point", "position": [-0.5, 0.5, 0], "intensity": [0, 0, 0]}])");
    auto mixed = sceneFromJson(doc);
    const uint64_t n = 30000;
    PhotonTracing m = trace(*mixed, n);
    DVec3 total = totalLightPower(*mixed);
    EXPECT_NEAR(luminance(Color(m.emittedPower)), luminance(Color(total)),
                1e-5 * luminance(Color(total)));
    for (int c = 0; c < 3; ++c) {
        double secondMoment = 0;  // of one path's value, times n^2
        for (size_t l = 0; l < mixed->lights.size(); ++l) {
            double pmf = mixed->lightSampler.pmf(l), power = mixed->lights[l]->power()[c];
            if (pmf > 0) secondMoment += power * power / pmf;
        }
        double se = std::sqrt((secondMoment - total[c] * total[c]) / double(n));
        EXPECT_NEAR(m.emittedPower[c], total[c], 5 * se + 1e-5 * total[c]) << "channel " << c;
    }
}

// Lights at infinity send photons in through a disk around the scene: the flux that lands on a
// floor of area A is E cos(theta) A from a directional light, and pi Le A on each side from a
// constant environment.
TEST(PhotonTracer, LightsAtInfinityDeliverTheirIrradiance) {
    const json floor = json::parse(R"({
      "camera": {"position": [0, 5, 5], "look_at": [0, 0, 0]},
      "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]}},
      "shapes": [{"type": "quad", "origin": [-1, 0, -2], "u": [0, 0, 4], "v": [2, 0, 0],
                  "material": "black"}]
    })");
    const double area = 8.0;
    json sun = floor, sky = floor;
    sun["lights"] = json::parse(R"([{"type": "directional", "direction": [0.6, -0.8, 0],
                                     "irradiance": [2, 1, 0.5]}])");
    sky["environment"] = {{"color", {0.5, 1, 2}}};
    const DVec3 expectedSun = DVec3(2, 1, 0.5) * 0.8 * area;
    const DVec3 expectedSky = DVec3(0.5, 1, 2) * (2.0 * kPi * area);
    for (const auto& [doc, expected, tolerance] :
         {std::tuple{sun, expectedSun, 0.015}, std::tuple{sky, expectedSky, 0.02}}) {
        auto scene = sceneFromJson(doc);
        PhotonTracing t = trace(*scene, 200000);
        DVec3 landed(0.0);
        for (const Photon& p : t.photons) landed += DVec3(p.power);
        // Only how many photons land is random (binomial): each tolerance is about 5 standard
        // errors.
        expectRelativelyNear(landed, expected, tolerance);
    }
}

TEST(PhotonTracer, NothingEmitsNothingTraced) {
    json doc = exampleScene("cornell-spheres");
    doc["materials"]["lamp"].erase("emission");
    PhotonTracing t = trace(*sceneFromJson(doc), 1000);
    EXPECT_TRUE(t.photons.empty());
    EXPECT_EQ(t.rays, 0u);
}

TEST(PhotonTracer, PathsAreTagged) {
    auto cornell = sceneFromJson(exampleScene("cornell-spheres"));
    PhotonTracing t = trace(*cornell, 50000);
    size_t count[3] = {0, 0, 0};
    for (const Photon& p : t.photons) ++count[int(p.path)];
    // The lamp faces down onto diffuse walls: direct photons; the glass and mirror spheres make
    // caustics; bounces make the rest.
    EXPECT_GT(count[int(PhotonPath::Direct)], 10000u);
    EXPECT_GT(count[int(PhotonPath::Caustic)], 100u);
    EXPECT_GT(count[int(PhotonPath::Indirect)], 10000u);

    // Without specular surfaces there are no caustics.
    json doc = exampleScene("cornell-spheres");
    doc["materials"]["mirror"] = {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}};
    doc["materials"]["glass"] = {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}};
    for (const Photon& p : trace(*sceneFromJson(doc), 20000).photons)
        ASSERT_NE(p.path, PhotonPath::Caustic);
}

// A glossy surface below followedRoughness is passed as a mirror: no photon lands on it, and
// what it sends on to a diffuse surface is a caustic; at 0 it is a surface like any other.
TEST(PhotonTracer, SurfacesBelowTheFollowedRoughnessArePassedAsMirrors) {
    json doc = exampleScene("cornell-spheres");
    doc["materials"]["glass"] = {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}};
    doc["materials"]["mirror"] = {
        {"type", "conductor"}, {"roughness", 0.1}, {"f0", {0.9, 0.9, 0.9}}};
    auto scene = sceneFromJson(doc);
    auto accel = createAccelerator("embree", scene->geometry);
    const uint32_t metal =
        uint32_t(std::find(scene->materialNames.begin(), scene->materialNames.end(), "mirror") -
                 scene->materialNames.begin());
    EXPECT_FLOAT_EQ(scene->materials[metal]->lobeRoughness(), 0.1f);
    // The metal sphere, from its primitive's bounds.
    Bounds3 sphere;
    for (uint32_t prim = 0; prim < scene->geometry.size(); ++prim)
        if (scene->geometry.material(prim) == metal) sphere = scene->geometry.bounds(prim);
    const Vec3 centre = 0.5f * (sphere.lo + sphere.hi);
    const float radius = 0.5f * (sphere.hi.x - sphere.lo.x);
    auto count = [&](float followed) {
        PhotonTracingOptions o;
        o.photons = 20000;
        o.seed = 3;
        o.followedRoughness = followed;
        size_t onMetal = 0, caustic = 0;
        for (const Photon& p : tracePhotons(*scene, *accel, o).photons) {
            caustic += p.path == PhotonPath::Caustic;
            onMetal += glm::length(p.p - centre) < 1.001f * radius;
        }
        return std::make_pair(onMetal, caustic);
    };
    const auto [mapped, mappedCaustics] = count(0.0f);
    EXPECT_GT(mapped, 100u);
    EXPECT_EQ(mappedCaustics, 0u);
    const auto [followed, followedCaustics] = count(0.2f);
    EXPECT_EQ(followed, 0u);
    EXPECT_GT(followedCaustics, 100u);
}

TEST(PhotonTracer, CausticOnlyTracingEstimatesTheSameCaustics) {
    // A path stores at most one caustic photon (its first diffuse hit, after specular bounces
    // only), and in the Cornell box every caustic photon carries the same power: one light, white
    // mirror and glass, and Russian roulette that keeps the largest channel of the power. So each
    // tracing's caustic count is binomial in the paths with the same p, and the two must agree by
    // a two-proportion z-test (|z| < 5).
    auto cornell = sceneFromJson(exampleScene("cornell-spheres"));
    auto accel = createAccelerator("embree", cornell->geometry);
    PhotonTracingOptions o;
    o.photons = 100000;
    o.seed = 1;
    PhotonTracing all = tracePhotons(*cornell, *accel, o);
    o.causticOnly = true;
    PhotonTracing caustic = tracePhotons(*cornell, *accel, o);
    double n = double(o.photons), countAll = 0, countCaustic = double(caustic.photons.size());
    DVec3 powerAll(0.0), powerCaustic(0.0);
    for (const Photon& p : all.photons)
        if (p.path == PhotonPath::Caustic) {
            countAll += 1;
            powerAll += DVec3(p.power);
        }
    for (const Photon& p : caustic.photons) {
        ASSERT_EQ(p.path, PhotonPath::Caustic);
        powerCaustic += DVec3(p.power);
    }
    ASSERT_GT(countAll, 500);
    const double pooled = (countAll + countCaustic) / (2 * n);
    const double z = (countAll - countCaustic) / n / std::sqrt(pooled * (1 - pooled) * 2 / n);
    EXPECT_LT(std::abs(z), 5.0) << countAll << " against " << countCaustic;
    expectRelativelyNear(powerCaustic / countCaustic, powerAll / countAll, 1e-5);
    // Its own random numbers, and paths that end at their first diffuse hit: fewer rays.
    EXPECT_NE(countAll, countCaustic);
    EXPECT_LT(caustic.rays, all.rays / 2);
}

TEST(PhotonTracer, SameListOnAnyThreadCount) {
    auto cornell = sceneFromJson(exampleScene("cornell-spheres"));
    int before = omp_get_max_threads();
    omp_set_num_threads(1);
    PhotonTracing one = trace(*cornell, 10000);
    omp_set_num_threads(2);
    PhotonTracing two = trace(*cornell, 10000);
    omp_set_num_threads(before);
    ASSERT_EQ(one.photons.size(), two.photons.size());
    for (size_t i = 0; i < one.photons.size(); ++i) {
        ASSERT_EQ(one.photons[i].p, two.photons[i].p) << i;
        ASSERT_EQ(one.photons[i].power, two.photons[i].power) << i;
    }
}

TEST(PhotonTracer, StoredFluxFollowsTheAlbedoInAFurnace) {
    // A closed diffuse sphere of albedo rho lit from its inside. Every path lands first on the
    // wall (a direct photon carrying total / N), then bounces with probability rho (Russian
    // roulette on the throughput change keeps the power): the number K of indirect photons of a
    // path is geometric, P(K = k) = (1 - rho) rho^k (cut at max_depth - 1 = 15, which removes
    // rho^16 = 1.5e-5 of the mean), mean rho / (1 - rho), variance rho / (1 - rho)^2.
    const double rho = 0.5;
    json doc = json::parse(R"({
      "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "width": 4, "height": 4},
      "materials": {"wall": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5],
                             "emission": [1, 2, 3]}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "wall",
                  "flip_normals": true}]
    })");
    auto scene = sceneFromJson(doc);
    const uint64_t n = 200000;
    PhotonTracing t = trace(*scene, n);
    DVec3 direct(0.0), indirect(0.0);
    for (const Photon& p : t.photons) {
        ASSERT_NE(p.path, PhotonPath::Caustic);
        (p.path == PhotonPath::Direct ? direct : indirect) += DVec3(p.power);
    }
    DVec3 total = totalLightPower(*scene);
    expectRelativelyNear(direct, total, 1e-5);
    // Indirect flux / total = mean of K; its standard error sqrt(var / n) = 0.32%: 5 of them.
    double mean = rho / (1 - rho), se = std::sqrt(rho / ((1 - rho) * (1 - rho)) / double(n));
    expectRelativelyNear(indirect, total * mean, 5 * se / mean);
}

}  // namespace
}  // namespace caustic
