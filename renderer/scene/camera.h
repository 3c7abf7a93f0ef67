// A pinhole camera with a vertical field of view. Raster space: x right, y down, pixel (i, j)
// covers [i, i+1) x [j, j+1).
#pragma once

#include "core/ray.h"

namespace caustic {

class Camera {
public:
    Camera() = default;
    /// fovDegrees is the vertical field of view, in (0, 180). Requires position != lookAt and up
    /// not parallel to the viewing direction (the scene loader checks both).
    Camera(const Vec3& position, const Vec3& lookAt, const Vec3& up, float fovDegrees, int width,
           int height);

    /// The primary ray through raster point (x, y); unit direction. Thread-safe.
    Ray generateRay(float x, float y) const {
        float sx = (2.0f * x / static_cast<float>(width_) - 1.0f) * tanHalfX_;
        float sy = (1.0f - 2.0f * y / static_cast<float>(height_)) * tanHalfY_;
        return Ray{position_, glm::normalize(forward_ + sx * right_ + sy * up_)};
    }

    /// The raster point whose primary ray passes through world point p (generateRay's inverse);
    /// false when p is not in front of the camera.
    bool raster(const Vec3& p, float& x, float& y) const {
        Vec3 v = p - position_;
        float z = glm::dot(v, forward_);
        if (!(z > 0.0f)) return false;
        x = (glm::dot(v, right_) / (z * tanHalfX_) + 1.0f) * 0.5f * static_cast<float>(width_);
        y = (1.0f - glm::dot(v, up_) / (z * tanHalfY_)) * 0.5f * static_cast<float>(height_);
        return true;
    }

    /// How far a point p on a surface of unit normal n moves per pixel across the image, in dpdx
    /// and dpdy: the rays through the neighbouring pixels met on the plane of p, as pbrt-v4's
    /// CameraBase::Approximate_dp_dxy (10.1.1) does at every bounce of every path, and scaled by
    /// `scale` (a pixel's share of its samples). Zero where a neighbouring ray misses the plane.
    void approximateDpDxy(const Vec3& p, const Vec3& n, float scale, Vec3& dpdx, Vec3& dpdy) const;

    /// The same camera with another image size: the vertical field of view is kept, the
    /// horizontal one follows the new aspect ratio. Requires width, height >= 1.
    Camera resized(int width, int height) const;

    int width() const { return width_; }
    int height() const { return height_; }
    const Vec3& position() const { return position_; }
    const Vec3& forward() const { return forward_; }

private:
    Vec3 position_{0.0f}, forward_{0.0f, 0.0f, -1.0f}, right_{1.0f, 0.0f, 0.0f},
        up_{0.0f, 1.0f, 0.0f};
    float tanHalfX_ = 1.0f, tanHalfY_ = 1.0f;
    int width_ = 1, height_ = 1;
};

}  // namespace caustic
