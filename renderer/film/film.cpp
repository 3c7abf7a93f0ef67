#include "film/film.h"

#include <omp.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace caustic {

Film::Film(int width, int height, bool bias)
    : width_(width),
      height_(height),
      sum_(size_t(width) * size_t(height) * (bias ? 6 : 3), 0),
      sumSq_(size_t(width) * size_t(height) * (bias ? 6 : 3)) {}

namespace {

// Films hold at most exact::kMaxPasses passes, numbered below it: the sums' range needs it.
void checkPassCount(const PassSet& held, int more) {
    if (held.end() > exact::kMaxPasses || held.count() + more > exact::kMaxPasses)
        throw std::invalid_argument("a film holds at most " + std::to_string(exact::kMaxPasses) +
                                    " passes, numbered below that");
}

}  // namespace

void Film::addPass(int index, const std::vector<Color>& pass, uint64_t dropped, int threads) {
    if (pass.size() != passPixels())
        throw std::invalid_argument("a pass of " + std::to_string(pass.size()) +
                                    " pixels for a film of " + std::to_string(passPixels()) +
                                    (tracksBias() ? " (an image and its bias)" : ""));
    if (index < 0 || index >= exact::kMaxPasses)
        throw std::invalid_argument("pass index " + std::to_string(index) + " out of range");
    checkPassCount(passSet_, 1);
    passSet_.insert(index, index + 1);
    static_assert(sizeof(Color) == 3 * sizeof(float), "a pass is read as interleaved floats");
    const float* values = pass.empty() ? nullptr : &pass[0][0];
    const int64_t n = int64_t(sum_.size());
    uint64_t clamped = 0;
    // Every thread the render had idles while a pass is added: share the work (a large film).
    const int team = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for schedule(static) reduction(+ : clamped) num_threads(team) if (n > 262144)
    for (int64_t i = 0; i < n; ++i)
        clamped += exact::accumulate(values[i], sum_[size_t(i)], sumSq_[size_t(i)]);
    clamped_ += clamped;
    dropped_ += dropped;
    updateRelativeError(team);
}

void Film::merge(const Film& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw std::invalid_argument(
            "cannot merge a " + std::to_string(other.width_) + "x" + std::to_string(other.height_) +
            " film into a " + std::to_string(width_) + "x" + std::to_string(height_) + " one");
    if (other.tracksBias() != tracksBias())
        throw std::invalid_argument("cannot merge a film with and one without the bias layer");
    checkPassCount(passSet_, other.passes());
    passSet_.insert(other.passSet_);  // throws before anything changes
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < sum_.size(); ++i) {
        sum_[i] += other.sum_[i];
        sumSq_[i].add(other.sumSq_[i]);
    }
    dropped_ += other.dropped_;
    clamped_ += other.clamped_;
    updateRelativeError(0);
}

double Film::variance(size_t i) const {
    const int n = passes();
    if (n < 2) return 0.0;
    double mean = exact::sumToDouble(sum_[i]) / n;
    // Unbiased sample variance; clamped since cancellation can make it slightly negative.
    return std::max(0.0, (exact::squaresToDouble(sumSq_[i]) - n * mean * mean) / (n - 1.0));
}

Color Film::mean(int x, int y) const {
    size_t i = 3 * (size_t(y) * size_t(width_) + size_t(x));
    Color m(0.0f);
    if (passes() == 0) return m;
    for (int c = 0; c < 3; ++c) m[c] = float(exact::sumToDouble(sum_[i + size_t(c)]) / passes());
    return m;
}

Color Film::standardError(int x, int y) const {
    size_t i = 3 * (size_t(y) * size_t(width_) + size_t(x));
    Color se;
    for (int c = 0; c < 3; ++c)
        se[c] = float(std::sqrt(variance(i + size_t(c)) / std::max(passes(), 1)));
    return se;
}

