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

Camera Camera::resized(int width, int height) const {
    Camera c = *this;
    c.width_ = width;
    c.height_ = height;
    c.tanHalfX_ = tanHalfY_ * static_cast<float>(width) / static_cast<float>(height);
    return c;
}

}  // namespace caustic
