// A material at one surface point: its BSDF in the point's shading frame (pbrt-v4 10.1: a BSDF
// lives in the shading frame alone). Integrators and photon tracing scatter only through it.
//
// With interpolated vertex normals the shading normal ns differs from the geometric normal n. Where
// they disagree about a pair of directions (light just behind a coarse mesh's flat face but in
// front of its smooth surface: the shadow terminator), the shading frame decides, and occlusion
// does the rest: rays leave from the point lifted onto the smooth surface (rayOrigin, Hanika 2021),
// so that the flat faces do not shadow themselves, while light from behind a surface must still
// cross it. Photons are the exception: a photon map counts a photon only on the side of the
// geometry it landed on (PhotonMap::reflected). Light carried with importance (photons) is
// corrected for the non-symmetry shading normals introduce (Veach 1997, eq. 5.20).
#pragma once

#include "geometry/hit.h"
#include "materials/material.h"

namespace caustic {

class SurfaceBsdf {
public:
    SurfaceBsdf(const Material& m, const SurfaceInteraction& si)
        : m_(m), n_(si.n), ns_(si.ns), smooth_(si.ns != si.n) {}

    const Material& material() const { return m_; }
    const Vec3& shadingNormal() const { return ns_; }
    bool isSpecular() const { return m_.isSpecular(); }

    Color f(const Vec3& wo, const Vec3& wi) const { return m_.f(wo, wi, ns_); }
    float pdf(const Vec3& wo, const Vec3& wi) const { return m_.pdf(wo, wi, ns_); }
    /// |cos| of wi with the shading normal: the projected-area factor of the rendering equation.
    float absCos(const Vec3& wi) const { return std::abs(glm::dot(wi, ns_)); }

    std::optional<BsdfSample> sample(const Vec3& wo, float uc, Vec2 u, TransportMode mode) const {
        std::optional<BsdfSample> s = m_.sample(wo, ns_, uc, u, mode);
        if (s && smooth_ && mode == TransportMode::Importance)
            s->weight *= importanceCorrection(wo, s->wi);
        return s;
    }
    int specularLobes(const Vec3& wo, TransportMode mode, SpecularLobe out[2]) const {
        return m_.specularLobes(wo, ns_, mode, out);
    }

    /// Whether the geometric normal agrees with the shading normal that wo and wi are a reflection
    /// (same side) or a transmission (opposite sides); always, without a shading normal.
    bool agreesWithGeometry(const Vec3& wo, const Vec3& wi) const {
        if (!smooth_) return true;
        const bool reflectGeometric = glm::dot(wo, n_) * glm::dot(wi, n_) > 0.0f;
        const bool reflectShading = glm::dot(wo, ns_) * glm::dot(wi, ns_) > 0.0f;
        return reflectGeometric == reflectShading;
    }

private:
    /// |wo.ns| |wi.n| / (|wo.n| |wi.ns|): the adjoint BSDF with shading normals (Veach 1997,
    /// eq. 5.20; pbrt-v3 16.1.3), wo the direction the photon came from.
    float importanceCorrection(const Vec3& wo, const Vec3& wi) const {
        const float denominator = std::abs(glm::dot(wo, n_)) * std::abs(glm::dot(wi, ns_));
        if (!(denominator > 0.0f)) return 0.0f;
        return std::abs(glm::dot(wo, ns_)) * std::abs(glm::dot(wi, n_)) / denominator;
    }

    const Material& m_;
    Vec3 n_, ns_;
    bool smooth_;
};

}  // namespace caustic
