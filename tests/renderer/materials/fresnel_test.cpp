// Fresnel reflectance, Schlick's approximation and refraction against double-precision references
// written from the textbook formulas (Hecht, Optics, 4th ed., section 4.6), not from fresnel.cpp.
#include "materials/fresnel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace caustic {
namespace {

/// One float ulp at 1 (2^-23); tolerances below are multiples of it.
constexpr double kEps = std::numeric_limits<float>::epsilon();
constexpr double kHalfPi = 1.57079632679489661923;

/// The sweep: kAngles incidence angles evenly spaced over [0, 90] degrees, kEtas indices evenly
/// spaced over [1, 4] (eta = 1 is the first of them).
constexpr int kAngles = 2000;
constexpr int kEtas = 100;
float sweepCos(int i) {
    return static_cast<float>(std::cos(kHalfPi * i / (kAngles - 1)));
}
float sweepEta(int j, double maxEta) {
    return static_cast<float>(1.0 + (maxEta - 1.0) * j / (kEtas - 1));
}

struct Interface {
    double r;  ///< Unpolarized reflectance.
    double t;  ///< Unpolarized transmittance.
};

/// Exact reflectance and transmittance from the s- and p-polarized amplitude coefficients (Hecht
/// 4.6.2-4.6.3), in double; cosI and eta follow fresnelDielectric's convention. `shift` moves
/// cos^2(theta_t), to measure how sensitive R is to rounding there (see fresnelTolerance).
Interface exactFresnel(double cosI, double eta, double shift = 0.0) {
    if (cosI < 0.0) {
        eta = 1.0 / eta;
        cosI = -cosI;
    }
    // Snell: cos^2 t = 1 - sin^2 i / eta^2, written without the cancellation in 1 - sin^2 i.
    double cos2T = (cosI * cosI + (eta * eta - 1.0)) / (eta * eta) + shift;
    if (cos2T <= 0.0) return {1.0, 0.0};
    double cosT = std::sqrt(cos2T);
    double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    double ts = 2.0 * cosI / (cosI + eta * cosT);
    double tp = 2.0 * cosI / (eta * cosI + cosT);
    // Transmitted power scales by the ratio of beam cross-sections and of impedances (Hecht 4.6.3).
    double t = cosI > 0.0 ? eta * cosT / cosI * 0.5 * (ts * ts + tp * tp) : 0.0;
    return {0.5 * (rs * rs + rp * rp), t};
}

/// The error to expect from fresnelDielectric(cosI, eta) in float. Its rounding leaves cos^2 t off
/// by a few ulps of max(1, 1/eta'^2) (eta' the ratio after flipping to the incident side; the
/// division by eta'^2 scales the ulps of 1 - cos^2 i), and dR/d(cos^2 t) grows like 1/cos t towards
/// the critical angle. So: the change of the exact R under an 8-ulp shift of cos^2 t, plus 16 ulps
/// for the remaining ~15 operations on quantities below 1.
double fresnelTolerance(double cosI, double eta) {
    double etaI = cosI < 0.0 ? 1.0 / eta : eta;
    double delta = 8.0 * kEps * std::max(1.0, 1.0 / (etaI * etaI));
    double r = exactFresnel(cosI, eta).r;
    double up = std::abs(exactFresnel(cosI, eta, delta).r - r);
    double down = std::abs(exactFresnel(cosI, eta, -delta).r - r);
    return std::max(up, down) + 16.0 * kEps;
}

/// Schlick's formula in double with the cosine it should use, or 1 under total internal reflection.
double exactSchlick(double cosI, double eta, double shift = 0.0) {
    double r0 = (eta - 1.0) / (eta + 1.0);
    r0 *= r0;
    double cosine = cosI;
    if (cosI < 0.0) {
        // Inside (the relative index is 1/eta): use the transmitted angle, Snell as above.
        double cos2T = cosI * cosI * eta * eta + (1.0 - eta * eta) + shift;
        if (cos2T <= 0.0) return 1.0;
        cosine = std::sqrt(cos2T);
    }
    return r0 + (1.0 - r0) * std::pow(1.0 - cosine, 5.0);
}

}  // namespace

