#include "core/distribution.h"

#include <algorithm>
#include <limits>

namespace caustic {

Distribution1D::Distribution1D(std::vector<float> values)
    : values_(std::move(values)), cdf_(values_.size() + 1, 0.0) {
    const size_t n = values_.size();
    for (size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + double(values_[i]) / double(n);
    integral_ = cdf_[n];
    if (!(integral_ > 0.0)) {
        // Nothing to prefer: uniform.
        std::fill(values_.begin(), values_.end(), 1.0f);
        for (size_t i = 0; i < n; ++i) cdf_[i + 1] = double(i + 1) / double(n);
        integral_ = 0.0;
    } else {
        for (size_t i = 1; i <= n; ++i) cdf_[i] /= integral_;
    }
    cdf_[n] = 1.0;
}

float Distribution1D::sample(float u, float& pdf, size_t& index) const {
    // The last interval whose CDF start is <= u, skipping zero-width ones (u never lands there).
    auto it = std::upper_bound(cdf_.begin(), cdf_.end(), double(u));
    index = std::min(size_t(std::max<ptrdiff_t>(it - cdf_.begin() - 1, 0)), values_.size() - 1);
    const double width = cdf_[index + 1] - cdf_[index];
    const double within = width > 0.0 ? (double(u) - cdf_[index]) / width : 0.0;
    const double norm = integral_ > 0.0 ? integral_ : 1.0;
    pdf = float(double(values_[index]) / norm);
    const float x = float((double(index) + std::clamp(within, 0.0, 1.0)) / double(values_.size()));
    return std::min(x, 1.0f - std::numeric_limits<float>::epsilon() / 2.0f);
}

float Distribution1D::pdf(float x) const {
    if (values_.empty()) return 0.0f;
    const size_t i =
        std::min(size_t(std::max(x, 0.0f) * float(values_.size())), values_.size() - 1);
    const double norm = integral_ > 0.0 ? integral_ : 1.0;
    return float(double(values_[i]) / norm);
}

Distribution2D::Distribution2D(const std::vector<float>& values, int width, int height) {
    std::vector<float> rowIntegrals(static_cast<size_t>(height));
    rows_.reserve(size_t(height));
    for (int y = 0; y < height; ++y) {
        auto begin = values.begin() + ptrdiff_t(y) * width;
        rows_.emplace_back(std::vector<float>(begin, begin + width));
        rowIntegrals[size_t(y)] = float(rows_.back().integral());
    }
    marginal_ = Distribution1D(std::move(rowIntegrals));
}

Vec2 Distribution2D::sample(Vec2 u, float& pdf) const {
    float pdfV = 0.0f, pdfU = 0.0f;
    size_t row = 0, column = 0;
    const float v = marginal_.sample(u.y, pdfV, row);
    const float x = rows_[row].sample(u.x, pdfU, column);
    pdf = pdfV * pdfU;
    return Vec2(x, v);
}

float Distribution2D::pdf(Vec2 p) const {
    if (rows_.empty()) return 0.0f;
    const size_t row =
        std::min(size_t(std::max(p.y, 0.0f) * float(rows_.size())), rows_.size() - 1);
    return marginal_.pdf(p.y) * rows_[row].pdf(p.x);
}

size_t Distribution2D::memoryBytes() const {
    size_t bytes = marginal_.memoryBytes() + rows_.capacity() * sizeof(Distribution1D);
    for (const Distribution1D& r : rows_) bytes += r.memoryBytes();
    return bytes;
}

}  // namespace caustic
