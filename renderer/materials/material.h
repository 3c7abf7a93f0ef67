// Materials: a BSDF for scattering plus optional emission. All are two-sided for scattering;
// emission leaves the front side (the geometric normal's side) only. Directions point away from the
// surface; n is the unit geometric normal on the front side.
#pragma once

#include <optional>

#include "core/math.h"

namespace caustic {

struct MaterialScratch;
struct TexturePoint;

/// Which quantity a path carries: radiance from the camera, or importance from lights (photons).
/// Refraction scales radiance by 1/eta^2 but not photon power (Veach 1997, section 5.2).
enum class TransportMode { Radiance, Importance };

/// A sampled scattering direction.
struct BsdfSample {
    Vec3 wi;
    Color f;           ///< BSDF value; for a specular lobe, its weight * pdf / |cos theta_i|.
    float pdf = 0.0f;  ///< Solid-angle density; for a specular lobe, its selection probability.
    Color weight;      ///< f |cos theta_i| / pdf: the factor the path throughput is multiplied by.
    bool specular = false;
    /// For a transmitted sample, the ratio of the indices of refraction, far side over near side
    /// (pbrt-v4 BSDFSample::eta); 1 otherwise. In Radiance mode `weight` holds 1 / eta^2.
    float eta = 1.0f;
};

/// A BSDF's value for a pair of directions and the density with which its sampling returns the
/// second, computed together where they share work (a half vector, a Fresnel term).
struct BsdfEval {
    Color f{0.0f};
    float pdf = 0.0f;
};

/// One deterministic specular branch (for Whitted tracing): direction and its full weight.
struct SpecularLobe {
    Vec3 wi;
    Color weight;
};

/// The sample of a specular lobe chosen with probability `pdf` (1 for the only lobe): its weight
/// over pdf, and f = the lobe's weight / |cos theta_i| (BsdfSample's convention); nullopt at
/// grazing incidence, where that is undefined. n: the unit normal.
inline std::optional<BsdfSample> specularSample(const SpecularLobe& lobe, const Vec3& n,
                                                float pdf = 1.0f) {
    const float cosI = std::abs(glm::dot(lobe.wi, n));
    if (cosI == 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = lobe.wi;
    s.f = lobe.weight / cosI;
    s.pdf = pdf;
    s.weight = lobe.weight / pdf;
    s.specular = true;
    return s;
}

class Material {
public:
    explicit Material(const Color& emission, bool specular)
        : emission_(emission), specular_(specular), lobeRoughness_(specular ? 0.0f : 1.0f) {}
    virtual ~Material() = default;

    /// BSDF value f(wo, wi) for the non-specular part; zero for specular materials. Thread-safe.
    virtual Color f(const Vec3& wo, const Vec3& wi, const Vec3& n) const = 0;
    /// Solid-angle density with which `sample` returns wi given wo; zero for specular materials.
    virtual float pdf(const Vec3& wo, const Vec3& wi, const Vec3& n) const = 0;
    /// Samples wi given wo, from a lobe choice uc in [0,1) and a 2D sample u in [0,1)^2. nullopt
    /// when no direction scatters (the path ends). Thread-safe.
    virtual std::optional<BsdfSample> sample(const Vec3& wo, const Vec3& n, float uc, Vec2 u,
                                             TransportMode mode) const = 0;
    /// Every specular branch at once, for deterministic tracing: writes up to two lobes into `out`
    /// and returns their count; zero for non-specular materials.
    virtual int specularLobes(const Vec3& wo, const Vec3& n, TransportMode mode,
                              SpecularLobe out[2]) const = 0;

    /// For a Lambertian BSDF, its constant value: f(wo, wi) is that when wi is on wo's side of
    /// the surface and zero otherwise. A photon map's density estimate then evaluates f once, not
    /// once a photon. nullopt for any other BSDF.
    virtual std::optional<Color> lambertian() const { return std::nullopt; }

    /// An upper bound on every channel of the weight `sample` returns (f |cos theta_i| / pdf): the
    /// most of a path's throughput one scattering keeps. 1 unless a material knows better.
    virtual float maxScatterWeight() const { return 1.0f; }

    /// True for a material with inputs read from images: atPoint gives the material a point sees.
    bool isTextured() const { return textured_; }
    /// The material at one surface point: its textured inputs looked up there, into `scratch`
    /// (which the result may live in, until the next call with it); a normal map turns the
    /// shading normal ns. *this for a material without textures. The result is specular exactly
    /// when this material is.
    virtual const Material& atPoint(const TexturePoint& /*point*/, Vec3& /*ns*/,
                                    MaterialScratch& /*scratch*/) const {
        return *this;
    }
    /// Whether atPoint reads a tangent frame (a normal map): meshes then get MikkTSpace tangents.
    virtual bool needsTangents() const { return false; }

    /// Emitted radiance (front side) at a point the scene does not shade, such as a light sample:
    /// for an emissive texture, its value there at the finest level; emission() otherwise.
    virtual Color emissionAt(const TexturePoint& /*point*/) const { return emission_; }
    /// The emission averaged over the surface's texture (for choosing lights by power).
    virtual Color averageEmission() const { return emission_; }

    /// Whether parts of the surface may be cut out (glTF's alpha modes mask and blend): rays pass
    /// through those as if nothing were there (scene/visibility.h).
    bool hasAlpha() const { return alpha_; }
    /// Whether a ray passes through the surface at the point: below the cutoff (mask), or with
    /// probability 1 - alpha from the ray's own uniform number u (blend: stochastic transparency).
    virtual bool cutOut(const TexturePoint& /*point*/, float /*u*/) const { return false; }

    /// True when every lobe is a Dirac delta (mirror, dielectric): no light sampling is possible.
    bool isSpecular() const { return specular_; }
    /// The perceptual roughness of a surface all of whose lobes are microfacet reflection or
    /// refraction (the widest of them); 0 for a specular surface, 1 for one with a diffuse lobe.
    /// The photon mappers follow a surface below their threshold as they do a mirror
    /// (integrators/photon.h).
    float lobeRoughness() const { return lobeRoughness_; }
    bool isEmissive() const { return !isBlack(emission_); }
    const Color& emission() const { return emission_; }
    /// Emitted radiance towards w (front side only).
    Color Le(const Vec3& w, const Vec3& n) const {
        return glm::dot(w, n) > 0.0f ? emission_ : Color(0.0f);
    }

protected:
    void setTextured() { textured_ = true; }
    void setLobeRoughness(float roughness) { lobeRoughness_ = roughness; }
    void setAlpha() { alpha_ = true; }

private:
    Color emission_;
    bool specular_;
    float lobeRoughness_;
    bool textured_ = false;
    bool alpha_ = false;
};

}  // namespace caustic
