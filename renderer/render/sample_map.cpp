#include "render/sample_map.h"

#include <algorithm>
#include <cmath>

namespace caustic {

std::vector<uint16_t> adaptiveSampleMap(const Film& pilot, int sppPerPass) {
    const int width = pilot.width(), height = pilot.height();
    const size_t pixels = size_t(width) * size_t(height);
    // The standard error of the pilot's mean is sigma / sqrt(passes * sppPerPass) for every pixel
    // alike, so it is proportional to sigma.
    std::vector<double> sigma(pixels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            Color se = pilot.standardError(x, y);
            sigma[size_t(y) * size_t(width) + size_t(x)] =
                std::sqrt(double(se.r) * se.r + double(se.g) * se.g + double(se.b) * se.b);
        }
    std::vector<double> weight(pixels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double sum = 0;
            int n = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= width || yy >= height) continue;
                    sum += sigma[size_t(yy) * size_t(width) + size_t(xx)];
                    ++n;
                }
            weight[size_t(y) * size_t(width) + size_t(x)] = sum / n;
        }

    const double least = std::max(1, sppPerPass / 4), most = 8.0 * sppPerPass;
    const double budget = double(sppPerPass) * double(pixels);
    auto samples = [&](double scale) {
        double total = 0;
        for (double w : weight) total += std::clamp(scale * w, least, most);
        return total;
    };
    // The scale whose clamped allocation spends the budget: total(scale) grows with scale, from
    // pixels * least at 0; bisection in the order of doubles, the same on every machine.
    double maxWeight = *std::max_element(weight.begin(), weight.end());
    std::vector<uint16_t> map(pixels, uint16_t(std::min(sppPerPass, 65535)));
    if (!(maxWeight > 0) || samples(0) >= budget) return map;
    double lo = 0, hi = most / maxWeight;
    while (samples(hi) < budget && hi < 1e300) hi *= 2;
    for (int i = 0; i < 100; ++i) {
        double mid = 0.5 * (lo + hi);
        (samples(mid) < budget ? lo : hi) = mid;
    }
    for (size_t i = 0; i < pixels; ++i)
        map[i] =
            uint16_t(std::min(65535.0, std::floor(std::clamp(hi * weight[i], least, most) + 0.5)));
    return map;
}

}  // namespace caustic
