// Materials: specular lobes of Dielectric and Mirror, Diffuse's BSDF and sampling, and the
// statistics of sampling against their expected values.
#include "materials/material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/rng.h"
#include "core/sampling.h"
#include "materials/dielectric.h"
#include "materials/diffuse.h"
#include "materials/fresnel.h"
#include "materials/mirror.h"

namespace caustic {
namespace {

/// One float ulp at 1 (2^-23); tolerances below are multiples of it.
constexpr double kEps = std::numeric_limits<float>::epsilon();

/// A tilted unit normal, so that no test relies on axis-aligned arithmetic.
const Vec3 kNormal = glm::normalize(Vec3(-0.2f, 0.6f, 0.7f));

/// The unit direction at cos theta = c from kNormal (negative c: below it), in a fixed plane.
Vec3 directionAt(double c) {
    Vec3 t, b;
    coordinateSystem(kNormal, t, b);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    return Vec3(DVec3(t) * s + DVec3(kNormal) * c);
}

const double kCosines[] = {1.0, 0.9, 0.7, 0.5, 0.3, 0.1, 0.01, -0.01, -0.3, -0.5, -0.7, -0.9, -1.0};

}  // namespace

TEST(Dielectric, IndexOneTransmitsStraightThroughWithWeightOne) {
    // No interface: no reflection lobe, one transmission lobe with weight exactly (1 - 0) * 1 / 1,
    // along -wo up to normalization's rounding (an ulp or two per component).
    const Dielectric glass(1.0f, FresnelModel::Exact, Color(1.0f), Color(0.0f));
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
        for (double c : kCosines) {
            const Vec3 wo = directionAt(c);
            SpecularLobe lobes[2];
            ASSERT_EQ(glass.specularLobes(wo, kNormal, mode, lobes), 1) << "cos " << c;
            EXPECT_EQ(lobes[0].weight, Color(1.0f)) << "cos " << c;
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(lobes[0].wi[k], -wo[k], 1e-6) << "cos " << c;
            // sample() then always refracts, with probability 1 and weight 1.
            auto s = glass.sample(wo, kNormal, 0.999f, Vec2(0.5f), mode);
            ASSERT_TRUE(s.has_value());
            EXPECT_EQ(s->wi, lobes[0].wi);
            EXPECT_EQ(s->pdf, 1.0f);
            EXPECT_EQ(s->weight, Color(1.0f));
        }
    }
}

TEST(Dielectric, LobeWeightsConserveEnergy) {
    // Radiance: R + T' eta_path^2 = 1, where T' = (1 - R) / eta_path^2 is the transmitted radiance
    // weight. Importance: R + T = 1 with no 1/eta^2. Float rounds 1 - R and the division by
    // eta_path^2 (half an ulp each), and its eta_path = 1/ior differs from the double one here by
    // half an ulp, an ulp once squared: 4 ulps.
    for (float ior : {1.33f, 1.5f, 2.4f}) {
        const Dielectric glass(ior, FresnelModel::Exact, Color(1.0f), Color(0.0f));
        for (double c : kCosines) {
            const Vec3 wo = directionAt(c);
            const bool outside = glm::dot(wo, kNormal) > 0.0f;
            const double etaPath = outside ? ior : 1.0 / ior;
            SpecularLobe rad[2], imp[2];
            const int count = glass.specularLobes(wo, kNormal, TransportMode::Radiance, rad);
            ASSERT_EQ(glass.specularLobes(wo, kNormal, TransportMode::Importance, imp), count);
            ASSERT_GE(count, 1);
            // Lobe 0 reflects (wi on wo's side) with weight R in both modes.
            const double r = glass.reflectance(wo, kNormal);
            EXPECT_GT(glm::dot(rad[0].wi, kNormal) * glm::dot(wo, kNormal), 0.0f);
            EXPECT_EQ(rad[0].weight, Color(static_cast<float>(r)));
            EXPECT_EQ(imp[0].weight, rad[0].weight);
            if (count == 1) {
                EXPECT_EQ(r, 1.0) << "only total internal reflection drops the transmission";
                continue;
            }
            for (int k = 0; k < 3; ++k) {
                EXPECT_NEAR(r + rad[1].weight[k] * etaPath * etaPath, 1.0, 4.0 * kEps)
                    << "ior " << ior << " cos " << c;
                EXPECT_NEAR(r + imp[1].weight[k], 1.0, 4.0 * kEps) << "ior " << ior << " cos " << c;
            }
            EXPECT_EQ(imp[1].wi, rad[1].wi);
        }
    }
}