TEST(Fresnel, NormalIncidenceGlassIsFourPercent) {
    // ((1.5 - 1) / (1.5 + 1))^2 = 0.04. About ten float operations, each rounding by at most half
    // an ulp of a value below 1, so 8 ulps relative.
    const double expected = std::pow((1.5 - 1.0) / (1.5 + 1.0), 2.0);
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.5f), expected, 8.0 * kEps * expected);
    EXPECT_NEAR(fresnelDielectric(-1.0f, 1.5f), expected, 8.0 * kEps * expected);
}

TEST(Fresnel, FortyFiveDegreesAirToGlass) {
    const float cos45 = static_cast<float>(std::cos(kHalfPi / 2.0));
    const double expected = exactFresnel(cos45, 1.5).r;
    // The reference itself against the value worked by hand from Hecht's formulas:
    // R_s = 0.092014, R_p = 0.008466, R = 0.050240 (to the 6 digits written here).
    EXPECT_NEAR(expected, 0.050240, 1e-6);
    EXPECT_NEAR(fresnelDielectric(cos45, 1.5f), expected, fresnelTolerance(cos45, 1.5));
}

TEST(Fresnel, TotalInternalReflectionBeyondCriticalAngleIsExactlyOne) {
    // Glass to air: critical angle asin(1/1.5) = 41.8 degrees. Angles are at least 3 degrees past
    // it, far beyond float rounding, so the result must be exactly 1.
    const double degree = kHalfPi / 90.0;
    for (double deg : {45.0, 60.0, 75.0, 89.0, 90.0}) {
        float cosI = -static_cast<float>(std::cos(deg * degree));
        EXPECT_EQ(fresnelDielectric(cosI, 1.5f), 1.0f) << deg << " degrees";
    }
    // And just inside it, partial reflection.
    EXPECT_LT(fresnelDielectric(-static_cast<float>(std::cos(40.0 * degree)), 1.5f), 1.0f);
}

TEST(Fresnel, ReflectancePlusTransmittanceIsOneOverSweep) {
    // R from fresnelDielectric, T from the transmission amplitudes in double: R + T = 1 checks R
    // against an independent derivation. Tolerance per point from fresnelTolerance.
    double worst = 0.0;
    for (int j = 0; j < kEtas; ++j) {
        const float eta = sweepEta(j, 4.0);
        for (int i = 0; i < kAngles; ++i) {
            for (float cosI : {sweepCos(i), -sweepCos(i)}) {
                const float r = fresnelDielectric(cosI, eta);
                ASSERT_GE(r, 0.0f) << "cos " << cosI << " eta " << eta;
                ASSERT_LE(r, 1.0f) << "cos " << cosI << " eta " << eta;
                const double t = exactFresnel(cosI, eta).t;
                ASSERT_NEAR(r + t, 1.0, fresnelTolerance(cosI, eta))
                    << "cos " << cosI << " eta " << eta;
                worst = std::max(worst, std::abs(r + t - 1.0));
            }
        }
    }
    RecordProperty("max_abs_R_plus_T_minus_1", std::to_string(worst));
}

TEST(Fresnel, IndexMatchedInterfaceDoesNotReflect) {
    // Without an interface every amplitude ratio vanishes. R is a square of such ratios, so a few
    // ulps of error in each leaves R below 1e-12; any real reflection is many orders larger.
    // Grazing angles down to cos = 1e-6 included; cos = 0 exactly (0/0 in every ratio) is not.
    std::vector<float> cosines = {1e-6f, 1e-5f, 1e-4f, 1e-3f};
    for (int i = 0; i < kAngles; ++i) cosines.push_back(sweepCos(i));
    for (float c : cosines) {
        EXPECT_LE(fresnelDielectric(c, 1.0f), 1e-12f) << "cos " << c;
        EXPECT_LE(fresnelDielectric(-c, 1.0f), 1e-12f) << "cos " << -c;
    }
}

