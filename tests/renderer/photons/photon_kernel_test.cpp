// Photon density-estimate kernels and the photon integrator: a single photon traces each
// kernel's profile, a uniform field gives the irradiance for every kernel (normalization and
// shape), and the integrator adds nothing to direct light where the photon maps hold nothing to
// add. The statistics follow photon_estimate_test.cpp's header.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "core/rng.h"
#include "materials/diffuse.h"
#include "photon_estimate_support.h"
#include "photons/photon_kdtree.h"
#include "photons/photon_map.h"
#include "photons/photon_tracer.h"
#include "support/point_light_plane.h"
#include "support/region_stats.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using namespace estimate_test;  // kernels, plane points, thresholds
using nlohmann::json;
using testing::pointLightOverPlane;
using testing::sceneFromJson;
using testing::settingsFrom;
using testing::twoSidedNormalQuantile;

TEST(PhotonEstimate, OnePhotonTracesTheKernelProfile) {
    const float r = 0.5f;
    const Color power(1.0f, 2.0f, 0.5f);
    Diffuse plane(kAlbedo, Color(0.0f));
    std::vector<Neighbor> scratch;
    SurfaceInteraction si = planePoint(0.0, 0.0);
    // Axis-aligned offsets, so d^2 is exact in float (d = r lies exactly on the rim).
    const std::vector<Vec3> offsets = {Vec3(0.0f),         Vec3(0.125f, 0, 0),
                                       Vec3(0, 0, -0.25f), Vec3(-0.375f, 0, 0),
                                       Vec3(0, 0, 0.5f),   Vec3(0.5001f, 0, 0)};
    for (const Vec3& o : offsets) {
        PhotonMap map({Photon{o, kUp, power, PhotonPath::Direct, 0}});
        double d = glm::length(DVec3(o));
        for (int k = 0; k < 3; ++k) {
            Color L = map.reflected(si, kUp, plane, PhotonEstimate{1, r, kKernels[k]},
                                    kAllPhotonPaths, scratch);
            double K = d <= r ? kernelValue(kKernels[k], d, r) : 0.0;
            for (int c = 0; c < 3; ++c) {
                double expected = kAlbedo[c] / kPiD * power[c] * K;
                EXPECT_NEAR(L[c], expected, 1e-6 * expected + 1e-12)
                    << kKernelNames[k] << " at d = " << d << " channel " << c;
            }
            // k nearest with k = 1: the radius is the photon's own distance, where the cone and
            // Simpson kernels are 0 and the box is 1 / (pi d^2) (the source of the box's k / (k -
            // 1) bias below). At d = 0 there is no disk: 0.
            if (d > 0.0) {
                Color Lk = map.reflected(si, kUp, plane, PhotonEstimate{1, 0.0f, kKernels[k]},
                                         kAllPhotonPaths, scratch);
                double Kk = kernelValue(kKernels[k], d, d);
                for (int c = 0; c < 3; ++c) {
                    double expected = kAlbedo[c] / kPiD * power[c] * Kk;
                    EXPECT_NEAR(Lk[c], expected, 1e-6 * expected + 1e-12)
                        << kKernelNames[k] << " k = 1 at d = " << d << " channel " << c;
                }
            }
        }
    }
}

