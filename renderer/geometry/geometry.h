// Every primitive of a scene in flat arrays, addressed by one primitive index. Accelerators see
// only this interface: bounds, intersection and the finishing of a hit.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/bounds.h"
#include "geometry/hit.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace caustic {

enum class PrimKind : uint8_t { Sphere, Quad, Triangle };

/// A planar parallelogram with corners v[0], v[0]+u, v[0]+u+v, v[0]+v, stored counter-clockwise so
/// that its front faces normalize(cross(u, v)). Intersected as two watertight triangles, as Embree
/// does, so that quads sharing an edge leave no crack.
struct Quad {
    Vec3 v[4];
    Vec3 n;      ///< Unit front-side normal, computed once (every hit and light sample needs it).
    float area;  ///< |cross(u, v)|.
};

/// A primitive's hit before it is finished into a Hit: distance and surface parameters.
struct PrimHit {
    float t;
    Vec2 uv;
};

/// Texture coordinates at a surface point and the point's derivatives along them: what a texture
/// lookup needs to filter by the pixel's footprint, and a normal map to orient its tangent frame
/// (pbrt-v4 6.2.2 and 6.5.4). t runs down the image, as in glTF and OpenImageIO.
struct TextureFrame {
    Vec2 st{0.0f};
    Vec3 dpds{0.0f}, dpdt{0.0f};
    /// A mesh's interpolated MikkTSpace tangent (unnormalized, as MikkTSpace's per-pixel
    /// reconstruction wants) and its bitangent sign; zero without one (dpds serves instead).
    Vec3 tangent{0.0f};
    float bitangentSign = 1.0f;
};

/// The scene's primitives. Built once by the scene loader, then read-only and thread-safe.
class Geometry {
public:
    uint32_t addSphere(const Sphere& s, uint32_t material);
    uint32_t addQuad(const Vec3& origin, const Vec3& u, const Vec3& v, uint32_t material);
    /// Adds a triangle mesh: vertex positions and counter-clockwise index triples, and optionally
    /// per-vertex normals (unit, any side), texture coordinates and tangents (xyz and the
    /// bitangent's sign in w), each empty or one per position. Returns the primitive index of its
    /// first triangle; the others follow in order. Each attribute's array exists only once a mesh
    /// brings it.
    uint32_t addTriangles(const std::vector<Vec3>& positions,
                          const std::vector<glm::uvec3>& triangles, uint32_t material,
                          const std::vector<Vec3>& normals = {},
                          const std::vector<Vec2>& texcoords = {},
                          const std::vector<glm::vec4>& tangents = {});

    /// Frees the arrays' spare capacity (growth leaves up to half of each unused): called once
    /// every primitive is in, so that memoryBytes() is what the counts say.
    void shrinkToFit();

    /// What every query reads of a primitive first, in one 8-byte record (one cache line fetch
    /// where three arrays cost three): its kind in the top 2 bits of `kindAndLocal`, its index
    /// within its kind's array below them, and its material.
    struct PrimRecord {
        static constexpr int kLocalBits = 30;
        uint32_t kindAndLocal;
        uint32_t material;

        PrimKind kind() const { return static_cast<PrimKind>(kindAndLocal >> kLocalBits); }
        uint32_t local() const { return kindAndLocal & ((1u << kLocalBits) - 1u); }
    };

    uint32_t size() const { return static_cast<uint32_t>(prims_.size()); }
    PrimKind kind(uint32_t prim) const { return prims_[prim].kind(); }
    uint32_t material(uint32_t prim) const { return prims_[prim].material; }
    bool hasTriangles() const { return !triangles_.empty(); }
    bool hasVertexNormals() const { return !normals_.empty(); }
    bool hasTexcoords() const { return !texcoords_.empty(); }
    bool hasTangents() const { return !tangents_.empty(); }
    Bounds3 bounds(uint32_t prim) const;
    Bounds3 bounds() const;

