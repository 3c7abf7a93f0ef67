#include "lights/environment_light.h"

#include <algorithm>
#include <cmath>

#include "core/sampling.h"

namespace caustic {
namespace {

constexpr float kInv2Pi = 0.5f * kInvPi;

// (u, v) of a local direction: u = atan2(x, -z) / 2 pi, v = theta / pi from +y (Mitsuba 3,
// emitters/envmap.cpp).
Vec2 equirectUv(const Vec3& d) {
    float u = std::atan2(d.x, -d.z) * kInv2Pi;
    u -= std::floor(u);
    const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) * kInvPi;
    return Vec2(std::min(u, 1.0f - 1e-7f), std::min(v, 1.0f - 1e-7f));
}

}  // namespace

EnvironmentLight::EnvironmentLight(const Color& radiance, const Bounds3& sceneBounds)
    : constant_(radiance) {
    sceneBoundingSphere(sceneBounds, center_, radius_);
    power_ = constant_ * (4.0f * kPi) * (kPi * radius_ * radius_);
}

EnvironmentLight::EnvironmentLight(RgbImage image, float rotationDegrees, float strength,
                                   const Bounds3& sceneBounds)
    : image_(std::move(image)), strength_(strength) {
    sceneBoundingSphere(sceneBounds, center_, radius_);
    const float r = radians(rotationDegrees);
    cosRotation_ = std::cos(r);
    sinRotation_ = std::sin(r);
    const int w = image_.width, h = image_.height;
    // The density over (u, v): Le sin(theta), Le the bilinear reconstruction averaged over each
    // texel (pbrt-v4 12.5.2, Image::GetSamplingDistribution). Per axis a texel's average takes
    // 3/4 of its own value and 1/8 of each neighbour's; it is positive wherever Le is.
    std::vector<float> values(size_t(w) * size_t(h));
    DVec3 integral(0.0);
    constexpr float kWeights[3] = {0.125f, 0.75f, 0.125f};
    for (int y = 0; y < h; ++y) {
        const float theta0 = kPi * float(y) / float(h), theta1 = kPi * float(y + 1) / float(h);
        const float sinTheta = std::sin(0.5f * (theta0 + theta1));
        const double rowSolidAngle = 2.0 * double(kPi) / w * (std::cos(theta0) - std::cos(theta1));
        for (int x = 0; x < w; ++x) {
            float average = 0.0f;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    average +=
                        kWeights[dy + 1] * kWeights[dx + 1] * luminance(texel(x + dx, y + dy));
            values[size_t(y) * w + x] = average * sinTheta;
            integral += DVec3(texel(x, y)) * rowSolidAngle;
        }
    }
    distribution_ = Distribution2D(values, w, h);
    // MIS compensation: the density less its average, clamped at zero (all zero: uniform).
    double mean = 0.0;
    for (float v : values) mean += double(v) / double(values.size());
    for (float& v : values) v = std::max(0.0f, float(double(v) - mean));
    compensated_ = Distribution2D(values, w, h);
    power_ = Color(integral) * strength_ * (kPi * radius_ * radius_);
}

Color EnvironmentLight::texel(int x, int y) const {
    const int w = image_.width, h = image_.height;
    x = ((x % w) + w) % w;  // longitude wraps
    y = std::clamp(y, 0, h - 1);
    const float* p = &image_.pixels[3 * (size_t(y) * w + x)];
    return Color(p[0], p[1], p[2]);
}

Vec3 EnvironmentLight::toLocal(const Vec3& w) const {
    return Vec3(cosRotation_ * w.x - sinRotation_ * w.z, w.y,
                sinRotation_ * w.x + cosRotation_ * w.z);
}

Vec3 EnvironmentLight::toWorld(const Vec3& l) const {
    return Vec3(cosRotation_ * l.x + sinRotation_ * l.z, l.y,
                -sinRotation_ * l.x + cosRotation_ * l.z);
}

