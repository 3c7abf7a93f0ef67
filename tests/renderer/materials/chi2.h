// A chi-square test of a sampling routine against the density it claims, in the manner of Mitsuba
// 3's ChiSquareTest (mitsuba/python/chi2.py): the sphere of directions is cut into cells of equal
// solid angle (cos theta by phi), the samples are counted per cell, the density is integrated over
// each cell by Simpson's rule, cells expecting fewer than 5 samples are pooled, and Pearson's
// statistic gives a p-value. Samples that fail (no direction) form a cell of their own, expected
// in proportion to the density's missing mass. A test passes when p is above its significance,
// which a caller divides among its tests (Sidak's correction, chi2Significance).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/math.h"
#include "core/rng.h"
#include "materials/material.h"

namespace caustic::testing {

struct Chi2Result {
    double statistic = 0.0;
    int dof = 0;
    double pValue = 0.0;
    double pdfIntegral = 0.0;      ///< The density's integral over the sphere.
    double sampledFraction = 0.0;  ///< The samples that returned a direction.
    std::string summary;           ///< One line for a failure message.
};

/// The regularized upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a): the
/// probability that a chi-square variable of 2a degrees of freedom exceeds 2x (Numerical Recipes,
/// 3rd ed., 6.2: its series below a + 1, its continued fraction above).
inline double upperIncompleteGamma(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double logPrefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 100000 && std::abs(term) > std::abs(sum) * 1e-15; ++n) {
            term *= x / (a + n);
            sum += term;
        }
        return std::max(0.0, 1.0 - sum * std::exp(logPrefix));
    }
    // Lentz's method for the continued fraction.
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(logPrefix) * h;
}

namespace detail {

// Simpson's rule on k x k points (k odd) of the cell [z0, z1] x [p0, p1] in (cos theta, phi),
// where the solid angle element is dz dphi.
inline double simpsonCell(const std::function<double(const Vec3&)>& pdf, double z0, double z1,
                          double p0, double p1, int k) {
    auto weight = [k](int i) { return i == 0 || i == k - 1 ? 1.0 : i % 2 == 1 ? 4.0 : 2.0; };
    double sum = 0.0;
    for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) {
            const double z = z0 + (z1 - z0) * a / (k - 1), phi = p0 + (p1 - p0) * b / (k - 1);
            const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
            sum += weight(a) * weight(b) *
                   pdf(Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)));
        }
    return sum * (z1 - z0) / (3.0 * (k - 1)) * (p1 - p0) / (3.0 * (k - 1));
}

// The integral over a cell: Simpson on 5 x 5 points, and on 9 x 9; where they differ by more than
// a fiftieth of the expected count's standard deviation (sqrt(integral / samples), in units of the
// integral) the cell is split in four, down to 16 levels: a lobe refracted through an index near 1
// is a few thousandths of a radian wide, and at the pole a few millionths of cos theta.
inline double integrateCell(const std::function<double(const Vec3&)>& pdf, double z0, double z1,
                            double p0, double p1, double samples, int depth = 0) {
    const double coarse = simpsonCell(pdf, z0, z1, p0, p1, 5);
    const double fine = simpsonCell(pdf, z0, z1, p0, p1, 9);
    const double tolerance = 0.02 * std::sqrt(std::max(std::abs(fine), 1e-12) / samples);
    if (depth >= 16 || std::abs(fine - coarse) <= tolerance) return fine;
    const double zm = 0.5 * (z0 + z1), pm = 0.5 * (p0 + p1);
    return integrateCell(pdf, z0, zm, p0, pm, samples, depth + 1) +
           integrateCell(pdf, zm, z1, p0, pm, samples, depth + 1) +
           integrateCell(pdf, z0, zm, pm, p1, samples, depth + 1) +
           integrateCell(pdf, zm, z1, pm, p1, samples, depth + 1);
}

}  // namespace detail

/// The significance of each of `tests` tests for a family-wise false-alarm rate `alpha` (Sidak).
inline double chi2Significance(int tests, double alpha = 0.01) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / tests);
}

