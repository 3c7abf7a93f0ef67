// The environment light: its layout and rotation (Mitsuba 3's envmap convention), that its sampling
// matches its density, the photons it emits carry its power, and importance sampling a small sun
// beats uniform sampling of the sphere (issue 38, acceptance 3).
#include "lights/environment_light.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "core/rng.h"
#include "core/sampling.h"
#include "renderer/materials/chi2.h"
#include "support/environment_maps.h"

namespace caustic {
namespace {

using testing::skyWithSun;

Bounds3 unitBox() {
    Bounds3 b;
    b.extend(Vec3(-1.0f));
    b.extend(Vec3(1.0f));
    return b;
}

// An 8 x 4 image bright (1) where u < 1/2 and dark (0) where u >= 1/2, and a top row of 5.
RgbImage halves() {
    RgbImage image{8, 4, std::vector<float>(8 * 4 * 3, 0.0f)};
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 3; ++c)
                image.pixels[3 * size_t(y * 8 + x) + c] = y == 0 ? 5.0f : x < 4 ? 1.0f : 0.0f;
    return image;
}

TEST(EnvironmentLight, LayoutFollowsMitsubasEnvmap) {
    // u = atan2(x, -z) / 2 pi: +x is at u = 1/4 (bright half), -x at 3/4 (dark half); row 0 is +y.
    EnvironmentLight env(halves(), 0.0f, 2.0f, unitBox());
    EXPECT_FLOAT_EQ(env.Le(Vec3(1, 0, 0)).r, 2.0f);
    EXPECT_FLOAT_EQ(env.Le(Vec3(-1, 0, 0)).r, 0.0f);
    EXPECT_FLOAT_EQ(env.Le(Vec3(0, 1, 0)).g, 10.0f);
}

TEST(EnvironmentLight, RotationTurnsTheMapAboutY) {
    // Turned 90 degrees counter-clockwise seen from +y, the map's +x goes to -z.
    EnvironmentLight env(halves(), 90.0f, 1.0f, unitBox());
    EXPECT_FLOAT_EQ(env.Le(Vec3(0, 0, -1)).r, 1.0f);
    EXPECT_FLOAT_EQ(env.Le(Vec3(0, 0, 1)).r, 0.0f);
    EXPECT_NEAR(env.Le(Vec3(1, 0, 0)).r, 0.5f, 1e-5f);  // on the seam between the halves
}

TEST(EnvironmentLight, DensityIntegratesToOneOverTheSphere) {
    EnvironmentLight env(skyWithSun(64, 32, 20, 9, 2, 200.0f), 30.0f, 1.0f, unitBox());
    // Midpoint rule in (cos theta, phi): its cells straddle texel edges, where the density jumps,
    // which leaves an error of a few 1e-4 at this resolution.
    const int n = 2048;
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            const double z = -1.0 + 2.0 * (i + 0.5) / n, phi = kPi * (j + 0.5) / n;
            const double s = std::sqrt(1 - z * z);
            sum += env.pdfDirection(
                Vec3(float(s * std::cos(phi)), float(z), float(s * std::sin(phi))));
        }
    EXPECT_NEAR(sum * (2.0 / n) * (kPi / n), 1.0, 2e-3);
}

// Both densities: the plain one, and the MIS-compensated one (zero over the dim sky).
TEST(EnvironmentLight, SamplingMatchesItsDensity) {
    const double significance = testing::chi2Significance(4);
    for (bool compensated : {false, true})
        for (float rotation : {0.0f, 75.0f}) {
            EnvironmentLight env(skyWithSun(64, 32, 20, 9, 4, 50.0f), rotation, 1.0f, unitBox());
            const testing::Chi2Result r = testing::chi2Test(
                [&](Vec2 u, float) -> std::optional<Vec3> {
                    auto s = compensated ? env.sampleLiCompensated(Vec3(0.0f), u)
                                         : env.sampleLi(Vec3(0.0f), u);
                    if (!s) return std::nullopt;
                    EXPECT_NEAR(s->pdf, env.pdfDirection(s->wi, compensated), 1e-4f * s->pdf);
                    return s->wi;
                },
                [&](const Vec3& w) { return double(env.pdfDirection(w, compensated)); }, 400000);
            EXPECT_NEAR(r.pdfIntegral, r.sampledFraction, 4e-3) << r.summary;
            EXPECT_GT(r.pValue, significance) << (compensated ? "compensated, " : "") << "rotation "
                                              << rotation << ": " << r.summary;
        }
}

