// Geometry::textureFrame: texture coordinates and dp/ds, dp/dt at a surface point.
#include <cmath>

#include "geometry/geometry.h"

namespace caustic {

namespace {

// dp/ds and dp/dt of a triangle from its corners' positions and texture coordinates, by solving
// the 2x2 system of two edges (pbrt-v4 6.5.4); a frame around the normal where the coordinates
// are degenerate (a mesh without them, or a corner repeated).
void triangleDerivatives(const Vec3 p[3], const Vec2 st[3], const Vec3& n, Vec3& dpds, Vec3& dpdt) {
    const Vec2 d02 = st[0] - st[2], d12 = st[1] - st[2];
    const Vec3 dp02 = p[0] - p[2], dp12 = p[1] - p[2];
    const float determinant = differenceOfProducts(d02.x, d12.y, d02.y, d12.x);
    const bool degenerate = std::abs(determinant) < 1e-9f;
    if (!degenerate) {
        const float inv = 1.0f / determinant;
        dpds = (d12.y * dp02 - d02.y * dp12) * inv;
        dpdt = (d02.x * dp12 - d12.x * dp02) * inv;
    }
    if (degenerate || !isFinite(dpds) || !isFinite(dpdt) ||
        glm::dot(glm::cross(dpds, dpdt), glm::cross(dpds, dpdt)) == 0.0f)
        coordinateSystem(n, dpds, dpdt);
}

}  // namespace

TextureFrame Geometry::textureFrame(const SurfaceInteraction& si) const {
    TextureFrame f;
    const PrimRecord r = prims_[si.prim];
    const uint32_t i = r.local();
    switch (r.kind()) {
        case PrimKind::Sphere: {
            // p = c + r (sin theta cos phi, sin theta sin phi, cos theta), phi = 2 pi s,
            // theta = pi t.
            const Sphere& sphere = spheres_[i];
            f.st = sphere.uv(si.p);
            const float phi = 2.0f * kPi * f.st.x, theta = kPi * f.st.y;
            const float sinTheta = std::sin(theta), cosTheta = std::cos(theta);
            const float radius = sphere.radius;
            f.dpds = 2.0f * kPi * radius * sinTheta * Vec3(-std::sin(phi), std::cos(phi), 0.0f);
            f.dpdt =
                kPi * radius * Vec3(cosTheta * std::cos(phi), cosTheta * std::sin(phi), -sinTheta);
            // At the poles dp/ds vanishes: any tangent will do.
            if (!(glm::dot(f.dpds, f.dpds) > 0.0f)) coordinateSystem(si.n, f.dpds, f.dpdt);
            break;
        }
        case PrimKind::Quad: {
            const Quad& q = quads_[i];
            f.st = Vec2(si.uv.x, 1.0f - si.uv.y);
            f.dpds = q.v[1] - q.v[0];
            f.dpdt = q.v[0] - q.v[3];
            break;
        }
        case PrimKind::Triangle: {
            const glm::uvec3& t = triangles_[i];
            const Vec3 p[3] = {positions_[t.x], positions_[t.y], positions_[t.z]};
            const float b[3] = {1.0f - si.uv.x - si.uv.y, si.uv.x, si.uv.y};
            Vec2 st[3] = {Vec2(0.0f, 0.0f), Vec2(1.0f, 0.0f), Vec2(1.0f, 1.0f)};
            if (!texcoords_.empty()) {
                st[0] = texcoords_[t.x], st[1] = texcoords_[t.y], st[2] = texcoords_[t.z];
                f.st = b[0] * st[0] + b[1] * st[1] + b[2] * st[2];
            } else {
                f.st = Vec2(b[1] + b[2], b[2]);
            }
            triangleDerivatives(p, st, si.n, f.dpds, f.dpdt);
            if (!tangents_.empty()) {
                const glm::vec4 tangent =
                    b[0] * tangents_[t.x] + b[1] * tangents_[t.y] + b[2] * tangents_[t.z];
                f.tangent = Vec3(tangent);
                f.bitangentSign = tangents_[t.x].w < 0.0f ? -1.0f : 1.0f;
            }
            break;
        }
    }
    return f;
}

}  // namespace caustic