Color EnvironmentLight::Le(const Vec3& w) const {
    if (image_.pixels.empty()) return constant_;
    const Vec2 uv = equirectUv(toLocal(w));
    // Bilinear between the four nearest texel centres.
    const float fx = uv.x * float(image_.width) - 0.5f, fy = uv.y * float(image_.height) - 0.5f;
    const float x0 = std::floor(fx), y0 = std::floor(fy);
    const float tx = fx - x0, ty = fy - y0;
    const int x = int(x0), y = int(y0);
    const Color top = (1.0f - tx) * texel(x, y) + tx * texel(x + 1, y);
    const Color bottom = (1.0f - tx) * texel(x, y + 1) + tx * texel(x + 1, y + 1);
    return strength_ * ((1.0f - ty) * top + ty * bottom);
}

Vec3 EnvironmentLight::sampleDirection(Vec2 u, float& pdf, bool compensated) const {
    if (image_.pixels.empty()) {
        pdf = kUniformSpherePdf;
        return sampleUniformSphere(u);
    }
    float pdfUv = 0.0f;
    const Vec2 uv = (compensated ? compensated_ : distribution_).sample(u, pdfUv);
    const float theta = kPi * uv.y, phi = 2.0f * kPi * uv.x;
    const float sinTheta = std::sin(theta);
    const Vec3 w =
        toWorld(Vec3(sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)));
    // The density pdfDirection gives the direction, which MIS weighs against: computed from w as
    // it evaluates it, not from (u, v), whose sin(theta) differs in the last bits near the poles.
    pdf = pdfUv > 0.0f ? pdfDirection(w, compensated) : 0.0f;
    return w;
}

float EnvironmentLight::pdfDirection(const Vec3& w, bool compensated) const {
    if (image_.pixels.empty()) return kUniformSpherePdf;
    const Vec3 local = toLocal(w);
    const float sinTheta = safeSqrt(1.0f - local.y * local.y);
    if (!(sinTheta > 0.0f)) return 0.0f;
    const Distribution2D& d = compensated ? compensated_ : distribution_;
    return d.pdf(equirectUv(local)) / (2.0f * kPi * kPi * sinTheta);
}

std::optional<LightSample> EnvironmentLight::sampleLi(const LightSampleContext& ref, Vec2 u) const {
    return sample(ref, u, false);
}

std::optional<LightSample> EnvironmentLight::sampleLiCompensated(const LightSampleContext& ref,
                                                                 Vec2 u) const {
    return sample(ref, u, true);
}

std::optional<LightSample> EnvironmentLight::sample(const LightSampleContext& ref, Vec2 u,
                                                    bool compensated) const {
    LightSample s;
    s.wi = sampleDirection(u, s.pdf, compensated);
    if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
    s.Li = Le(s.wi);
    // A point past the bounding sphere, for the shadow ray.
    const float far = 2.0f * radius_ + glm::length(ref.p - center_);
    s.at = SurfaceSample{ref.p + far * s.wi, Vec3(0.0f), Vec3(0.0f), 0.0f};
    return s;
}

std::optional<LightLeSample> EnvironmentLight::sampleLe(Vec2 uPosition, Vec2 uDirection) const {
    float pdfDirection = 0.0f;
    const Vec3 w = sampleDirection(uDirection, pdfDirection, false);
    if (!(pdfDirection > 0.0f) || !std::isfinite(pdfDirection)) return std::nullopt;
    Vec3 t, b;
    coordinateSystem(w, t, b);
    const Vec2 d = sampleConcentricDisk(uPosition);
    const Vec3 origin = center_ + radius_ * (w + d.x * t + d.y * b);
    // Flux per sample: Le / (p(direction) p(position)), p(position) = 1 / (pi R^2).
    const Color power = Le(w) * (kPi * radius_ * radius_ / pdfDirection);
    return LightLeSample{Ray{origin, -w}, power};
}

size_t EnvironmentLight::memoryBytes() const {
    return image_.pixels.capacity() * sizeof(float) + distribution_.memoryBytes() +
           compensated_.memoryBytes();
}

}  // namespace caustic
