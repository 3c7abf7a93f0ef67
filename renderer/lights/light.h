// Light sources: point lights, and area lights made from emissive primitives.
#pragma once

#include <algorithm>
#include <optional>

#include "core/math.h"
#include "core/ray.h"
#include "geometry/hit.h"

namespace caustic {

/// The point light arrives at: a surface point with its rounding-error bound and normal (both zero
/// for a point in space). Lights that choose a sampling strategy by where the point lies (inside
/// or outside a sphere) decide with the error bound, so that a point on the surface is never taken
/// for one off it.
struct LightSampleContext {
    Vec3 p;
    Vec3 pError{0.0f};
    Vec3 n{0.0f};

    LightSampleContext(const Vec3& point) : p(point) {}  // NOLINT: a point in space converts
    LightSampleContext(const SurfaceInteraction& si)
        : p(si.p), pError(si.pError), n(si.n) {}  // NOLINT
};

/// Incident light at a reference point from a sampled point on a light.
struct LightSample {
    Color Li;          ///< Radiance (area) or intensity / distance^2 (point) arriving at the point.
    Vec3 wi;           ///< Unit direction from the reference point towards the light.
    float pdf = 0.0f;  ///< Solid-angle density of wi; 1 for a point light.
    SurfaceSample at;  ///< The point on the light (normal zero for a point light).
};

/// A ray leaving a light, for photon tracing: its origin (offset off the emitter's surface) and
/// direction, and the flux it carries, Le |cos| / (p(position) p(direction)) (pbrt-v4 12.1).
struct LightLeSample {
    Ray ray;
    Color power;
};

/// The cosine a light's importance at ref weighs unit direction w by: |cos| to the geometric
/// normal, but never below kMinImportanceCosine (1 for a point in space). A shading normal (smooth
/// or normal-mapped surfaces) or a glossy lobe may take light that grazes the geometric surface:
/// a light chosen with a probability near zero there would return a sample of near-infinite
/// weight, so the floor bounds that weight at 1 / kMinImportanceCosine of its fair share.
inline constexpr float kMinImportanceCosine = 0.1f;
inline float importanceCosine(const Vec3& w, const LightSampleContext& ref) {
    if (!(glm::dot(ref.n, ref.n) > 0.0f)) return 1.0f;
    return std::max(std::abs(glm::dot(w, ref.n)), kMinImportanceCosine);
}

/// importanceCosine / d^2 of a light at `position` seen from ref: how a point light's irradiance
/// at ref scales, for choosing among lights.
inline float pointLightFactor(const Vec3& position, const LightSampleContext& ref) {
    const Vec3 d = position - ref.p;
    const float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return 0.0f;
    return importanceCosine(d / std::sqrt(dist2), ref) / dist2;
}

class Light {
public:
    virtual ~Light() = default;
    /// Samples incident light at world point `ref` from a 2D sample u in [0,1)^2; nullopt when no
    /// light can arrive (the back of an emitter, a zero density). Ignores occlusion. Thread-safe.
    virtual std::optional<LightSample> sampleLi(const LightSampleContext& ref, Vec2 u) const = 0;
    /// The solid-angle density with which sampleLi(ref, .) returns the direction towards `at`, a
    /// point on this light that a ray from ref reached (for multiple importance sampling). Zero
    /// for delta lights.
    virtual float pdfLi(const LightSampleContext& ref, const SurfaceInteraction& at) const = 0;
    /// Samples a ray of emitted light from two 2D samples in [0,1)^2 (position, direction);
    /// nullopt when none can leave. Thread-safe.
    virtual std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const = 0;
    /// Total emitted power in watts per channel, for choosing lights in proportion to power.
    virtual Color power() const = 0;
    /// True for lights that cannot be hit by a ray (point lights).
    virtual bool isDelta() const = 0;
    /// An estimate of the light's contribution at ref, for choosing among lights there
    /// (LocalLightSampler): positive wherever the light can contribute, zero only where it cannot.
    /// By default its power's luminance, the same everywhere.
    virtual float importance(const LightSampleContext&) const { return luminance(power()); }
};

}  // namespace caustic
