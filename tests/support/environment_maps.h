// Environment images for tests: a sky with a small, bright sun (the hard case for sampling).
#pragma once

#include <cmath>

#include "core/math.h"
#include "film/image_io.h"

namespace caustic::testing {

/// A width x height equirectangular sky: radiance from 0.2 at the horizon to 1 at the zenith (blue
/// tinted, black below the horizon), and a sun of `sunTexels` x `sunTexels` texels of radiance
/// `sun` centred at texel (sunX, sunY).
inline RgbImage skyWithSun(int width, int height, int sunX, int sunY, int sunTexels = 2,
                           float sun = 5000.0f) {
    RgbImage image{width, height, std::vector<float>(size_t(width) * height * 3)};
    for (int y = 0; y < height; ++y) {
        const float cosTheta = std::cos(kPi * (float(y) + 0.5f) / float(height));
        const float sky = cosTheta > 0.0f ? 0.2f + 0.8f * cosTheta : 0.0f;
        for (int x = 0; x < width; ++x) {
            const bool inSun =
                std::abs(x - sunX) * 2 < sunTexels && std::abs(y - sunY) * 2 < sunTexels;
            const Color c =
                inSun ? Color(sun, 0.9f * sun, 0.8f * sun) : Color(0.6f * sky, 0.8f * sky, sky);
            float* p = &image.pixels[3 * (size_t(y) * width + x)];
            p[0] = c.r;
            p[1] = c.g;
            p[2] = c.b;
        }
    }
    return image;
}

}  // namespace caustic::testing
