#include "scene/camera.h"

namespace caustic {

Camera::Camera(const Vec3& position, const Vec3& lookAt, const Vec3& up, float fovDegrees,
               int width, int height)
    : position_(position), width_(width), height_(height) {
    forward_ = glm::normalize(lookAt - position);
    right_ = glm::normalize(glm::cross(forward_, up));
    up_ = glm::cross(right_, forward_);
    tanHalfY_ = std::tan(0.5f * fovDegrees * kPi / 180.0f);
    tanHalfX_ = tanHalfY_ * static_cast<float>(width) / static_cast<float>(height);
}

void Camera::approximateDpDxy(const Vec3& p, const Vec3& n, float scale, Vec3& dpdx,
                              Vec3& dpdy) const {
    dpdx = dpdy = Vec3(0.0f);
    const Vec3 toP = p - position_;
    const float distance = glm::length(toP);
    if (!(distance > 0.0f)) return;
    const Vec3 d = toP / distance;
    const float along = glm::dot(n, toP);
    // A pixel's angular size at the image's centre, turned to be perpendicular to the ray to p.
    auto offset = [&](const Vec3& axis, float pixelAngle) {
        const Vec3 across = axis - d * glm::dot(d, axis);
        const float length = glm::length(across);
        if (!(length > 0.0f)) return Vec3(0.0f);
        const Vec3 ray = d + across * (pixelAngle / length);
        const float cosine = glm::dot(n, ray);
        if (std::abs(cosine) < 1e-6f) return Vec3(0.0f);
        const Vec3 hit = position_ + ray * (along / cosine);
        const Vec3 dp = (hit - p) * scale;
        return isFinite(dp) ? dp : Vec3(0.0f);
    };
    dpdx = offset(right_, 2.0f * tanHalfX_ / static_cast<float>(width_));
    dpdy = offset(-up_, 2.0f * tanHalfY_ / static_cast<float>(height_));
}

Camera Camera::resized(int width, int height) const {
    Camera c = *this;
    c.width_ = width;
    c.height_ = height;
    c.tanHalfX_ = tanHalfY_ * static_cast<float>(width) / static_cast<float>(height);
    return c;
}

}  // namespace caustic
