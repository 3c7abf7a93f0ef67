#include "render/forecast.h"

#include <algorithm>
#include <cmath>

namespace caustic {
namespace {

constexpr int kMinFitPoints = 4;

struct Fit {
    double slope = 0, logErrorAtLast = 0;
};

// log(error) = a + b log(passes) over the points with an error, less the first quarter of them
// (the earliest estimates, from few passes, are the noisiest). The line is evaluated at the last
// pass rather than taking that pass's own error, which is as noisy as any one point.
std::optional<Fit> fitRate(const std::vector<ProgressPoint>& history) {
    std::vector<const ProgressPoint*> points;
    for (const ProgressPoint& p : history)
        if (p.passes >= 2 && std::isfinite(p.relativeError) && p.relativeError > 0)
            points.push_back(&p);
    if (int(points.size()) < kMinFitPoints) return std::nullopt;
    points.erase(points.begin(), points.begin() + points.size() / 4);
    double n = double(points.size()), sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const ProgressPoint* p : points) {
        double x = std::log(double(p->passes)), y = std::log(p->relativeError);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    double det = n * sxx - sx * sx;
    if (!(det > 0)) return std::nullopt;
    Fit f;
    f.slope = (n * sxy - sx * sy) / det;
    double intercept = (sy - f.slope * sx) / n;
    f.logErrorAtLast = intercept + f.slope * std::log(double(points.back()->passes));
    return f;
}

}  // namespace

std::optional<StopForecast> forecastStop(const std::vector<ProgressPoint>& history, int passesTotal,
                                         double targetError, double timeLimit,
                                         int minTargetPasses) {
    if (history.empty() || history.back().passes <= 0) return std::nullopt;
    const ProgressPoint& last = history.back();
    // The pace of the recent passes: over the points of this history (a resumed render's history
    // may start late), else the mean.
    const ProgressPoint& first = history.front();
    double perPass = last.passes > first.passes
                         ? (last.seconds - first.seconds) / double(last.passes - first.passes)
                         : last.seconds / double(last.passes);
    perPass = std::max(perPass, 0.0);

    StopForecast f;
    f.totalPasses = double(passesTotal);
    f.reason = StopReason::Spp;
    if (targetError > 0) {
        if (std::isfinite(last.relativeError) && last.relativeError <= targetError) {
            // Reached, though a render with the maps' bias goes on to its fewest passes.
            f.totalPasses = std::max(last.passes, minTargetPasses);
            f.reason = StopReason::TargetError;
            if (f.totalPasses > passesTotal) {
                f.totalPasses = passesTotal;
                f.reason = StopReason::Spp;
            }
        } else if (std::optional<Fit> fit = fitRate(history)) {
            f.slope = fit->slope;
            // error(N) = error(n) (N / n)^slope; a rate flatter than -0.05 never gets there.
            if (fit->slope < -0.05) {
                double logRatio = (std::log(targetError) - fit->logErrorAtLast) / fit->slope;
                double passes = std::max(double(last.passes) * std::exp(std::min(logRatio, 50.0)),
                                         double(minTargetPasses));
                if (passes < f.totalPasses) {
                    f.totalPasses = std::max(passes, double(last.passes));
                    f.reason = StopReason::TargetError;
                }
            }
        }
    }
    f.secondsLeft = std::max(0.0, f.totalPasses - double(last.passes)) * perPass;
    if (timeLimit > 0 && timeLimit - last.seconds < f.secondsLeft) {
        f.secondsLeft = std::max(0.0, timeLimit - last.seconds);
        f.reason = StopReason::TimeLimit;
    }
    return f;
}

}  // namespace caustic