TEST(Fresnel, ReflectanceIsSymmetricAcrossInterface) {
    // Light from outside at theta_i refracts to theta_t; from inside at theta_t it reflects as much
    // as from outside at theta_i (Stokes relations). Both evaluations carry their own tolerance;
    // the inside one also covers rounding cos theta_t to float (a shift of cos^2 below one ulp *
    // eta^2).
    for (int j = 0; j < kEtas; ++j) {
        const float eta = sweepEta(j, 4.0);
        for (int i = 0; i < kAngles; ++i) {
            const float cosI = sweepCos(i);
            const double sinT = std::sqrt(std::max(0.0, 1.0 - double(cosI) * cosI)) / eta;
            const float cosT = static_cast<float>(std::sqrt(1.0 - sinT * sinT));
            ASSERT_NEAR(fresnelDielectric(-cosT, eta), fresnelDielectric(cosI, eta),
                        fresnelTolerance(-cosT, eta) + fresnelTolerance(cosI, eta))
                << "cos " << cosI << " eta " << eta;
        }
    }
}

TEST(Schlick, MatchesFormulaFromLessDenseSide) {
    // Same formula in double from the same float inputs; ~10 float operations on values below 1,
    // each rounding by at most half an ulp, so 8 ulps absolute.
    for (int j = 0; j < kEtas; ++j) {
        const float eta = sweepEta(j, 4.0);
        for (int i = 0; i < kAngles; ++i) {
            const float c = sweepCos(i);
            ASSERT_NEAR(fresnelSchlick(c, eta), exactSchlick(c, eta), 8.0 * kEps)
                << "cos " << c << " eta " << eta;
        }
    }
}

TEST(Schlick, UsesTransmittedCosineFromDenserSide) {
    // From inside: cos theta_t from Snell, and exactly 1 under total internal reflection. Float
    // rounding shifts cos^2 t by a few ulps of eta^2, which moves cos t by ~eps/cos t near the
    // critical angle; as in fresnelTolerance, propagate an 8-ulp shift, plus 8 ulps.
    for (int j = 1; j < kEtas; ++j) {
        const float eta = sweepEta(j, 4.0);
        for (int i = 0; i < kAngles; ++i) {
            const float c = -sweepCos(i);
            const double delta = 8.0 * kEps * double(eta) * eta;
            const double ref = exactSchlick(c, eta);
            const double tol = std::max(std::abs(exactSchlick(c, eta, delta) - ref),
                                        std::abs(exactSchlick(c, eta, -delta) - ref)) +
                               8.0 * kEps;
            ASSERT_NEAR(fresnelSchlick(c, eta), ref, tol) << "cos " << c << " eta " << eta;
            // Where even cos^2 t + delta is negative the reflection is total beyond doubt:
            // exactly 1.
            if (exactSchlick(c, eta, delta) == 1.0) {
                ASSERT_EQ(fresnelSchlick(c, eta), 1.0f) << "cos " << c << " eta " << eta;
            }
        }
    }
    // Glass to air at 60 degrees, well past the 41.8-degree critical angle.
    EXPECT_EQ(fresnelSchlick(-0.5f, 1.5f), 1.0f);
}

namespace {

// Measured maximum |Schlick - exact| from outside over the sweep's 2000 angles and 100 indices:
// - eta in [1, 2]: 1.0, at eta = 1 and 90 degrees. Schlick's (1 - cos)^5 term does not vanish as
//   eta -> 1 while the exact R does, so near eta = 1 the error approaches 1 at grazing angles; the
//   bound over this range is therefore vacuous and stated only for the record.
// - eta in [1.3, 2] (water to dense flint): 0.0683, at eta = 1.3 and about 83.5 degrees.
// - eta = 1.5 (glass): 0.0357, at about 85 degrees.
// Bounds are the measured figures rounded up to two significant digits.
constexpr double kSchlickMaxErrorEta1To2 = 1.0;
constexpr double kSchlickMaxErrorEta13To2 = 0.069;
constexpr double kSchlickMaxErrorGlass = 0.036;

double maxSchlickError(double minEta, double maxEta, int etas) {
    double worst = 0.0;
    for (int j = 0; j < etas; ++j) {
        const float eta =
            static_cast<float>(etas == 1 ? minEta : minEta + (maxEta - minEta) * j / (etas - 1));
        for (int i = 0; i < kAngles; ++i) {
            const float c = sweepCos(i);
            worst = std::max(worst, std::abs(fresnelSchlick(c, eta) - exactFresnel(c, eta).r));
        }
    }
    return worst;
}

}  // namespace

