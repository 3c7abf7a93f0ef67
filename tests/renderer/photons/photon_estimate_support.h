// What the photon estimate tests share: the kernels as the literature writes them, the test
// plane's albedo and points on it, and the thresholds (photon_estimate_test.cpp for the fields
// under point and quad lights, photon_kernel_test.cpp for the kernels and the integrator).
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "geometry/hit.h"
#include "photons/photon_map.h"

namespace caustic::estimate_test {

constexpr double kPiD = 3.14159265358979323846;
constexpr double kFamilyWiseFalseAlarm = 1e-3;
constexpr double kRounding = 1e-4;
constexpr std::array<PhotonKernel, 3> kKernels = {PhotonKernel::Box, PhotonKernel::Cone,
                                                  PhotonKernel::Simpson};
constexpr const char* kKernelNames[3] = {"box", "cone", "simpson"};

// The albedo of every test plane.
inline const Color kAlbedo(0.5f, 0.25f, 0.75f);

// The kernels as the literature writes them, in double, at distance s in a disk of radius r:
// uniform 1 / (pi r^2); cone 3 (1 - s/r) / (pi r^2) (Jensen 2001, 7.2: the cone filter
// w = 1 - d / (k r) normalized by 1 - 2 / (3k), here with k = 1); Simpson's, which is Silverman's
// bivariate biweight (1986, 4.2), 3 (1 - s^2/r^2)^2 / (pi r^2).
inline double kernelValue(PhotonKernel k, double s, double r) {
    double t = s / r, a = kPiD * r * r;
    switch (k) {
        case PhotonKernel::Box:
            return 1.0 / a;
        case PhotonKernel::Cone:
            return 3.0 * (1.0 - t) / a;
        case PhotonKernel::Simpson:
            return 3.0 * (1.0 - t * t) * (1.0 - t * t) / a;
    }
    return 0.0;
}

inline SurfaceInteraction planePoint(double x, double z) {
    SurfaceInteraction si;
    si.p = Vec3(float(x), 0.0f, float(z));
    si.pError = Vec3(0.0f);
    si.n = si.ns = Vec3(0.0f, 1.0f, 0.0f);
    si.pShading = si.p;
    return si;
}
inline const Vec3 kUp(0.0f, 1.0f, 0.0f);

inline std::vector<Vec2> grid(double cx, double cz, double half, int n) {
    std::vector<Vec2> points;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            points.emplace_back(float(cx - half + 2.0 * half * i / (n - 1)),
                                float(cz - half + 2.0 * half * j / (n - 1)));
    return points;
}

}  // namespace caustic::estimate_test
