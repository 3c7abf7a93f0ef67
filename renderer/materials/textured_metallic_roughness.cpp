#include "materials/textured_metallic_roughness.h"

#include <algorithm>

namespace caustic {

TexturedMetallicRoughness::TexturedMetallicRoughness(const Inputs& inputs,
                                                     std::shared_ptr<const TextureStore> store)
    : Material(inputs.emission, false),
      in_(inputs),
      store_(std::move(store)),
      factors_(inputs.baseColor, inputs.metallic, inputs.roughness, inputs.multipleScattering,
               inputs.emission, inputs.ior) {
    setTextured();
    if (in_.alphaMode != AlphaMode::Opaque) setAlpha();
}

Color TexturedMetallicRoughness::emitted(const TextureQuery& q) const {
    if (!in_.emissiveTexture || isBlack(emission())) return emission();
    float rgb[3];
    in_.emissiveTexture.lookup(*store_, q, 0, 3, rgb);
    return emission() * Color(rgb[0], rgb[1], rgb[2]);
}

Color TexturedMetallicRoughness::emissionAt(const TexturePoint& point) const {
    TextureQuery finest;
    finest.st = point.query.st;
    return emitted(finest);
}

Color TexturedMetallicRoughness::averageEmission() const {
    // A footprint as large as the image: the coarsest MIP level, the image's mean.
    TextureQuery whole;
    whole.dstdx = Vec2(1.0f, 0.0f);
    whole.dstdy = Vec2(0.0f, 1.0f);
    return emitted(whole);
}

bool TexturedMetallicRoughness::cutOut(const TexturePoint& point, float u) const {
    float alpha = in_.alpha;
    if (in_.baseColorTexture) {
        float a;
        in_.baseColorTexture.lookup(*store_, point.query, 3, 1, &a);
        alpha *= a;
    }
    switch (in_.alphaMode) {
        case AlphaMode::Opaque:
            return false;
        case AlphaMode::Mask:
            return alpha < in_.alphaCutoff;
        case AlphaMode::Blend:
            return u >= alpha;
    }
    return false;
}

const Material& TexturedMetallicRoughness::atPoint(const TexturePoint& point, Vec3& ns,
                                                   MaterialScratch& scratch) const {
    Color base = in_.baseColor;
    float metallic = in_.metallic, roughness = in_.roughness;
    if (in_.baseColorTexture) {
        float rgb[3];
        in_.baseColorTexture.lookup(*store_, point.query, 0, 3, rgb);
        base *= glm::clamp(Color(rgb[0], rgb[1], rgb[2]), Color(0.0f), Color(1.0f));
    }
    if (in_.metallicRoughnessTexture) {
        float gb[2];  // glTF: roughness in G, metalness in B
        in_.metallicRoughnessTexture.lookup(*store_, point.query, 1, 2, gb);
        roughness *= std::clamp(gb[0], 0.0f, 1.0f);
        metallic *= std::clamp(gb[1], 0.0f, 1.0f);
    }
    if (in_.normalTexture) ns = mappedNormal(point, ns);
    scratch.metallicRoughness.emplace(base, metallic, roughness, in_.multipleScattering,
                                      emitted(point.query), in_.ior);
    return *scratch.metallicRoughness;
}

Vec3 TexturedMetallicRoughness::mappedNormal(const TexturePoint& point, const Vec3& ns) const {
    float v[3];
    in_.normalTexture.lookup(*store_, point.query, 0, 3, v);
    const Vec3 local((2.0f * v[0] - 1.0f) * in_.normalScale, (2.0f * v[1] - 1.0f) * in_.normalScale,
                     2.0f * v[2] - 1.0f);
    // The tangent frame: a mesh's MikkTSpace tangent, reconstructed per point as MikkTSpace
    // defines (bitangent = sign (n x t), neither normalized nor orthogonalized), else dp/ds
    // with the bitangent towards the image's top (-dp/dt, since t runs down the image: glTF's
    // +y up).
    Vec3 tangent = point.frame.tangent;
    float sign = point.frame.bitangentSign;
    if (!(glm::dot(tangent, tangent) > 0.0f)) {
        tangent = point.frame.dpds - ns * glm::dot(ns, point.frame.dpds);
        const float length = glm::length(tangent);
        if (length > 0.0f && std::isfinite(length)) {
            tangent /= length;
        } else {
            Vec3 other;
            coordinateSystem(ns, tangent, other);
        }
        sign = glm::dot(glm::cross(ns, tangent), -point.frame.dpdt) < 0.0f ? -1.0f : 1.0f;
    }
    const Vec3 bitangent = sign * glm::cross(ns, tangent);
    Vec3 mapped = local.x * tangent + local.y * bitangent + local.z * ns;
    const float length = glm::length(mapped);
    if (!(length > 0.0f) || !std::isfinite(length)) return ns;
    mapped /= length;
    // A normal the map tilts past the surface's plane is brought back just in front of it: the
    // shading normal stays on the geometric normal's side (SurfaceInteraction::ns).
    constexpr float kMinCosine = 0.01f;
    const float cosine = glm::dot(mapped, point.n);
    if (cosine < kMinCosine) mapped = glm::normalize(mapped + (kMinCosine - cosine) * point.n);
    return mapped;
}

}  // namespace caustic