TEST(Dielectric, SampleChoosesReflectionWithProbabilityR) {
    // The number of reflections in N samples is binomial(N, R): |z| < 4 fails by chance with
    // probability 6e-5 per case, and the seed is fixed.
    const int n = 200000;
    struct Case {
        float ior;
        FresnelModel model;
        double cosO;
    };
    for (Case k :
         {Case{1.5f, FresnelModel::Exact, 0.95}, Case{1.5f, FresnelModel::Exact, 0.1},
          Case{1.5f, FresnelModel::Exact, -0.8}, Case{1.33f, FresnelModel::Exact, 0.02},
          Case{2.4f, FresnelModel::Schlick, 0.3}, Case{1.5f, FresnelModel::Schlick, -0.9}}) {
        const Dielectric glass(k.ior, k.model, Color(1.0f), Color(0.0f));
        const Vec3 wo = directionAt(k.cosO);
        const double r = glass.reflectance(wo, kNormal);
        const double etaPath = k.cosO > 0.0 ? k.ior : 1.0 / k.ior;
        Rng rng(1234);
        int reflections = 0;
        for (int i = 0; i < n; ++i) {
            auto s =
                glass.sample(wo, kNormal, rng.uniform(), rng.uniform2(), TransportMode::Radiance);
            ASSERT_TRUE(s.has_value());
            ASSERT_TRUE(s->specular);
            const bool reflected = glm::dot(s->wi, kNormal) * glm::dot(wo, kNormal) > 0.0f;
            reflections += reflected;
            // Each branch's weight is its lobe weight over its probability: 1 for reflection,
            // 1 / eta_path^2 for refraction (tint 1), up to a few roundings.
            const double expected = reflected ? 1.0 : 1.0 / (etaPath * etaPath);
            ASSERT_NEAR(s->weight.r, expected, 8.0 * kEps * expected);
            ASSERT_NEAR(s->pdf, reflected ? r : 1.0 - r, 4.0 * kEps);
        }
        const double z = (reflections - n * r) / std::sqrt(n * r * (1.0 - r));
        EXPECT_LT(std::abs(z), 4.0) << "ior " << k.ior << " cos " << k.cosO << " R " << r;
    }
}

TEST(Mirror, ReflectsAboutNormalWithReflectanceWeight) {
    const Color reflectance(0.9f, 0.5f, 0.2f);
    const Mirror mirror(reflectance, Color(0.0f));
    for (double c : kCosines) {
        const Vec3 wo = directionAt(c);
        SpecularLobe lobes[2];
        ASSERT_EQ(mirror.specularLobes(wo, kNormal, TransportMode::Radiance, lobes), 1);
        const Vec3 wi = lobes[0].wi;
        EXPECT_EQ(lobes[0].weight, reflectance);
        // Same angle to n, same side, and wo + wi along n: each to a few ulps of a unit vector.
        EXPECT_NEAR(glm::dot(wi, kNormal), glm::dot(wo, kNormal), 1e-6) << "cos " << c;
        EXPECT_NEAR(glm::length(glm::cross(wo + wi, kNormal)), 0.0, 1e-6) << "cos " << c;
        EXPECT_NEAR(glm::length(wi), 1.0, 1e-6) << "cos " << c;

        auto s = mirror.sample(wo, kNormal, 0.5f, Vec2(0.5f), TransportMode::Radiance);
        ASSERT_TRUE(s.has_value());
        EXPECT_EQ(s->wi, wi);
        EXPECT_EQ(s->weight, reflectance);
        EXPECT_EQ(s->pdf, 1.0f);
        EXPECT_TRUE(s->specular);
        const float cosI = std::abs(glm::dot(wi, kNormal));
        for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(s->f[k] * cosI, reflectance[k]);
    }
}