std::vector<float> Film::meanRgb() const {
    std::vector<float> out(values(), 0.0f);
    if (passes() == 0) return out;
    for (size_t i = 0; i < values(); ++i) out[i] = float(exact::sumToDouble(sum_[i]) / passes());
    return out;
}

std::vector<float> Film::standardErrorRgb() const {
    std::vector<float> out(values(), 0.0f);
    for (size_t i = 0; i < values(); ++i)
        out[i] = float(std::sqrt(variance(i) / std::max(passes(), 1)));
    return out;
}

Color Film::bias(int x, int y) const {
    Color b(0.0f);
    if (!tracksBias() || passes() == 0) return b;
    const size_t i = values() + 3 * (size_t(y) * size_t(width_) + size_t(x));
    for (int c = 0; c < 3; ++c) b[c] = float(exact::sumToDouble(sum_[i + size_t(c)]) / passes());
    return b;
}

std::vector<float> Film::biasRgb() const {
    std::vector<float> out(values(), 0.0f);
    if (!tracksBias() || passes() == 0) return out;
    for (size_t i = 0; i < values(); ++i)
        out[i] = float(exact::sumToDouble(sum_[values() + i]) / passes());
    return out;
}

void Film::updateRelativeError(int threads) {
    const int n = passes();
    if (n < 2) {
        relativeError_ = relativeNoise_ = relativeBias_ = std::nan("");
        return;
    }
    // Partial sums over fixed blocks, added in block order: the bits do not depend on threads.
    constexpr size_t kBlock = 3 * 1024;
    const size_t count = values();
    const bool bias = tracksBias();
    const int64_t blocks = int64_t((count + kBlock - 1) / kBlock);
    std::vector<double> err2(size_t(blocks), 0.0), mean2(size_t(blocks), 0.0),
        bias2(size_t(blocks), 0.0);
    const int team = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for schedule(static) num_threads(team) if (blocks > 64)
    for (int64_t b = 0; b < blocks; ++b) {
        size_t end = std::min(count, size_t(b + 1) * kBlock);
        for (size_t i = size_t(b) * kBlock; i < end; ++i) {
            double m = exact::sumToDouble(sum_[i]) / n;
            err2[size_t(b)] += variance(i) / n;
            mean2[size_t(b)] += m * m;
            if (bias) {
                // E[mean^2] = bias^2 + variance / n: the square less its noise.
                double mb = exact::sumToDouble(sum_[count + i]) / n;
                bias2[size_t(b)] += mb * mb - variance(count + i) / n;
            }
        }
    }
    double e = 0.0, m = 0.0, b2 = 0.0;
    for (int64_t b = 0; b < blocks; ++b) {
        e += err2[size_t(b)];
        m += mean2[size_t(b)];
        b2 += bias2[size_t(b)];
    }
    b2 = std::max(0.0, b2);
    relativeNoise_ = m > 0.0 ? std::sqrt(e / m) : 0.0;
    relativeBias_ = m > 0.0 ? std::sqrt(b2 / m) : 0.0;
    relativeError_ = m > 0.0 ? std::sqrt((e + b2) / m) : 0.0;
}

std::vector<double> Film::sums() const {
    std::vector<double> out(values());
    for (size_t i = 0; i < values(); ++i) out[i] = exact::sumToDouble(sum_[i]);
    return out;
}

std::vector<double> Film::sumsOfSquares() const {
    std::vector<double> out(values());
    for (size_t i = 0; i < values(); ++i) out[i] = exact::squaresToDouble(sumSq_[i]);
    return out;
}

bool Film::operator==(const Film& o) const {
    return width_ == o.width_ && height_ == o.height_ && passSet_ == o.passSet_ &&
           dropped_ == o.dropped_ && clamped_ == o.clamped_ && sum_ == o.sum_ && sumSq_ == o.sumSq_;
}

size_t Film::bytesFor(int width, int height, bool bias) {
    return size_t(width) * size_t(height) * (bias ? 6 : 3) *
           (sizeof(exact::Int128) + sizeof(exact::Wide192));
}

}  // namespace caustic
