// Region statistics of a render from its passes, for comparing two renders by a z-test.
//
// A pass is an independent estimate of the whole image, so the mean of a region's pixels in one
// pass is one independent sample of that region's mean, and the spread of those samples over the
// passes gives the standard error of the region's mean directly. Nothing is assumed about how
// pixels of one pass relate to each other (the alternative, Var(region mean) = sum of per-pixel
// variances / n^2, holds only if they are independent). The Film keeps cumulative per-pixel sums,
// so each pass is recovered by differencing the sums seen in consecutive onPass calls.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "film/film.h"
#include "render/renderer.h"

namespace caustic::testing {

/// A rectangle of pixels, [x0, x1) x [y0, y1).
struct Region {
    int x0, y0, x1, y1;
    int pixels() const { return (x1 - x0) * (y1 - y0); }
    std::string name() const {
        // snprintf, not operator+ on "[" + to_string(): GCC 12 warns falsely there (-Wrestrict).
        char buf[64];
        std::snprintf(buf, sizeof buf, "[%d,%d)x[%d,%d)", x0, x1, y0, y1);
        return buf;
    }
};

/// Square blocks of `block` pixels on a side tiling a width x height image (the last row and
/// column of blocks may be narrower).
inline std::vector<Region> blocks(int width, int height, int block) {
    std::vector<Region> out;
    for (int y = 0; y < height; y += block)
        for (int x = 0; x < width; x += block)
            out.push_back({x, y, std::min(x + block, width), std::min(y + block, height)});
    return out;
}

/// Blocks of every size in `sizes`: a hierarchy from small regions, sensitive to local errors,
/// to the whole image, sensitive to small errors everywhere.
inline std::vector<Region> blockHierarchy(int width, int height, const std::vector<int>& sizes) {
    std::vector<Region> out;
    for (int size : sizes) {
        std::vector<Region> level = blocks(width, height, size);
        out.insert(out.end(), level.begin(), level.end());
    }
    return out;
}

/// Collects, per region and channel, the sum and sum of squares of the per-pass region means.
/// Pass `callbacks()` to render(); read the statistics after it returns.
class RegionStats {
public:
    RegionStats(int width, int height, std::vector<Region> regions)
        : width_(width),
          regions_(std::move(regions)),
          previous_(size_t(width) * size_t(height) * 3, 0.0),
          sum_(regions_.size() * 3, 0.0),
          sumSq_(regions_.size() * 3, 0.0) {}

    RenderCallbacks callbacks() {
        RenderCallbacks c;
        c.onPass = [this](const Film& film) { addPass(film); };
        return c;
    }

    const std::vector<Region>& regions() const { return regions_; }
    int passes() const { return passes_; }
    /// Mean over the passes of the region's mean, channel c.
    double mean(size_t r, int c) const { return sum_[3 * r + c] / passes_; }
    /// Standard error of mean(r, c): sqrt(s^2 / n), s^2 the unbiased variance over the n passes.
    double standardError(size_t r, int c) const {
        if (passes_ < 2) return 0.0;
        double n = passes_, m = mean(r, c);
        double s2 = std::max(0.0, (sumSq_[3 * r + c] - n * m * m) / (n - 1.0));
        return std::sqrt(s2 / n);
    }

private:
    void addPass(const Film& film) {
        const std::vector<double>& sums = film.sums();
        for (size_t r = 0; r < regions_.size(); ++r) {
            const Region& g = regions_[r];
            double m[3] = {0, 0, 0};
            for (int y = g.y0; y < g.y1; ++y)
                for (int x = g.x0; x < g.x1; ++x)
                    for (int c = 0; c < 3; ++c) {
                        size_t i = 3 * (size_t(y) * size_t(width_) + size_t(x)) + size_t(c);
                        m[c] += sums[i] - previous_[i];
                    }
            for (int c = 0; c < 3; ++c) {
                m[c] /= g.pixels();
                sum_[3 * r + c] += m[c];
                sumSq_[3 * r + c] += m[c] * m[c];
            }
        }
        previous_ = sums;
        ++passes_;
    }

    int width_;
    std::vector<Region> regions_;
    std::vector<double> previous_;  ///< The film's sums after the previous pass.
    std::vector<double> sum_, sumSq_;
    int passes_ = 0;
};

/// The two-sided standard normal quantile: z with P(|Z| > z) = p, by bisection on erfc.
inline double twoSidedNormalQuantile(double p) {
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
    }
    return lo;
}

/// The worst region of a comparison of two renders of the same regions.
struct Comparison {
    double worstZ = 0.0;  ///< Largest |z| over regions and channels.
    size_t region = 0;
    int channel = 0;
    double meanA = 0, seA = 0, meanB = 0, seB = 0;

    std::string describe(const std::vector<Region>& regions) const {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "worst |z| = %.3f in region %s channel %d: %.6g +- %.3g vs %.6g +- %.3g",
                      worstZ, regions[region].name().c_str(), channel, meanA, seA, meanB, seB);
        return buf;
    }
};

/// z = (mA - mB) / sqrt(seA^2 + seB^2) for every region and channel of two independent renders;
/// the largest |z|. Where both standard errors are zero the means must be equal (z = 0 if they
/// are, infinite if not): a region that no sample varies in is known exactly by both.
inline Comparison compare(const RegionStats& a, const RegionStats& b) {
    Comparison worst;
    worst.worstZ = -1.0;  // below any |z|: the first check sets it
    for (size_t r = 0; r < a.regions().size(); ++r) {
        for (int c = 0; c < 3; ++c) {
            double ma = a.mean(r, c), mb = b.mean(r, c);
            double sa = a.standardError(r, c), sb = b.standardError(r, c);
            double se = std::sqrt(sa * sa + sb * sb);
            double z = se > 0.0 ? std::abs(ma - mb) / se : (ma == mb ? 0.0 : INFINITY);
            if (std::isnan(z)) z = INFINITY;  // a NaN must fail, not slip past a comparison
            if (z > worst.worstZ) worst = {z, r, c, ma, sa, mb, sb};
        }
    }
    return worst;
}

}  // namespace caustic::testing
