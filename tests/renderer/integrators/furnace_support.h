// Shared by the furnace and dielectric energy tests: the path tracer's ways of finding emitters,
// closed enclosures of uniform diffuse albedo and emission (whose radiance is known exactly), and
// the statistical test of a pass-based film against a known uniform radiance.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/student_t.h"
#include "film/film.h"
#include "support/test_scenes.h"

namespace caustic::testing {

// ---------------------------------------------------------------------------------------------
// The furnace. Inside a closed surface of diffuse albedo rho emitting Le everywhere on its inside,
// the radiance L is the same at every point and in every direction, and the rendering equation
//   L = Le + integral of (rho / pi) L cos(theta) dw = Le + rho L
// gives L = Le / (1 - rho) (the sum Le (1 + rho + rho^2 + ...) of every bounce count), whatever the
// shape of the enclosure and wherever the camera is inside it.

enum class Enclosure {
    Sphere,     ///< One sphere with flip_normals: the analytic surface, cone/area sampled.
    Box,        ///< Six inward-facing quads.
    Icosphere,  ///< A once-subdivided icosahedron: 80 inward-facing "triangle" shapes.
};

inline const char* enclosureName(Enclosure e) {
    switch (e) {
        case Enclosure::Sphere:
            return "Sphere";
        case Enclosure::Box:
            return "Box";
        case Enclosure::Icosphere:
            return "Icosphere";
    }
    return "?";
}

/// The three ways the path tracer can account for emission: BSDF sampling alone, light sampling
/// alone at non-specular vertices, and both weighted by MIS.
enum class Sampling { Bsdf, Light, Mis };

inline const char* samplingName(Sampling s) {
    constexpr const char* kNames[] = {"BsdfOnly", "LightSampling", "Mis"};
    return kNames[int(s)];
}

/// For GoogleTest's messages and test listings: the name rather than the enum's bytes.
inline void PrintTo(Sampling s, std::ostream* os) {
    *os << samplingName(s);
}

/// The path tracer's settings that select `s`.
inline nlohmann::json samplingSettings(Sampling s) {
    return {{"light_sampling", s != Sampling::Bsdf}, {"mis", s == Sampling::Mis}};
}

/// Le / (1 - rho) per channel.
inline std::array<double, 3> furnaceRadiance(double rho, const std::array<double, 3>& Le) {
    return {Le[0] / (1.0 - rho), Le[1] / (1.0 - rho), Le[2] / (1.0 - rho)};
}

namespace detail {

using nlohmann::json;
using P3 = std::array<double, 3>;

inline P3 sub(const P3& a, const P3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline P3 cross(const P3& a, const P3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const P3& a, const P3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline P3 unit(const P3& a) {
    double l = std::sqrt(dot(a, a));
    return {a[0] / l, a[1] / l, a[2] / l};
}
inline json point(const P3& p) {
    return json::array({p[0], p[1], p[2]});
}

// The 80 triangles of an icosahedron subdivided once, on the unit sphere, each wound so that its
// front side (cross(p1 - p0, p2 - p0), DESIGN.md) faces the center. Shared vertices are computed
// from the same doubles in the same order, so neighbouring triangles share them bit for bit and
// the watertight triangle test leaves no crack for a ray to escape through.
inline std::vector<std::array<P3, 3>> inwardIcosphere() {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<P3> v = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
    for (P3& p : v) p = unit(p);
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                              {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                              {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                              {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    // The midpoint of an edge, the same whichever way round the edge is given (a + b == b + a).
    auto mid = [](const P3& a, const P3& b) {
        return unit(P3{a[0] + b[0], a[1] + b[1], a[2] + b[2]});
    };
    std::vector<std::array<P3, 3>> out;
    for (const auto& f : faces) {
        const P3 &a = v[f[0]], &b = v[f[1]], &c = v[f[2]];
        P3 ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
        for (std::array<P3, 3> t : {std::array<P3, 3>{a, ab, ca}, std::array<P3, 3>{ab, b, bc},
                                    std::array<P3, 3>{ca, bc, c}, std::array<P3, 3>{ab, bc, ca}}) {
            P3 centroid{(t[0][0] + t[1][0] + t[2][0]) / 3, (t[0][1] + t[1][1] + t[2][1]) / 3,
                        (t[0][2] + t[1][2] + t[2][2]) / 3};
            // Outward-facing: swap two vertices to face the center.
            if (dot(cross(sub(t[1], t[0]), sub(t[2], t[0])), centroid) > 0) std::swap(t[1], t[2]);
            out.push_back(t);
        }
    }
    return out;
}

}  // namespace detail

/// Where furnaceScene puts the camera: off-centre, looking in no special direction. Dyadic
/// fractions, so that positions relative to the camera (as the loader stores them) stay exact.
constexpr std::array<double, 3> kFurnaceCamera = {0.25, -0.125, 0.0625};
constexpr std::array<double, 3> kFurnaceLookAt = {1.0, 0.375, -0.625};

/// A closed enclosure of material "wall" (diffuse albedo rho, emission Le, on its inside) with the
/// camera inside it, `size` x `size` pixels with a 90 degree field of view.
inline nlohmann::json furnaceScene(Enclosure enclosure, double rho, const std::array<double, 3>& Le,
                                   int size) {
    using nlohmann::json;
    json doc = {
        {"camera",
         {{"position", kFurnaceCamera},
          {"look_at", kFurnaceLookAt},
          {"fov", 90},
          {"width", size},
          {"height", size}}},
        {"materials",
         {{"wall",
           {{"type", "diffuse"},
            {"albedo", {rho, rho, rho}},
            {"emission", {Le[0], Le[1], Le[2]}}}}}},
        {"shapes", json::array()},
    };
    json& shapes = doc["shapes"];
    switch (enclosure) {
        case Enclosure::Sphere:
            // flip_normals: the front side, the side that emits, is the inside.
            shapes.push_back({{"type", "sphere"},
                              {"center", {0, 0, 0}},
                              {"radius", 1.0},
                              {"flip_normals", true},
                              {"material", "wall"}});
            break;
        case Enclosure::Box: {
            // The box [-1, 1] x [-1.5, 1.5] x [-0.75, 0.75] (a cube would be needlessly symmetric);
            // each quad's cross(u, v) points inwards. The corners, relative to the camera too, are
            // sums of dyadic fractions, exact in float, so adjacent quads share their edges
            // exactly and no ray escapes between them.
            const double x = 1.0, y = 1.5, z = 0.75;
            auto quad = [&](json origin, json u, json v) {
                shapes.push_back({{"type", "quad"},
                                  {"origin", origin},
                                  {"u", u},
                                  {"v", v},
                                  {"material", "wall"}});
            };
            quad({-x, -y, -z}, {0, 2 * y, 0}, {0, 0, 2 * z});  // x = -1, normal +x
            quad({x, -y, -z}, {0, 0, 2 * z}, {0, 2 * y, 0});   // x = +1, normal -x
            quad({-x, -y, -z}, {0, 0, 2 * z}, {2 * x, 0, 0});  // y = -1.5, normal +y
            quad({-x, y, -z}, {2 * x, 0, 0}, {0, 0, 2 * z});   // y = +1.5, normal -y
            quad({-x, -y, -z}, {2 * x, 0, 0}, {0, 2 * y, 0});  // z = -0.75, normal +z
            quad({-x, -y, z}, {0, 2 * y, 0}, {2 * x, 0, 0});   // z = +0.75, normal -z
            break;
        }
        case Enclosure::Icosphere:
            for (const auto& t : detail::inwardIcosphere())
                shapes.push_back(
                    {{"type", "triangle"},
                     {"vertices",
                      json::array({detail::point(t[0]), detail::point(t[1]), detail::point(t[2])})},
                     {"material", "wall"}});
            break;
    }
    return doc;
}

// ---------------------------------------------------------------------------------------------
// The statistical test. A film is the mean of n independent pass estimates, and Film::standardError
// is sqrt(s^2 / n) from their sample variance, so (mean - true) / standardError is Student-t
// distributed with n - 1 degrees of freedom when the pass estimates are normal (each is the mean
// of many samples). With 64 passes its tail is much heavier than the normal one far out:
// P(|T_63| > 5) = 4.9e-6 against P(|Z| > 5) = 5.7e-7, so the threshold comes from t.

using caustic::studentThreshold;  // core/student_t.h

/// A film compared with a uniform expected radiance, pixel by pixel and as a whole.
struct UniformCheck {
    int failures = 0;                   ///< Pixel values outside threshold * se + rounding.
    double worstT = 0;                  ///< Largest |mean - expected| / se over pixel values.
    std::string worst;                  ///< The worst pixel value, for the message.
    std::array<double, 3> imageMean{};  ///< Mean over pixels, per channel.
    std::array<double, 3> imageSe{};    ///< Its standard error: sqrt(sum se^2) / pixels.
    std::array<double, 3> imageT{};     ///< (imageMean - expected) / imageSe.
};

/// Every pixel value must satisfy |mean - expected| <= threshold se + rounding expected, where
/// `rounding` covers float arithmetic along a path (values of zero variance must match to it).
inline UniformCheck checkUniform(const Film& film, const std::array<double, 3>& expected,
                                 double threshold, double rounding = 1e-5) {
    UniformCheck r;
    double worstExcess = 0;
    std::array<double, 3> sumSe2{};
    const double pixels = double(film.width()) * film.height();
    for (int y = 0; y < film.height(); ++y) {
        for (int x = 0; x < film.width(); ++x) {
            Color m = film.mean(x, y), se = film.standardError(x, y);
            for (int c = 0; c < 3; ++c) {
                r.imageMean[c] += m[c] / pixels;
                sumSe2[c] += double(se[c]) * se[c];
                double diff = std::abs(m[c] - expected[c]);
                double tol = threshold * se[c] + rounding * expected[c];
                if (se[c] > 0) r.worstT = std::max(r.worstT, diff / se[c]);
                if (!(diff <= tol)) {
                    ++r.failures;
                    double excess = tol > 0 ? diff / tol : HUGE_VAL;
                    if (excess > worstExcess) {
                        worstExcess = excess;
                        r.worst = pixelValueText(x, y, c, m[c], se[c]) + ", expected " +
                                  std::to_string(expected[c]);
                    }
                }
            }
        }
    }
    for (int c = 0; c < 3; ++c) {
        r.imageSe[c] = std::sqrt(sumSe2[c]) / pixels;
        r.imageT[c] = r.imageSe[c] > 0 ? (r.imageMean[c] - expected[c]) / r.imageSe[c] : 0;
    }
    return r;
}

/// checkUniform as test expectations: no pixel value fails, and in each channel the image mean
/// passes the same test with its own standard error, |imageMean - expected| <= threshold imageSe +
/// rounding expected (a bias too small to show in one pixel shows there).
inline void expectUniform(const Film& film, const std::array<double, 3>& expected, double threshold,
                          double rounding = 1e-5) {
    UniformCheck c = checkUniform(film, expected, threshold, rounding);
    EXPECT_EQ(c.failures, 0) << "threshold " << threshold << "; worst: " << c.worst
                             << "; largest |t| " << c.worstT;
    for (int ch = 0; ch < 3; ++ch)
        EXPECT_LE(std::abs(c.imageMean[ch] - expected[ch]),
                  threshold * c.imageSe[ch] + rounding * expected[ch])
            << "channel " << ch << ": image mean " << c.imageMean[ch] << " +- " << c.imageSe[ch]
            << ", expected " << expected[ch] << " (t = " << c.imageT[ch] << ")";
}

}  // namespace caustic::testing
