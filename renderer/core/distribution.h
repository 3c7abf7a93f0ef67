// Piecewise-constant densities on [0,1) and [0,1)^2, sampled by inverting their CDFs (pbrt-v4,
// sections A.4.3 and A.5.6): what an environment map's importance sampling draws from.
#pragma once

#include <cstddef>
#include <vector>

#include "core/math.h"

namespace caustic {

/// A density on [0,1) proportional to n non-negative values, each over one of n equal intervals.
/// Values that are all zero give the uniform density (so that sampling never fails).
class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(std::vector<float> values);

    /// The x in [0,1) whose CDF is u in [0,1), its density, and the interval holding it.
    float sample(float u, float& pdf, size_t& index) const;
    /// The density at x in [0,1).
    float pdf(float x) const;
    /// The mean of the values: their integral over [0,1).
    double integral() const { return integral_; }
    size_t size() const { return values_.size(); }
    size_t memoryBytes() const {
        return values_.capacity() * sizeof(float) + cdf_.capacity() * sizeof(double);
    }

private:
    std::vector<float> values_;
    std::vector<double> cdf_;  // size n + 1, cdf_[0] = 0, cdf_[n] = 1; double so that 4096^2
                               // texels' running sums keep every texel's share
    double integral_ = 0.0;
};

/// A density on [0,1)^2 proportional to a width x height grid of non-negative values (row-major,
/// row 0 at v in [0, 1/height)): a marginal over rows, then a conditional within the row.
class Distribution2D {
public:
    Distribution2D() = default;
    Distribution2D(const std::vector<float>& values, int width, int height);

    /// The point (u, v) in [0,1)^2 for a sample in [0,1)^2, and its density.
    Vec2 sample(Vec2 u, float& pdf) const;
    float pdf(Vec2 p) const;
    size_t memoryBytes() const;

private:
    std::vector<Distribution1D> rows_;
    Distribution1D marginal_;
};

}  // namespace caustic
