// The pass-based film: per pixel, the sum and sum of squares of independent pass estimates, in
// exact fixed point (film/exact_sum.h), and the set of passes it holds. From it come the image
// (the mean), the per-pixel standard error, the whole-image error estimate, checkpoints, and
// merging of passes rendered elsewhere: films holding disjoint pass ranges, merged in any order,
// hold the very bits of one film that added every pass.
//
// A film of a biased estimator (photon maps) has a second layer: each pass's estimate of its own
// bias at every pixel (the integrator's, e.g. from two kernel radii), summed as the image is. The
// bias of the mean image is the mean of the passes' biases, so the layer's mean estimates it, and
// its pass variance says how well; the error estimate adds it to the noise.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/math.h"
#include "film/exact_sum.h"
#include "film/pass_set.h"

namespace caustic {

class Film {
public:
    /// `bias`: whether the film has the bias layer (then every pass brings its bias image).
    Film(int width, int height, bool bias = false);

    /// Adds pass `index` (0 <= index < exact::kMaxPasses): one estimate of every pixel's radiance
    /// (W/(m^2 sr) per linear RGB channel), row-major, top row first, with the samples it dropped.
    /// A film with the bias layer takes twice the pixels: the image, then the pass's estimate of
    /// its own bias at each pixel (the expected value of the pixel's estimate less the true
    /// radiance). Throws std::invalid_argument if the film holds that pass or the size is not the
    /// film's. Not thread-safe; it runs on `threads` OpenMP threads itself (0: OpenMP's default).
    void addPass(int index, const std::vector<Color>& pass, uint64_t dropped = 0, int threads = 0);
    /// Adds the pass after the highest one held.
    void addPass(const std::vector<Color>& pass) { addPass(passSet_.end(), pass); }
    /// Adds another film's passes (same size and layers; throws std::invalid_argument, changing
    /// nothing, if a pass is held by both or the sizes or layers differ). Exact: any order of
    /// merges gives one result.
    void merge(const Film& other);

    int width() const { return width_; }
    int height() const { return height_; }
    int passes() const { return passSet_.count(); }
    /// Whether the film has the bias layer.
    bool tracksBias() const { return sum_.size() > values(); }
    /// Pixels of a pass: width x height, twice that with the bias layer.
    size_t passPixels() const { return sum_.size() / 3; }
    const PassSet& passSet() const { return passSet_; }
    /// Samples dropped for being NaN or infinite.
    uint64_t droppedSamples() const { return dropped_; }
    /// Pass values out of the fixed-point range: clamped (|v| >= 2^35) or not a number (counted
    /// as 0; film/exact_sum.h).
    uint64_t clampedValues() const { return clamped_; }

    /// Mean of the pass estimates at a pixel; zero before the first pass.
    Color mean(int x, int y) const;
    /// Standard error of the mean at a pixel, sqrt(s^2 / n) with s^2 the unbiased sample variance
    /// of the passes; zero with fewer than two passes.
    Color standardError(int x, int y) const;
    /// The mean image as interleaved RGB floats, row-major.
    std::vector<float> meanRgb() const;
    /// The standard error image as interleaved RGB floats.
    std::vector<float> standardErrorRgb() const;
    /// The bias of the mean image at a pixel as the bias layer estimates it (the layer's mean);
    /// zero without the layer or before the first pass.
    Color bias(int x, int y) const;
    /// The bias layer's mean as interleaved RGB floats (zeros without the layer).
    std::vector<float> biasRgb() const;

    /// Relative RMS error of the image: sqrt((noise^2 + bias^2) / sum of squared means) over all
    /// pixels and channels, noise^2 the sum of squared standard errors and bias^2 the sum of the
    /// bias layer's squared means less their squared standard errors (an unbiased estimate of the
    /// sum of squared biases; 0 when it comes out negative). NaN with fewer than two passes.
    /// Computed once per change of the film (over fixed blocks of pixels added in block order: the
    /// same bits on any number of threads), so reading it is free.
    double relativeError() const { return relativeError_; }
    /// Its two parts, each relative to the same sum of squared means: relativeError()^2 =
    /// relativeNoise()^2 + relativeBias()^2. relativeBias() is 0 without the bias layer.
    double relativeNoise() const { return relativeNoise_; }
    double relativeBias() const { return relativeBias_; }

    /// The image layer's sums and sums of squares per pixel and channel (interleaved), rounded to
    /// double.
    std::vector<double> sums() const;
    std::vector<double> sumsOfSquares() const;
    /// Same size, passes, counters and accumulators, bit for bit.
    bool operator==(const Film& other) const;

    /// The whole film as bytes (a checkpoint, or a pass range sent elsewhere), compactly and
    /// exactly (film_bytes.cpp: about a third of memoryBytes() for a rendered image), and back:
    /// null for bytes that are not a film of width x height (torn or foreign).
    std::string toBytes() const;
    static std::unique_ptr<Film> fromBytes(std::string_view bytes, int width, int height);
    /// The width and height toBytes() wrote in `bytes`; nothing for bytes that are no film.
    static std::optional<std::pair<int, int>> sizeOf(std::string_view bytes);

    size_t memoryBytes() const { return bytesFor(width_, height_, tracksBias()); }
    /// Bytes of a film of this size (with the bias layer, twice as many).
    static size_t bytesFor(int width, int height, bool bias = false);

private:
    /// Values of one layer: three a pixel. The bias layer's follow the image's in sum_ and sumSq_.
    size_t values() const { return size_t(width_) * size_t(height_) * 3; }
    double variance(size_t i) const;
    void updateRelativeError(int threads);
    /// Reads the accumulators of toBytes()'s compact body; false for bytes that are not one.
    bool readCompact(std::string_view bytes);

    int width_, height_;
    PassSet passSet_;
    uint64_t dropped_ = 0;
    uint64_t clamped_ = 0;
    double relativeError_ = std::nan("");
    double relativeNoise_ = std::nan("");
    double relativeBias_ = std::nan("");
    std::vector<exact::Int128> sum_;
    std::vector<exact::Wide192> sumSq_;
};

}  // namespace caustic
