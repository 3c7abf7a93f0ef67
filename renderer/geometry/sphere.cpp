#include "geometry/sphere.h"

#include "core/sampling.h"

namespace caustic {

std::optional<float> Sphere::intersect(const Ray& ray, float tMax) const {
    // Quadratic with the discriminant written as r^2 - |f + (b/a) d|^2, which keeps its precision
    // for rays far from a small sphere (Haines et al., Ray Tracing Gems, chapter 7).
    Vec3 f = ray.o - center;
    float a = glm::dot(ray.d, ray.d);
    float b = -glm::dot(f, ray.d);
    Vec3 l = f + (b / a) * ray.d;
    float disc = a * (radius * radius - glm::dot(l, l));
    if (disc < 0.0f) return std::nullopt;
    float c = glm::dot(f, f) - radius * radius;
    float q = b + std::copysign(std::sqrt(disc), b);
    float t0 = c / q, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    float t = t0 > 0.0f ? t0 : t1;
    if (!(t > 0.0f && t < tMax)) return std::nullopt;
    return t;
}

Vec2 Sphere::uv(const Vec3& point) const {
    Vec3 p = glm::normalize(point - center);
    float phi = std::atan2(p.y, p.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    float theta = std::acos(std::clamp(p.z, -1.0f, 1.0f));
    return Vec2(phi / (2.0f * kPi), theta / kPi);
}

void Sphere::hitPoint(const Ray& ray, float t, Vec3& p, Vec3& pError) const {
    // Reproject onto the surface: the error is then that of the projection (pbrt-v4, 6.8.5) plus
    // the rounding of adding the center back.
    Vec3 local = ray.o + t * ray.d - center;
    local *= radius / glm::length(local);
    p = center + local;
    pError = gamma(5) * glm::abs(local) + gamma(1) * glm::abs(p);
}

namespace {

// The point at outward unit direction n from the center, with the error bound of hitPoint.
SurfaceSample pointAt(const Sphere& sphere, const Vec3& n) {
    Vec3 local = sphere.radius * n;
    SurfaceSample s;
    s.p = sphere.center + local;
    s.pError = gamma(5) * glm::abs(local) + gamma(1) * glm::abs(s.p);
    s.n = sphere.flipped ? -n : n;
    return s;
}

// Below sin^2(1.5 degrees), 1 - cos(theta_max) loses its digits to cancellation: use the Taylor
// expansion sin^2 / 2 instead (pbrt-v4, Sphere::Sample).
constexpr float kSmallSin2 = 0.00068523f;

float oneMinusCosThetaMax(float sin2ThetaMax) {
    if (sin2ThetaMax < kSmallSin2) return 0.5f * sin2ThetaMax;
    return 1.0f - std::sqrt(std::max(0.0f, 1.0f - sin2ThetaMax));
}

}  // namespace

SurfaceSample Sphere::sample(Vec2 u) const {
    SurfaceSample s = pointAt(*this, sampleUniformSphere(u));
    s.pdfArea = 1.0f / area();
    return s;
}

std::optional<SurfaceSample> Sphere::sampleCone(const Vec3& ref, Vec2 u, float& pdf) const {
    Vec3 toCenter = center - ref;
    float dist2 = glm::dot(toCenter, toCenter);
    if (!(dist2 > radius * radius)) return std::nullopt;
    float dist = std::sqrt(dist2);
    float sinThetaMax = radius / dist;
    float sin2ThetaMax = sinThetaMax * sinThetaMax;
    float oneMinusCos = oneMinusCosThetaMax(sin2ThetaMax);

    // theta: angle from the axis at ref, uniform in cos theta over the cone.
    float cosTheta = 1.0f - oneMinusCos * u.x;
    float sin2Theta = 1.0f - cosTheta * cosTheta;
    if (sin2ThetaMax < kSmallSin2) {
        sin2Theta = sin2ThetaMax * u.x;
        cosTheta = std::sqrt(1.0f - sin2Theta);
    }
    // alpha: angle at the center between the axis (back towards ref) and the sampled point.
    float cosAlpha = sin2Theta / sinThetaMax +
                     cosTheta * std::sqrt(std::max(0.0f, 1.0f - sin2Theta / sin2ThetaMax));
    float sinAlpha = std::sqrt(std::max(0.0f, 1.0f - cosAlpha * cosAlpha));
    float phi = 2.0f * kPi * u.y;
    Vec3 local(sinAlpha * std::cos(phi), sinAlpha * std::sin(phi), cosAlpha);
    Vec3 n = -fromLocal(local, toCenter / dist);
    pdf = 1.0f / (2.0f * kPi * oneMinusCos);
    SurfaceSample s = pointAt(*this, glm::normalize(n));
    s.pdfArea = 0.0f;  // the density is per solid angle: `pdf`
    return s;
}

float Sphere::coneSolidAnglePdf(const Vec3& ref) const {
    Vec3 toCenter = center - ref;
    float dist2 = glm::dot(toCenter, toCenter);
    if (!(dist2 > radius * radius)) return 0.0f;
    float sinThetaMax = radius / std::sqrt(dist2);  // as in sampleCone, to the last bit
    return 1.0f / (2.0f * kPi * oneMinusCosThetaMax(sinThetaMax * sinThetaMax));
}

}  // namespace caustic
