// The pass-based film: per pixel, the sum and sum of squares (in double) of independent pass
// estimates. From it come the image (the mean), the per-pixel standard error, the whole-image error
// estimate, checkpoints, and merging of passes rendered elsewhere (add the sums).
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace caustic {

class Film {
public:
    Film(int width, int height);

    /// Adds one pass: one estimate of every pixel, row-major, top row first. Not thread-safe.
    void addPass(const std::vector<Color>& pass);
    /// Adds another film's passes (same size): the result is as if its passes had been added here.
    void merge(const Film& other);
    /// Counts samples dropped for being NaN or infinite.
    void addDropped(uint64_t count) { dropped_ += count; }

    int width() const { return width_; }
    int height() const { return height_; }
    int passes() const { return passes_; }
    uint64_t droppedSamples() const { return dropped_; }

    /// Mean of the pass estimates at a pixel; zero before the first pass.
    Color mean(int x, int y) const;
    /// Standard error of the mean at a pixel, sqrt(s^2 / n) with s^2 the unbiased sample variance
    /// of the passes; zero with fewer than two passes.
    Color standardError(int x, int y) const;
    /// The mean image as interleaved RGB floats, row-major.
    std::vector<float> meanRgb() const;
    /// The standard error image as interleaved RGB floats.
    std::vector<float> standardErrorRgb() const;
    /// Relative RMS error of the image: sqrt(sum of squared standard errors / sum of squared means)
    /// over all pixels and channels. NaN with fewer than two passes.
    double relativeError() const;

    /// Raw accumulators (per pixel and channel, interleaved), for checkpoints.
    const std::vector<double>& sums() const { return sum_; }
    const std::vector<double>& sumsOfSquares() const { return sumSq_; }
    /// Restores accumulators saved from a film of the same size.
    void restore(std::vector<double> sum, std::vector<double> sumSq, int passes, uint64_t dropped);
    size_t memoryBytes() const { return (sum_.capacity() + sumSq_.capacity()) * sizeof(double); }

private:
    double variance(size_t i) const;

    int width_, height_;
    int passes_ = 0;
    uint64_t dropped_ = 0;
    std::vector<double> sum_;
    std::vector<double> sumSq_;
};

}  // namespace caustic
