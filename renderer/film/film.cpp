#include "film/film.h"

#include "core/check.h"

namespace caustic {

Film::Film(int width, int height)
    : width_(width),
      height_(height),
      sum_(size_t(width) * size_t(height) * 3, 0.0),
      sumSq_(size_t(width) * size_t(height) * 3, 0.0) {}

void Film::addPass(const std::vector<Color>& pass) {
    CAUSTIC_CHECK_EQ(pass.size() * 3, sum_.size());
    for (size_t p = 0; p < pass.size(); ++p) {
        for (int c = 0; c < 3; ++c) {
            double v = pass[p][c];
            sum_[3 * p + c] += v;
            sumSq_[3 * p + c] += v * v;
        }
    }
    ++passes_;
}

void Film::merge(const Film& other) {
    CAUSTIC_CHECK(other.width_ == width_ && other.height_ == height_);
    for (size_t i = 0; i < sum_.size(); ++i) {
        sum_[i] += other.sum_[i];
        sumSq_[i] += other.sumSq_[i];
    }
    passes_ += other.passes_;
    dropped_ += other.dropped_;
}

double Film::variance(size_t i) const {
    if (passes_ < 2) return 0.0;
    double n = passes_;
    double mean = sum_[i] / n;
    // Unbiased sample variance; clamped since cancellation can make it slightly negative.
    return std::max(0.0, (sumSq_[i] - n * mean * mean) / (n - 1.0));
}

Color Film::mean(int x, int y) const {
    size_t i = 3 * (size_t(y) * size_t(width_) + size_t(x));
    if (passes_ == 0) return Color(0.0f);
    return Color(float(sum_[i] / passes_), float(sum_[i + 1] / passes_),
                 float(sum_[i + 2] / passes_));
}

Color Film::standardError(int x, int y) const {
    size_t i = 3 * (size_t(y) * size_t(width_) + size_t(x));
    Color se;
    for (int c = 0; c < 3; ++c) se[c] = float(std::sqrt(variance(i + c) / std::max(passes_, 1)));
    return se;
}

std::vector<float> Film::meanRgb() const {
    std::vector<float> out(sum_.size(), 0.0f);
    if (passes_ == 0) return out;
    for (size_t i = 0; i < sum_.size(); ++i) out[i] = float(sum_[i] / passes_);
    return out;
}

std::vector<float> Film::standardErrorRgb() const {
    std::vector<float> out(sum_.size(), 0.0f);
    for (size_t i = 0; i < sum_.size(); ++i)
        out[i] = float(std::sqrt(variance(i) / std::max(passes_, 1)));
    return out;
}

double Film::relativeError() const {
    if (passes_ < 2) return std::nan("");
    double err2 = 0.0, mean2 = 0.0;
    for (size_t i = 0; i < sum_.size(); ++i) {
        double m = sum_[i] / passes_;
        err2 += variance(i) / passes_;
        mean2 += m * m;
    }
    return mean2 > 0.0 ? std::sqrt(err2 / mean2) : 0.0;
}

void Film::restore(std::vector<double> sum, std::vector<double> sumSq, int passes,
                   uint64_t dropped) {
    CAUSTIC_CHECK_EQ(sum.size(), sum_.size());
    CAUSTIC_CHECK_EQ(sumSq.size(), sumSq_.size());
    sum_ = std::move(sum);
    sumSq_ = std::move(sumSq);
    passes_ = passes;
    dropped_ = dropped;
}

}  // namespace caustic
