// Student's t distribution: the tail and two-sided threshold behind every pass-variance test and
// interval (tests, bench_study). A film is the mean of n independent pass estimates, and
// (mean - true) / standard error is t-distributed with n - 1 degrees of freedom when the pass
// estimates are normal (each the mean of many samples).
#pragma once

#include <algorithm>
#include <cmath>

namespace caustic {

/// P(|T| > t) for Student's t with `dof` degrees of freedom: the regularized incomplete beta
/// I_x(dof/2, 1/2) at x = dof / (dof + t^2) (Abramowitz and Stegun 26.7.1). With u = 1 - s^2 the
/// integrand u^(a-1) (1-u)^(-1/2) becomes 2 (1 - s^2)^(a-1), smooth on [sqrt(1 - x), 1], and
/// Simpson's rule integrates it to ~1e-12 relative.
inline double studentTwoSidedTail(double t, int dof) {
    const double a = 0.5 * dof;
    const double lower = std::abs(t) / std::sqrt(dof + t * t);  // sqrt(1 - x)
    const int n = 4096;
    const double h = (1.0 - lower) / n;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
        double s = lower + i * h;
        double f = 2.0 * std::pow(std::max(0.0, 1.0 - s * s), a - 1.0);
        sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
    }
    double beta = std::exp(std::lgamma(a) + std::lgamma(0.5) - std::lgamma(a + 0.5));
    return sum * h / 3.0 / beta;
}

/// The two-sided threshold of Student's t for a false-alarm rate `alpha` per check (bisection).
inline double studentThreshold(double alpha, int dof) {
    double lo = 0, hi = 100;
    for (int i = 0; i < 200; ++i) {
        double m = 0.5 * (lo + hi);
        (studentTwoSidedTail(m, dof) > alpha ? lo : hi) = m;
    }
    return hi;
}

}  // namespace caustic
