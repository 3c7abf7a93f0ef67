// The known-answer scene shared by the integrator and photon tests: a diffuse plane y = 0 under a
// point light, seen obliquely from above, and its exact pixel values.
#pragma once

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "film/film.h"
#include "scene/camera.h"
#include "support/test_scenes.h"

namespace caustic::testing {

// A diffuse plane y = 0 under a point light at height h, seen obliquely from above.
inline nlohmann::json pointLightOverPlane(int width, int height) {
    return mergePatched(nlohmann::json::parse(R"({
      "camera": {"position": [0, 2, 2.5], "look_at": [0, 0, 0], "fov": 40,
                 "width": 0, "height": 0},
      "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.25, 0.75]}},
      "shapes": [{"type": "quad", "origin": [-50, 0, -50], "u": [0, 0, 100], "v": [100, 0, 0],
                  "material": "white"}],
      "lights": [{"type": "point", "position": [0.3, 1.0, -0.2], "intensity": [10, 20, 5]}]
    })"),
                        {{"camera", {{"width", width}, {"height", height}}}});
}

// The scene's camera position: the loader stores positions relative to it.
inline const Vec3 kCamera(0.0f, 2.0f, 2.5f);

// Radiance of the plane at a point (world space): albedo / pi * I cos(theta) / d^2.
inline Color planeRadiance(const Vec3& p) {
    const Vec3 light(0.3f, 1.0f, -0.2f);
    const Color albedo(0.5f, 0.25f, 0.75f), intensity(10, 20, 5);
    Vec3 d = light - p;
    float d2 = glm::dot(d, d);
    float cosTheta = d.y / std::sqrt(d2);
    return albedo * kInvPi * intensity * cosTheta / d2;
}

// The exact pixel value: the analytic radiance averaged over the pixel's footprint (box filter),
// by a 32x32 midpoint rule in double.
inline Color pixelAverage(const Camera& camera, int x, int y) {
    constexpr int n = 32;
    DVec3 sum(0.0);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            Ray r = camera.generateRay(float(x) + (float(i) + 0.5f) / n,
                                       float(y) + (float(j) + 0.5f) / n);
            Vec3 o = r.o + kCamera;  // back to world space
            float t = -o.y / r.d.y;
            sum += DVec3(planeRadiance(o + t * r.d));
        }
    }
    return Color(sum / double(n * n));
}

/// Every pixel and channel of `film` against the exact pixel average, within 5 standard errors from
/// the pass variance plus 1e-5 relative (within a pixel the only randomness is the sample's
/// position, so the pass variance measures exactly the error tested: false-alarm rate ~6e-7 per
/// check, ~3e-3 over a 48 x 32 image). Returns the number of failures; `worst` gets the largest
/// error over its tolerance.
inline int pixelsOffTheAnalyticValue(const Film& film, const Camera& camera, double& worst) {
    int bad = 0;
    worst = 0.0;
    for (int y = 0; y < film.height(); ++y) {
        for (int x = 0; x < film.width(); ++x) {
            Color expected = pixelAverage(camera, x, y);
            Color got = film.mean(x, y), se = film.standardError(x, y);
            for (int c = 0; c < 3; ++c) {
                double tol = 5.0 * se[c] + 1e-5 * expected[c];
                worst = std::max(worst, std::abs(got[c] - expected[c]) / std::max(tol, 1e-12));
                if (std::abs(got[c] - expected[c]) > tol) ++bad;
            }
        }
    }
    return bad;
}

}  // namespace caustic::testing