TEST(EnvironmentLight, PhotonsCarryItsPower) {
    for (bool image : {false, true}) {
        EnvironmentLight env =
            image ? EnvironmentLight(skyWithSun(64, 32, 20, 9, 4, 50.0f), 10.0f, 1.0f, unitBox())
                  : EnvironmentLight(Color(0.5f, 1.0f, 2.0f), unitBox());
        Rng rng = Rng::forSample(3, 0, 0, 0);
        DVec3 sum(0.0);
        const int n = 400000;
        for (int i = 0; i < n; ++i) {
            auto le = env.sampleLe(rng.uniform2(), rng.uniform2());
            // None where the density rounds to zero: there is no light there either.
            if (!le) continue;
            // The photon starts outside the scene's bounding sphere and heads into it.
            ASSERT_GE(glm::length(le->ray.o), std::sqrt(3.0f) * 0.999f);
            sum += DVec3(le->power);
        }
        // The power() of an image sums its texels; photons see its bilinear interpolation.
        const Color mean(sum / double(n));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], env.power()[c], (image ? 0.02f : 1e-4f) * env.power()[c])
                << (image ? "image" : "constant") << " channel " << c;
    }
}

// Issue 38, acceptance 3: the irradiance on an upward-facing point from a sky with a small, bright
// sun, estimated from 16 directions by importance sampling and by uniform sampling of the sphere.
TEST(EnvironmentLight, ImportanceSamplingASmallSunBeatsUniformSampling) {
    EnvironmentLight env(skyWithSun(256, 128, 40, 40, 2, 5000.0f), 0.0f, 1.0f, unitBox());
    const Vec3 n(0.0f, 1.0f, 0.0f);
    auto importance = [&](Rng& rng) {
        auto s = env.sampleLi(Vec3(0.0f), rng.uniform2());
        return s ? double(luminance(s->Li)) * std::max(0.0f, glm::dot(s->wi, n)) / s->pdf : 0.0;
    };
    auto uniform = [&](Rng& rng) {
        const Vec3 w = sampleUniformSphere(rng.uniform2());
        return double(luminance(env.Le(w))) * std::max(0.0f, glm::dot(w, n)) / kUniformSpherePdf;
    };
    // The reference: 4M importance samples (their standard error is under 0.1% of E).
    Rng refRng = Rng::forSample(4, 0, 0, 0);
    double reference = 0.0;
    const int referenceSamples = 1 << 22;
    for (int i = 0; i < referenceSamples; ++i) reference += importance(refRng);
    reference /= referenceSamples;

    const int spp = 16, trials = 4000;
    double mse[2] = {0, 0}, mean[2] = {0, 0}, meanSq[2] = {0, 0};
    for (int method = 0; method < 2; ++method) {
        Rng rng = Rng::forSample(5 + method, 0, 0, 0);
        for (int t = 0; t < trials; ++t) {
            double e = 0.0;
            for (int s = 0; s < spp; ++s) e += method == 0 ? importance(rng) : uniform(rng);
            e /= spp;
            mse[method] += (e - reference) * (e - reference) / trials;
            mean[method] += e / trials;
            meanSq[method] += e * e / trials;
        }
    }
    const double ratio = mse[1] / mse[0];
    std::printf(
        "environment sampling, sun map, %d spp: MSE uniform %.4g, importance %.4g, "
        "ratio %.1f (E = %.4f)\n",
        spp, mse[1], mse[0], ratio, reference);
    EXPECT_GE(ratio, 5.0);
    // Both converge to the same irradiance: each mean within 5 standard errors of the reference.
    for (int method = 0; method < 2; ++method) {
        const double se = std::sqrt((meanSq[method] - mean[method] * mean[method]) / trials);
        EXPECT_NEAR(mean[method], reference, 5.0 * se + 1e-3 * reference)
            << (method == 0 ? "importance" : "uniform");
    }
}

}  // namespace
}  // namespace caustic
