// The GGX distribution: its normalization, Smith's masking against the closed form, and the
// sampling of visible normals against their density (chi-square).
#include "materials/ggx.h"

#include <gtest/gtest.h>

#include "renderer/materials/chi2.h"

namespace caustic {
namespace {

// The unit direction at polar angle theta (degrees) and azimuth phi (radians).
Vec3 direction(double thetaDegrees, double phi = 0.3) {
    const double t = thetaDegrees * M_PI / 180.0;
    return Vec3(float(std::sin(t) * std::cos(phi)), float(std::sin(t) * std::sin(phi)),
                float(std::cos(t)));
}

// int f over the hemisphere z > 0, by the midpoint rule in (theta, phi): fine enough in theta
// for the narrowest lobe tested (alpha 0.1) to be resolved at the pole.
template <class F>
double hemisphereIntegral(F f, int n = 2000) {
    double sum = 0.0;
    const double dTheta = 0.5 * M_PI / n, dPhi = 2.0 * M_PI / 400;
    for (int i = 0; i < n; ++i) {
        const double theta = (i + 0.5) * dTheta, s = std::sin(theta), z = std::cos(theta);
        for (int j = 0; j < 400; ++j) {
            const double phi = (j + 0.5) * dPhi;
            sum += s * f(Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)));
        }
    }
    return sum * dTheta * dPhi;
}

const Ggx kWidths[] = {Ggx(0.1f, 0.1f), Ggx(0.5f, 0.5f), Ggx(1.0f, 1.0f), Ggx(0.2f, 0.7f)};

}  // namespace

TEST(Ggx, ProjectedNormalsAndVisibleNormalsIntegrateToOne) {
    for (const Ggx& ggx : kWidths) {
        SCOPED_TRACE(::testing::Message() << "alpha " << ggx.alphaX() << ", " << ggx.alphaY());
        EXPECT_NEAR(hemisphereIntegral([&](const Vec3& wm) { return ggx.D(wm) * wm.z; }), 1.0,
                    2e-3);
        for (double theta : {0.0, 45.0, 80.0}) {
            const Vec3 wo = direction(theta);
            EXPECT_NEAR(hemisphereIntegral([&](const Vec3& wm) { return ggx.visibleD(wo, wm); }),
                        1.0, 2e-3)
                << "theta " << theta;
        }
    }
}

TEST(Ggx, SmithMaskingMatchesTheIsotropicClosedForm) {
    // G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2 theta)) (Walter et al. 2007, eq. 34).
    for (float alpha : {0.05f, 0.3f, 1.0f})
        for (double theta : {0.0, 30.0, 60.0, 89.0}) {
            const Ggx ggx(alpha, alpha);
            const double tan2 = std::pow(std::tan(theta * M_PI / 180.0), 2);
            const double g1 = 2.0 / (1.0 + std::sqrt(1.0 + alpha * alpha * tan2));
            EXPECT_NEAR(ggx.G1(direction(theta, 1.1)), g1, 1e-5) << alpha << " " << theta;
        }
    EXPECT_EQ(Ggx(0.5f, 0.5f).G1(Vec3(1.0f, 0.0f, 0.0f)), 0.0f);  // grazing: fully masked
}

TEST(Ggx, VisibleNormalSamplingMatchesItsDensity) {
    const int tests = 4 * 4;
    const double significance = testing::chi2Significance(tests);
    for (const Ggx& ggx : kWidths)
        for (double theta : {0.0, 30.0, 60.0, 85.0}) {
            const Vec3 wo = direction(theta);
            const testing::Chi2Result r = testing::chi2Test(
                [&](Vec2 u, float) -> std::optional<Vec3> { return ggx.sampleVisible(wo, u); },
                [&](const Vec3& wm) { return double(ggx.visibleD(wo, wm)); });
            EXPECT_GT(r.pValue, significance) << "alpha " << ggx.alphaX() << ", " << ggx.alphaY()
                                              << ", theta " << theta << ": " << r.summary;
        }
}

}  // namespace caustic