/// sample(u, uc): a unit direction from a 2D sample and a lobe choice, or nullopt. pdf(w): the
/// density per unit solid angle that sample claims. The cells are cut in a frame tilted away from
/// the caller's: lobes peak along the caller's z (a normal), and at a pole of the cells' (cos
/// theta, phi) coordinates a narrow peak is a few millionths of cos theta wide, too narrow to
/// integrate well.
inline Chi2Result chi2Test(const std::function<std::optional<Vec3>(Vec2, float)>& sample,
                           const std::function<double(const Vec3&)>& pdf,
                           uint64_t samples = 1000000, int cosBins = 40, int phiBins = 80,
                           uint64_t seed = 1) {
    const int cells = cosBins * phiBins;
    std::vector<double> observed(size_t(cells) + 1, 0.0), expected(size_t(cells) + 1, 0.0);
    Chi2Result r;
    Vec3 tx, ty;
    const Vec3 tz = glm::normalize(Vec3(0.3f, -0.5f, 0.81f));
    coordinateSystem(tz, tx, ty);
    const auto toCells = [&](const Vec3& w) {
        return Vec3(glm::dot(w, tx), glm::dot(w, ty), glm::dot(w, tz));
    };
    const std::function<double(const Vec3&)> cellPdf = [&](const Vec3& c) {
        return pdf(c.x * tx + c.y * ty + c.z * tz);
    };

    // Count the samples per cell; the last cell holds the failures.
    Rng rng(seed);
    uint64_t hits = 0;
    for (uint64_t i = 0; i < samples; ++i) {
        const Vec2 u(rng.uniform(), rng.uniform());
        const std::optional<Vec3> sampled = sample(u, rng.uniform());
        if (!sampled) {
            observed[size_t(cells)] += 1.0;
            continue;
        }
        ++hits;
        const Vec3 w = toCells(*sampled);
        const double z = std::clamp(double(w.z), -1.0, 1.0);
        const double phi = std::atan2(double(w.y), double(w.x));
        const int ic = std::min(cosBins - 1, int((z + 1.0) * 0.5 * cosBins));
        const int ip = std::clamp(int((phi + M_PI) / (2.0 * M_PI) * phiBins), 0, phiBins - 1);
        observed[size_t(ic * phiBins + ip)] += 1.0;
    }
    r.sampledFraction = double(hits) / double(samples);

    // Integrate the density over each cell, adaptively: a narrow lobe's peak may be far smaller
    // than a cell.
    const double dz = 2.0 / cosBins, dphi = 2.0 * M_PI / phiBins;
    for (int ic = 0; ic < cosBins; ++ic)
        for (int ip = 0; ip < phiBins; ++ip) {
            const double integral =
                detail::integrateCell(cellPdf, -1.0 + dz * ic, -1.0 + dz * (ic + 1),
                                      -M_PI + dphi * ip, -M_PI + dphi * (ip + 1), double(samples));
            expected[size_t(ic * phiBins + ip)] = integral * double(samples);
            r.pdfIntegral += integral;
        }
    expected[size_t(cells)] = std::max(0.0, 1.0 - r.pdfIntegral) * double(samples);

    // Pool the cells expecting fewer than 5 samples, smallest first, into bins of at least 5.
    std::vector<size_t> order(expected.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double poolObs = 0.0, poolExp = 0.0;
    int bins = 0;
    for (size_t i : order) {
        // A direction where the density is zero is a failure; the failures' own cell expects the
        // density's missing mass, which the integration's error may round to zero.
        if (expected[i] == 0.0 && observed[i] > 0.0 && i != size_t(cells)) {
            r.statistic = INFINITY;
            r.summary = "a cell of zero density got " + std::to_string(int(observed[i])) +
                        " samples (cell " + std::to_string(i) + ")";
            return r;
        }
        if (expected[i] < 5.0 || poolExp > 0.0) {
            poolObs += observed[i];
            poolExp += expected[i];
            if (poolExp >= 5.0) {
                r.statistic += (poolObs - poolExp) * (poolObs - poolExp) / poolExp;
                ++bins;
                poolObs = poolExp = 0.0;
            }
            continue;
        }
        r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++bins;
    }
    if (poolExp > 0.0) {  // only when every cell together expects fewer than 5 samples
        r.statistic += (poolObs - poolExp) * (poolObs - poolExp) / poolExp;
        ++bins;
    }
    r.dof = std::max(1, bins - 1);
    r.pValue = upperIncompleteGamma(0.5 * r.dof, 0.5 * r.statistic);
    std::ostringstream line;
    line << "chi2 " << r.statistic << " on " << r.dof << " dof, p " << r.pValue << "; pdf integral "
         << r.pdfIntegral << ", sampled fraction " << r.sampledFraction;
    r.summary = line.str();
    return r;
}

/// The unit direction at polar angle theta (degrees from +z; above 90, below the surface) and
/// azimuth phi (radians).
inline Vec3 directionAt(double thetaDegrees, double phi = 0.3) {
    const double t = thetaDegrees * M_PI / 180.0;
    return Vec3(float(std::sin(t) * std::cos(phi)), float(std::sin(t) * std::sin(phi)),
                float(std::cos(t)));
}

/// chi2Test of a material's sampling from wo (radiance), its normal +z, against its pdf, with
/// the check that the samples that fail are the density's missing mass (a tolerance of 4e-3:
/// five standard deviations of a failure fraction of 1/2 in 400000 samples). `what` names the
/// case in a failure.
inline void expectSamplingMatchesPdf(const Material& m, const Vec3& wo, double significance,
                                     const std::string& what, uint64_t samples = 400000) {
    const Vec3 n(0.0f, 0.0f, 1.0f);
    const Chi2Result r = chi2Test(
        [&](Vec2 u, float uc) -> std::optional<Vec3> {
            auto s = m.sample(wo, n, uc, u, TransportMode::Radiance);
            if (!s) return std::nullopt;
            return s->wi;
        },
        [&](const Vec3& wi) { return double(m.pdf(wo, wi, n)); }, samples);
    EXPECT_NEAR(r.pdfIntegral, r.sampledFraction, 4e-3) << what << ": " << r.summary;
    EXPECT_GT(r.pValue, significance) << what << ": " << r.summary;
}

/// Over `n` random pairs of wo (within thetaMaxDegrees of +z, the normal) and sample, that each
/// sample reports the f and pdf that f() and pdf() give for its direction, and the weight
/// f |cos| / pdf; returns the samples taken, for checks of the caller's own.
inline std::vector<std::pair<Vec3, BsdfSample>> expectSamplesReportValueAndDensity(
    const Material& m, Rng& rng, int n, double thetaMaxDegrees) {
    const Vec3 normal(0.0f, 0.0f, 1.0f);
    std::vector<std::pair<Vec3, BsdfSample>> taken;
    for (int i = 0; i < n; ++i) {
        const Vec3 wo = directionAt(thetaMaxDegrees * rng.uniform(), 6.28 * rng.uniform());
        const Vec2 u(rng.uniform(), rng.uniform());
        auto s = m.sample(wo, normal, rng.uniform(), u, TransportMode::Radiance);
        if (!s) continue;
        const Color f = m.f(wo, s->wi, normal);
        const float pdf = m.pdf(wo, s->wi, normal);
        EXPECT_NEAR(s->pdf, pdf, 1e-4f * pdf);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(s->f[c], f[c], 1e-4f * f[c]);
            EXPECT_NEAR(s->weight[c], f[c] * std::abs(s->wi.z) / pdf, 1e-4f * s->weight[c] + 1e-7f);
        }
        taken.emplace_back(wo, *s);
    }
    return taken;
}

/// That an opaque BSDF that reflects from both sides is reciprocal, f(a, b) = f(b, a), the same
/// from the back (f(-a, -b)), and passes nothing between the sides, over n random pairs.
inline void expectReciprocalTwoSidedReflector(const Material& m, Rng& rng, int n) {
    const Vec3 normal(0.0f, 0.0f, 1.0f);
    for (int i = 0; i < n; ++i) {
        const Vec3 a = directionAt(89.0 * rng.uniform(), 6.28 * rng.uniform());
        const Vec3 b = directionAt(89.0 * rng.uniform(), 6.28 * rng.uniform());
        const Color fab = m.f(a, b, normal), fba = m.f(b, a, normal);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(fab[c], fba[c], 1e-5f * fab[c] + 1e-7f);
        const Color back = m.f(-a, -b, normal);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], fab[c], 1e-5f * fab[c] + 1e-7f);
        EXPECT_EQ(m.f(a, -b, normal), Color(0.0f));
    }
}

}  // namespace caustic::testing