TEST(Schlick, ErrorAgainstExactIsBounded) {
    const double eta1To2 = maxSchlickError(1.0, 2.0, kEtas);
    const double eta13To2 = maxSchlickError(1.3, 2.0, kEtas);
    const double glass = maxSchlickError(1.5, 1.5, 1);
    RecordProperty("max_error_eta_1_2", std::to_string(eta1To2));
    RecordProperty("max_error_eta_1.3_2", std::to_string(eta13To2));
    RecordProperty("max_error_eta_1.5", std::to_string(glass));
    EXPECT_LE(eta1To2, kSchlickMaxErrorEta1To2);
    EXPECT_LE(eta13To2, kSchlickMaxErrorEta13To2);
    EXPECT_LE(glass, kSchlickMaxErrorGlass);
}

namespace {

/// A tilted unit normal, so that no test relies on axis-aligned arithmetic.
const Vec3 kNormal = glm::normalize(Vec3(0.3f, -0.5f, 0.8f));

/// The unit direction at cos theta = c from kNormal (negative c: below it), in a fixed plane.
Vec3 directionAt(double c) {
    Vec3 t, b;
    coordinateSystem(kNormal, t, b);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    return Vec3(DVec3(t) * s + DVec3(kNormal) * c);
}

std::vector<double> refractCosines() {
    std::vector<double> cosines = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2};
    for (int i = 0; i < kAngles; i += 4) cosines.push_back(std::cos(kHalfPi * i / (kAngles - 1)));
    return cosines;
}

// Calls visit(wi, cosI) for every direction of the refraction grid, from both sides.
template <class Visit>
void forEachIncidence(Visit visit) {
    for (double c : refractCosines()) {
        for (double side : {1.0, -1.0}) {
            const Vec3 wi = directionAt(side * c);
            visit(wi, glm::dot(kNormal, wi));
        }
    }
}

}  // namespace

TEST(Refract, SnellUnitLengthCoplanarOppositeSide) {
    for (float eta : {1.0001f, 1.33f, 1.5f, 2.4f, 4.0f, 10.0f}) {
        forEachIncidence([&](const Vec3& wi, float cosI) {
            float etaPath = 0.0f;
            Vec3 wt;
            if (!refract(wi, kNormal, eta, etaPath, wt)) return;  // TIR: see below.
            EXPECT_EQ(etaPath, cosI < 0.0f ? 1.0f / eta : eta);
            const DVec3 n(kNormal), i(wi), t(wt);
            // A float unit vector: |length - 1| within a few ulps.
            EXPECT_NEAR(glm::length(t), 1.0, 1e-6) << "cos " << cosI << " eta " << eta;
            // Snell: sin i = etaPath sin t. refract forms cos^2 t with an error of a few ulps
            // of max(1, 1 / etaPath^2) (the same model as fresnelTolerance: 8 ulps), and
            // normalizing wt turns that into a relative error of half as much in sin t; 16
            // ulps more for the rest. At etaPath = 0.1 (eta 10, from inside) that is 5e-5;
            // for etaPath >= 1, 2.4e-6. Plus an absolute floor for near-normal incidence,
            // where both sines are at rounding level: wt's components are off by a few ulps
            // of max(1, 1 / etaPath), which Snell multiplies by etaPath.
            const double sinI = glm::length(glm::cross(i, n)) / glm::length(i);
            const double sinT = glm::length(glm::cross(t, n)) / glm::length(t);
            const double relative =
                16.0 * kEps + 4.0 * kEps * std::max(1.0, 1.0 / (double(etaPath) * etaPath));
            const double floor = 8.0 * kEps * std::max(1.0f, etaPath);
            EXPECT_NEAR(sinI, etaPath * sinT, relative * sinI + floor)
                << "cos " << cosI << " eta " << eta;
            // Coplanar: wt has no component along wi x n (rounding-level, a few ulps).
            EXPECT_NEAR(glm::dot(t, glm::cross(i, n)), 0.0, 1e-6);
            // Opposite side of the interface from wi.
            if (cosI >= 0.0f) {
                EXPECT_LT(glm::dot(t, n), 0.0) << "cos " << cosI << " eta " << eta;
            } else {
                EXPECT_GT(glm::dot(t, n), 0.0) << "cos " << cosI << " eta " << eta;
            }
        });
    }
}