// Normalization in a uniform field: N photons of power Phi uniform on a square of area A give
// irradiance E = N Phi / A, and the expected estimate away from the edges is rho / pi * E exactly,
// whatever the (normalized) kernel, for a fixed radius. For the k nearest, pi R^2 / A is
// Beta(k, N - k + 1) distributed (while the disk stays inside the square), so E[1 / (pi R^2)] =
// lambda / (k - 1) exactly (lambda = N / A): cone and Simpson (zero weight on the k-th photon) are
// unbiased, the box is k / (k - 1) high. Variances, in units of (rho / pi E)^2, with c = pi r^2 int
// K^2 = 1, 3/2, 9/5: fixed c / (lambda pi r^2) - 1 / N (from (2)); k nearest c / (k - 2) for cone
// and Simpson, k^2 / ((k - 1)^2 (k - 2)) for the box (inverse-gamma moments, to O(1/N)).
TEST(PhotonEstimate, UniformFieldGivesTheIrradianceForEveryKernel) {
    const uint32_t n = 1u << 20;
    const double area = 4.0, lambda = n / area;  // photons on [-1, 1]^2
    const Color irradiance(1.0f, 2.0f, 0.5f);
    const Color power = irradiance * float(area / n);
    std::vector<Photon> photons(n);
    Rng rng(12345);
    for (Photon& p : photons) {
        Vec2 u = rng.uniform2();
        p = Photon{Vec3(2.0f * u.x - 1.0f, 0.0f, 2.0f * u.y - 1.0f), kUp, power, PhotonPath::Direct,
                   0};
    }
    PhotonMap map(std::move(photons));
    Diffuse plane(kAlbedo, Color(0.0f));
    std::vector<Neighbor> scratch;

    // 100 x 100 points 0.0192 apart, 0.95 from the middle: disjoint disks of radius 0.009 (~67
    // photons) and of the k = 20 nearest (R ~ 0.005), all well inside the square.
    const std::vector<Vec2> points = grid(0.0, 0.0, 0.95, 100);
    const float r = 0.009f;
    const int k = 20;
    const double c[3] = {1.0, 1.5, 1.8};
    const size_t checks = 3 * 2;
    const double z = twoSidedNormalQuantile(kFamilyWiseFalseAlarm / double(checks));
    for (int kk = 0; kk < 3; ++kk) {
        for (bool knn : {false, true}) {
            PhotonEstimate estimate{k, knn ? 0.0f : r, kKernels[kk]};
            double sum = 0.0, sumSq = 0.0;
            for (Vec2 x : points) {
                Color L = map.reflected(planePoint(x.x, x.y), kUp, plane, estimate, kAllPhotonPaths,
                                        scratch);
                // In units of rho / pi E: the same in every channel but for float rounding.
                double v = L[0] / (kAlbedo[0] / kPiD * irradiance[0]);
                for (int ch = 1; ch < 3; ++ch)
                    EXPECT_NEAR(L[ch] / (kAlbedo[ch] / kPiD * irradiance[ch]), v, 1e-5 * v);
                sum += v;
                sumSq += v * v;
            }
            const double m = double(points.size());
            const double mean = sum / m, s2 = (sumSq - m * mean * mean) / (m - 1.0);
            double expected = 1.0, var = c[kk] / (lambda * kPiD * r * r) - 1.0 / n;
            if (knn) {
                bool box = kKernels[kk] == PhotonKernel::Box;
                expected = box ? double(k) / (k - 1) : 1.0;
                var = box ? double(k) * k / ((k - 1.0) * (k - 1.0) * (k - 2.0)) : c[kk] / (k - 2.0);
            }
            // Disjoint disks: independent but for the multinomial's slight negative correlation,
            // which makes the standard error of the mean over points conservative.
            const double se = std::sqrt(var / m);
            char text[160];
            std::snprintf(text, sizeof text,
                          "%s %s: mean %.5f, expected %.5f +- %.5f, spread / predicted %.3f",
                          kKernelNames[kk], knn ? "k nearest" : "fixed radius", mean, expected, se,
                          s2 / var);
            ::testing::Test::RecordProperty(
                std::string(kKernelNames[kk]) + (knn ? "_knn" : "_fixed"), text);
            EXPECT_NEAR(mean, expected, z * se + kRounding) << text;
            // The spread over the points follows the predicted variance, which depends on the
            // kernel's shape through int K^2 (sd of the ratio ~0.02 over 10^4 points, with the
            // box's inverse-gamma kurtosis).
            EXPECT_NEAR(s2 / var, 1.0, 0.1) << text;
            if (knn && kKernels[kk] == PhotonKernel::Box) {
                EXPECT_GT(std::abs(mean - 1.0), z * se)
                    << "the box's k / (k - 1) bias shows: " << text;
            }
        }
    }
}

// The photon integrator over the known-answer scene (known_answer_test.cpp): a single diffuse plane
// under a point light. Direct light comes from light samples, not photons; the caustic map is
// empty (no specular surface) and the global map holds only direct photons, which the indirect
// lookup masks out. So the image must be exactly raycast's (same camera and light samples, photon
// terms exactly 0): any spurious light from the photon maps shows. And each pixel matches the
// analytic pixel average within 5 standard errors, as in known_answer_test.
TEST(PhotonEstimate, PhotonIntegratorAddsNothingToDirectLightOnAPlane) {
    auto scene = sceneFromJson(pointLightOverPlane(48, 32));
    // 10^4 photons a pass and radius 0.15: ~56 direct photons in a lookup disk at the light's
    // foot, ~2 at the far edge of the view, so the masks really have photons to reject.
    json photon = {{"integrator", "photon"}, {"spp", 64}, {"photons", 10000},
                   {"radius", 0.15},         {"k", 50},   {"kernel", "box"}};
    RenderResult r = render(*scene, settingsFrom(photon));
    RenderResult ref = render(*scene, settingsFrom({{"integrator", "raycast"}, {"spp", 64}}));
    const Film& film = *r.film;
    ASSERT_EQ(film.passes(), 64);
    EXPECT_GT(r.stats.memory.photonMaps, 0u) << "photons were traced";
    std::vector<float> a = film.meanRgb(), b = ref.film->meanRgb();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0)
        << "photon and raycast images differ";
    double worst = 0;
    EXPECT_EQ(testing::pixelsOffTheAnalyticValue(film, scene->camera, worst), 0)
        << "largest error / tolerance: " << worst;
    EXPECT_EQ(r.stats.droppedSamples, 0u);
}

}  // namespace
}  // namespace caustic