TEST(Diffuse, SampleWeightPdfAndValueAgree) {
    const Color albedo(0.8f, 0.4f, 0.1f);
    const Diffuse diffuse(albedo, Color(0.0f));
    Rng rng(99);
    for (double c : kCosines) {
        const Vec3 wo = directionAt(c);
        const float cosO = glm::dot(wo, kNormal);
        for (int i = 0; i < 1000; ++i) {
            auto s =
                diffuse.sample(wo, kNormal, rng.uniform(), rng.uniform2(), TransportMode::Radiance);
            ASSERT_TRUE(s.has_value());
            EXPECT_FALSE(s->specular);
            EXPECT_EQ(s->weight, albedo);
            EXPECT_GT(glm::dot(s->wi, kNormal) * cosO, 0.0f) << "wi on wo's side";
            // pdf() recomputes cos theta from the world-space wi, which differs from the local
            // z by a few ulps of the unit vector: relative 1e-5, floor 1e-6 (grazing samples).
            const float pdf = diffuse.pdf(wo, s->wi, kNormal);
            EXPECT_NEAR(s->pdf, pdf, 1e-5 * pdf + 1e-6);
            EXPECT_EQ(s->f, diffuse.f(wo, s->wi, kNormal));
        }
    }
}

TEST(Diffuse, ValueIsAlbedoOverPiOnSameSideOnly) {
    const Color albedo(0.8f, 0.4f, 0.1f);
    const Diffuse diffuse(albedo, Color(0.0f));
    for (double co : kCosines) {
        for (double ci : kCosines) {
            const Vec3 wo = directionAt(co), wi = directionAt(ci);
            const bool sameSide = co * ci > 0.0;
            EXPECT_EQ(diffuse.f(wo, wi, kNormal), sameSide ? albedo * kInvPi : Color(0.0f))
                << "cos o " << co << " cos i " << ci;
            EXPECT_EQ(diffuse.pdf(wo, wi, kNormal) > 0.0f, sameSide);
        }
    }
}

TEST(Diffuse, MonteCarloReflectanceEqualsAlbedo) {
    // Integral of f |cos i| over the sphere with uniform sphere samples (independent of Diffuse's
    // own cosine sampling; directions across the surface contribute 0). Mean within 4 standard
    // errors of the albedo, the standard error estimated from the samples themselves. With 2^22
    // samples that is about 0.06% of the albedo, so a 0.5% error in f fails.
    const Color albedo(0.8f, 0.4f, 0.1f);
    const Diffuse diffuse(albedo, Color(0.0f));
    for (double c : {0.8, 0.05, -0.6}) {
        const Vec3 wo = directionAt(c);
        Rng rng(2024);
        const int n = 1 << 22;
        DVec3 sum(0.0), sum2(0.0);
        for (int i = 0; i < n; ++i) {
            const Vec3 wi = sampleUniformSphere(rng.uniform2());
            const DVec3 x = DVec3(diffuse.f(wo, wi, kNormal)) *
                            double(std::abs(glm::dot(wi, kNormal)) / kUniformSpherePdf);
            sum += x;
            sum2 += x * x;
        }
        for (int k = 0; k < 3; ++k) {
            const double mean = sum[k] / n;
            const double stdErr = std::sqrt((sum2[k] / n - mean * mean) / (n - 1));
            EXPECT_NEAR(mean, albedo[k], 4.0 * stdErr) << "channel " << k << " cos " << c;
        }
    }
}

}  // namespace caustic