    /// Nearest hit of primitive `prim` in (0, tMax), without the normal. Thread-safe.
    std::optional<PrimHit> intersect(uint32_t prim, const WatertightRay& ray, float tMax) const;
    std::optional<PrimHit> intersect(uint32_t prim, const Ray& ray, float tMax) const {
        return intersect(prim, WatertightRay(ray), tMax);
    }
    /// intersect()'s triangle case on given vertices, for accelerators that keep their own copy
    /// of them (the kd-tree): the same vertices give the same bits.
    static std::optional<PrimHit> intersectVertices(const WatertightRay& ray, float tMax,
                                                    const Vec3& p0, const Vec3& p1,
                                                    const Vec3& p2) {
        if (auto h = caustic::intersectTriangle(ray, tMax, p0, p1, p2))
            return PrimHit{h->t, Vec2(h->b1, h->b2)};
        return std::nullopt;
    }
    /// The vertices of the mesh triangle of local index `local` (localIndex of a Triangle).
    void triangleVertices(uint32_t local, Vec3& p0, Vec3& p1, Vec3& p2) const {
        const glm::uvec3& t = triangles_[local];
        p0 = positions_[t.x];
        p1 = positions_[t.y];
        p2 = positions_[t.z];
    }
    /// Completes a primitive hit with the primitive index and the front-side unit normal, into
    /// `hit`: an accelerator passes the optional<Hit> it returns, so that the Hit is written in
    /// place. Returned by value and then copied, it would be written field by field and read back
    /// in 16-byte loads, which wait for the stores (failed store-to-load forwards, perf annotate).
    void finish(uint32_t prim, const Ray& ray, const PrimHit& h, Hit& hit) const;
    /// The same Hit, returned: for tests and callers off the hot path.
    Hit finish(uint32_t prim, const Ray& ray, const PrimHit& h) const {
        Hit hit;
        finish(prim, ray, h, hit);
        return hit;
    }
    /// The surface at a hit: point from the surface parameters, its error bound, normal, material.
    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const;
    /// Texture coordinates and their frame at si, computed only for a material that reads them: a
    /// mesh's own coordinates (else (0,0), (1,0), (1,1) at its corners, as pbrt-v4), a quad's
    /// (s, 1 - t) over its edges u and v (its image upright when u points right and v up), a
    /// sphere's (phi / 2pi, theta / pi).
    TextureFrame textureFrame(const SurfaceInteraction& si) const;

    /// Surface area of a primitive, and a uniform point on it (density 1 / area).
    float area(uint32_t prim) const;
    SurfaceSample sample(uint32_t prim, Vec2 u) const;

    /// The raw arrays, for accelerators that take geometry natively (Embree).
    const std::vector<Sphere>& spheres() const { return spheres_; }
    const std::vector<Quad>& quads() const { return quads_; }
    const std::vector<Vec3>& positions() const { return positions_; }
    const std::vector<glm::uvec3>& triangles() const { return triangles_; }
    /// Index of a primitive within the array of its kind.
    uint32_t localIndex(uint32_t prim) const { return prims_[prim].local(); }

    /// Bytes held by the primitive arrays, and by the triangle arrays alone (zero for a scene
    /// without meshes or triangles).
    size_t memoryBytes() const;
    size_t meshBytes() const {
        return positions_.capacity() * sizeof(Vec3) + triangles_.capacity() * sizeof(glm::uvec3) +
               normals_.capacity() * sizeof(Vec3) + texcoords_.capacity() * sizeof(Vec2) +
               tangents_.capacity() * sizeof(glm::vec4);
    }

private:
    uint32_t push(PrimKind kind, uint32_t local, uint32_t material);
    /// Completes si for a mesh triangle with vertex normals.
    void smoothTriangle(const glm::uvec3& t, const TriangleHit& b, const Vec3 p[3],
                        SurfaceInteraction& si) const;

    std::vector<PrimRecord> prims_;
    std::vector<Sphere> spheres_;
    std::vector<Quad> quads_;
    std::vector<Vec3> positions_;
    std::vector<glm::uvec3> triangles_;
    // Per position, once a mesh has them; zero for a mesh without.
    std::vector<Vec3> normals_;
    std::vector<Vec2> texcoords_;
    std::vector<glm::vec4> tangents_;
};

}  // namespace caustic
