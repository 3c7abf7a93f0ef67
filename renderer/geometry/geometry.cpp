#include "geometry/geometry.h"

#include "core/check.h"
#include "core/sampling.h"

namespace caustic {
namespace {

// A quad is split as Embree splits it: triangles (v0, v1, v3) and (v2, v3, v1). Their barycentrics
// map to the quad's (s, t), where p = v0 + s (v1 - v0) + t (v3 - v0).
Vec2 quadUv(bool second, const TriangleHit& h) {
    return second ? Vec2(1.0f - h.b1, 1.0f - h.b2) : Vec2(h.b1, h.b2);
}

// Barycentrics of a quad's (s, t) within the triangle that holds it (the second when s + t > 1).
TriangleHit quadBarycentrics(Vec2 uv, bool& second) {
    second = uv.x + uv.y > 1.0f;
    if (second) return TriangleHit{uv.x + uv.y - 1.0f, 1.0f - uv.x, 1.0f - uv.y, 0.0f};
    return TriangleHit{1.0f - uv.x - uv.y, uv.x, uv.y, 0.0f};
}

// The three corners of one of a quad's triangles.
void quadTriangle(const Quad& q, bool second, Vec3& p0, Vec3& p1, Vec3& p2) {
    if (second) {
        p0 = q.v[2], p1 = q.v[3], p2 = q.v[1];
    } else {
        p0 = q.v[0], p1 = q.v[1], p2 = q.v[3];
    }
}

}  // namespace

uint32_t Geometry::push(PrimKind kind, uint32_t local, uint32_t material) {
    CAUSTIC_CHECK_LT(local, 1u << PrimRecord::kLocalBits);
    prims_.push_back(
        PrimRecord{(static_cast<uint32_t>(kind) << PrimRecord::kLocalBits) | local, material});
    return size() - 1;
}

uint32_t Geometry::addSphere(const Sphere& s, uint32_t material) {
    spheres_.push_back(s);
    return push(PrimKind::Sphere, static_cast<uint32_t>(spheres_.size() - 1), material);
}

uint32_t Geometry::addQuad(const Vec3& origin, const Vec3& u, const Vec3& v, uint32_t material) {
    Quad q{{origin, origin + u, origin + u + v, origin + v}, Vec3(0.0f), 0.0f};
    // The normal of the triangle (v0, v1, v3) that intersection reports, and the exact area.
    q.n = triangleNormal(q.v[0], q.v[1], q.v[3]);
    q.area = glm::length(glm::cross(q.v[1] - q.v[0], q.v[3] - q.v[0]));
    quads_.push_back(q);
    return push(PrimKind::Quad, static_cast<uint32_t>(quads_.size() - 1), material);
}

namespace {

// Appends a mesh's per-vertex attribute, or zeros for a mesh without it once any mesh has it.
template <typename T>
void appendAttribute(std::vector<T>& all, const std::vector<T>& mesh, size_t base, size_t count) {
    CAUSTIC_CHECK(mesh.empty() || mesh.size() == count);
    if (mesh.empty() && all.empty()) return;
    all.resize(base, T(0.0f));
    if (mesh.empty())
        all.resize(base + count, T(0.0f));
    else
        all.insert(all.end(), mesh.begin(), mesh.end());
}

}  // namespace

uint32_t Geometry::addTriangles(const std::vector<Vec3>& positions,
                                const std::vector<glm::uvec3>& triangles, uint32_t material,
                                const std::vector<Vec3>& normals,
                                const std::vector<Vec2>& texcoords,
                                const std::vector<glm::vec4>& tangents) {
    auto base = static_cast<uint32_t>(positions_.size());
    appendAttribute(normals_, normals, base, positions.size());
    appendAttribute(texcoords_, texcoords, base, positions.size());
    appendAttribute(tangents_, tangents, base, positions.size());
    positions_.insert(positions_.end(), positions.begin(), positions.end());
    uint32_t first = size();
    for (const glm::uvec3& t : triangles) {
        CAUSTIC_CHECK(t.x < positions.size() && t.y < positions.size() && t.z < positions.size());
        triangles_.push_back(t + glm::uvec3(base));
        push(PrimKind::Triangle, static_cast<uint32_t>(triangles_.size() - 1), material);
    }
    return first;
}

Bounds3 Geometry::bounds(uint32_t prim) const {
    const PrimRecord r = prims_[prim];
    const uint32_t i = r.local();
    Bounds3 b;
    switch (r.kind()) {
        case PrimKind::Sphere:
            return spheres_[i].bounds();
        case PrimKind::Quad:
            for (const Vec3& v : quads_[i].v) b.extend(v);
            return b;
        case PrimKind::Triangle: {
            Vec3 p0, p1, p2;
            triangleVertices(i, p0, p1, p2);
            b.extend(p0);
            b.extend(p1);
            b.extend(p2);
            return b;
        }
    }
    return b;
}

Bounds3 Geometry::bounds() const {
    Bounds3 b;
    for (uint32_t prim = 0; prim < size(); ++prim) b.extend(bounds(prim));
    return b;
}

std::optional<PrimHit> Geometry::intersect(uint32_t prim, const WatertightRay& wr,
                                           float tMax) const {
    const Ray& ray = wr.ray;
    const PrimRecord r = prims_[prim];
    const uint32_t i = r.local();
    switch (r.kind()) {
        case PrimKind::Sphere:
            if (auto t = spheres_[i].intersect(ray, tMax)) return PrimHit{*t, Vec2(0.0f)};
            return std::nullopt;
        case PrimKind::Quad: {
            const Quad& q = quads_[i];
            if (auto h = intersectTriangle(wr, tMax, q.v[0], q.v[1], q.v[3]))
                return PrimHit{h->t, quadUv(false, *h)};
            if (auto h = intersectTriangle(wr, tMax, q.v[2], q.v[3], q.v[1]))
                return PrimHit{h->t, quadUv(true, *h)};
            return std::nullopt;
        }
        case PrimKind::Triangle: {
            Vec3 p0, p1, p2;
            triangleVertices(i, p0, p1, p2);
            return intersectVertices(wr, tMax, p0, p1, p2);
        }
    }
    return std::nullopt;
}

void Geometry::finish(uint32_t prim, const Ray& ray, const PrimHit& h, Hit& hit) const {
    hit.t = h.t;
    hit.prim = prim;
    hit.uv = h.uv;
    const PrimRecord r = prims_[prim];
    const uint32_t i = r.local();
    switch (r.kind()) {
        case PrimKind::Sphere: {
            // No uv: nothing shades by it yet, and its atan2 and acos cost ~2% of a path
            // tracer's time (Sphere::uv computes it when needed).
            hit.n = spheres_[i].normal(ray.o + h.t * ray.d);
            break;
        }
        case PrimKind::Quad:
            hit.n = quads_[i].n;
            break;
        case PrimKind::Triangle: {
            Vec3 p0, p1, p2;
            triangleVertices(i, p0, p1, p2);
            hit.n = triangleNormal(p0, p1, p2);
            break;
        }
    }
}

SurfaceInteraction Geometry::interaction(const Ray& ray, const Hit& hit) const {
    SurfaceInteraction si;
    si.n = hit.n;
    si.ns = hit.n;
    si.uv = hit.uv;
    si.prim = hit.prim;
    const PrimRecord r = prims_[hit.prim];
    si.material = r.material;
    const uint32_t i = r.local();
    switch (r.kind()) {
        case PrimKind::Sphere:
            spheres_[i].hitPoint(ray, hit.t, si.p, si.pError);
            break;
        case PrimKind::Quad: {
            bool second = false;
            TriangleHit b = quadBarycentrics(hit.uv, second);
            Vec3 p0, p1, p2;
            quadTriangle(quads_[i], second, p0, p1, p2);
            triangleHitPoint(b, p0, p1, p2, si.p, si.pError);
            break;
        }
        case PrimKind::Triangle: {
            const glm::uvec3& t = triangles_[i];
            const Vec3 p[3] = {positions_[t.x], positions_[t.y], positions_[t.z]};
            TriangleHit b{1.0f - hit.uv.x - hit.uv.y, hit.uv.x, hit.uv.y, hit.t};
            triangleHitPoint(b, p[0], p[1], p[2], si.p, si.pError);
            if (!normals_.empty()) {
                smoothTriangle(t, b, p, si);
                return si;
            }
            break;
        }
    }
    si.pShading = si.p;
    return si;
}

float Geometry::area(uint32_t prim) const {
    const PrimRecord r = prims_[prim];
    const uint32_t i = r.local();
    switch (r.kind()) {
        case PrimKind::Sphere:
            return spheres_[i].area();
        case PrimKind::Quad:
            return quads_[i].area;
        case PrimKind::Triangle: {
            Vec3 p0, p1, p2;
            triangleVertices(i, p0, p1, p2);
            return 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
        }
    }
    return 0.0f;
}

SurfaceSample Geometry::sample(uint32_t prim, Vec2 u) const {
    const PrimRecord r = prims_[prim];
    const uint32_t i = r.local();
    SurfaceSample s;
    switch (r.kind()) {
        case PrimKind::Sphere:
            return spheres_[i].sample(u);
        case PrimKind::Quad: {
            bool second = false;
            TriangleHit b = quadBarycentrics(u, second);
            Vec3 p0, p1, p2;
            quadTriangle(quads_[i], second, p0, p1, p2);
            triangleHitPoint(b, p0, p1, p2, s.p, s.pError);
            s.n = quads_[i].n;
            s.uv = u;
            s.pdfArea = 1.0f / quads_[i].area;
            break;
        }
        case PrimKind::Triangle: {
            Vec3 p0, p1, p2;
            triangleVertices(i, p0, p1, p2);
            Vec2 b = sampleUniformTriangle(u);
            triangleHitPoint(TriangleHit{b.x, b.y, 1.0f - b.x - b.y, 0.0f}, p0, p1, p2, s.p,
                             s.pError);
            s.uv = Vec2(b.y, 1.0f - b.x - b.y);
            Vec3 c = glm::cross(p1 - p0, p2 - p0);
            s.n = glm::normalize(c);  // as triangleNormal, to the bit
            s.pdfArea = 2.0f / glm::length(c);
            break;
        }
    }
    return s;
}

void Geometry::smoothTriangle(const glm::uvec3& t, const TriangleHit& b, const Vec3 p[3],
                              SurfaceInteraction& si) const {
    si.pShading = si.p;
    const Vec3 vn[3] = {normals_[t.x], normals_[t.y], normals_[t.z]};
    const Vec3 ns = b.b0 * vn[0] + b.b1 * vn[1] + b.b2 * vn[2];
    const float length = glm::length(ns);
    // A mesh without normals among meshes with them, or normals that cancel: flat.
    if (!(length > 1e-6f) || !std::isfinite(length)) return;
    // Vertex normals may face the back of the winding: the shading normal joins n's side.
    const float side = glm::dot(ns, si.n) < 0.0f ? -1.0f : 1.0f;
    si.ns = ns * (side / length);
    // Hanika 2021: the hit point moved off each vertex's tangent plane when below it, weighted by
    // the barycentrics: the point on the smooth surface the vertex normals describe.
    const float w[3] = {b.b0, b.b1, b.b2};
    Vec3 lifted(0.0f);
    for (int k = 0; k < 3; ++k) {
        const Vec3 normal = side * vn[k];
        const Vec3 d = si.p - p[k];
        lifted += w[k] * (si.p - std::min(0.0f, glm::dot(d, normal)) * normal);
    }
    if (isFinite(lifted)) si.pShading = lifted;
}

void Geometry::shrinkToFit() {
    normals_.shrink_to_fit();
    texcoords_.shrink_to_fit();
    tangents_.shrink_to_fit();
    prims_.shrink_to_fit();
    spheres_.shrink_to_fit();
    quads_.shrink_to_fit();
    positions_.shrink_to_fit();
    triangles_.shrink_to_fit();
}

size_t Geometry::memoryBytes() const {
    return prims_.capacity() * sizeof(PrimRecord) + spheres_.capacity() * sizeof(Sphere) +
           quads_.capacity() * sizeof(Quad) + meshBytes();
}

}  // namespace caustic