TEST(Refract, ExactlyGrazingIncidence) {
    // cos i = 0 exactly (axis-aligned so the dot product is exactly 0): from the less dense side
    // the ray bends to the critical angle, sin t = 1/eta, below the surface.
    const Vec3 n(0.0f, 0.0f, 1.0f), wi(1.0f, 0.0f, 0.0f);
    for (float eta : {1.0001f, 1.5f, 10.0f}) {
        float etaPath = 0.0f;
        Vec3 wt;
        ASSERT_TRUE(refract(wi, n, eta, etaPath, wt)) << "eta " << eta;
        EXPECT_NEAR(-wt.x, 1.0 / eta, 1e-6) << "eta " << eta;  // a few ulps of the unit vector
        EXPECT_LT(wt.z, 0.0f);
        EXPECT_EQ(wt.y, 0.0f);
        // With the indices swapped (arriving from the denser side) it is totally reflected.
        EXPECT_FALSE(refract(wi, n, 1.0f / eta, etaPath, wt)) << "eta " << eta;
    }
    // eta = 1 at exactly 90 degrees is degenerate (the straight-through direction is tangent, every
    // Fresnel ratio 0/0); whatever refract decides, fresnelDielectric must agree with it.
    float etaPath = 0.0f;
    Vec3 wt;
    const bool ok = refract(wi, n, 1.0f, etaPath, wt);
    EXPECT_EQ(fresnelDielectric(0.0f, 1.0f) == 1.0f, !ok);
}

TEST(Refract, FailsExactlyUnderTotalInternalReflection) {
    // Same float inputs to both functions: refract fails if and only if fresnelDielectric is 1.
    // (R could in principle round to 1 a hair inside the critical angle, where 1 - R ~ 4 cos t /
    // cos i falls below an ulp; no point of this grid is that close, so agreement is strict.)
    for (float eta : {1.0001f, 1.1f, 1.33f, 1.5f, 2.4f, 4.0f, 10.0f}) {
        forEachIncidence([&](const Vec3& wi, float cosI) {
            float etaPath = 0.0f;
            Vec3 wt;
            const bool ok = refract(wi, kNormal, eta, etaPath, wt);
            const float r = fresnelDielectric(cosI, eta);
            if (!ok) {
                EXPECT_EQ(r, 1.0f) << "cos " << cosI << " eta " << eta;
            } else {
                EXPECT_LT(r, 1.0f) << "cos " << cosI << " eta " << eta;
            }
            // Where exact arithmetic decides beyond float rounding (cos^2 t further from 0
            // than the 8 ulps of max(1, 1/eta'^2) of fresnelTolerance), the decision agrees.
            const double etaI = cosI < 0.0f ? 1.0 / eta : eta;
            const double sin2T = (1.0 - double(cosI) * cosI) / (etaI * etaI);
            if (std::abs(sin2T - 1.0) > 8.0 * kEps * std::max(1.0, 1.0 / (etaI * etaI))) {
                EXPECT_EQ(ok, sin2T < 1.0) << "cos " << cosI << " eta " << eta;
            }
        });
    }
}

TEST(Refract, IndexMatchedPassesStraightThrough) {
    // eta = 1: no bending, wt = -wi up to normalization's rounding (an ulp or two per component),
    // at every angle including grazing ones down to cos = 1e-6, from both sides (cos = 0 exactly:
    // see ExactlyGrazingIncidence).
    for (double c : refractCosines()) {
        for (double side : {1.0, -1.0}) {
            const Vec3 wi = directionAt(side * c);
            float etaPath = 0.0f;
            Vec3 wt;
            ASSERT_TRUE(refract(wi, kNormal, 1.0f, etaPath, wt)) << "cos " << side * c;
            EXPECT_EQ(etaPath, 1.0f);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(wt[k], -wi[k], 1e-6) << "cos " << side * c;
        }
    }
}

}  // namespace caustic
