#include "accel/kdtree/clip.h"

#include <utility>

namespace caustic {
namespace {

// Intersection of two boxes; empty when they do not overlap.
Bounds3 overlap(const Bounds3& a, const Bounds3& b) {
    return Bounds3{glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)};
}

// Writes to `out` the part of the convex polygon in[0, n) with sign * (p[axis] - plane) >= 0
// (Sutherland & Hodgman 1974); returns its vertex count. A triangle or quad clipped by six planes
// has at most 4 + 6 vertices. Each edge runs from the previous vertex to the current one, so the
// output is the textbook's up to a rotation: the same edges, the same interpolated points.
int clipPolygon(const Vec3* in, int n, Vec3* out, int axis, float plane, float sign) {
    int m = 0;
    Vec3 a = in[n - 1];
    float da = sign * (component(a, axis) - plane);
    for (int i = 0; i < n; ++i) {
        const Vec3 b = in[i];
        const float db = sign * (component(b, axis) - plane);
        if (da >= 0.0f) out[m++] = a;
        if ((da < 0.0f) != (db < 0.0f)) {
            Vec3 p = a + (b - a) * (da / (da - db));
            // Exactly on the plane, whatever the rounding.
            setComponent(p, axis, plane);
            out[m++] = p;
        }
        a = b;
        da = db;
    }
    return m;
}

}  // namespace

Bounds3 fuzzyBounds(const Geometry& geometry, uint32_t prim) {
    Bounds3 b = geometry.bounds(prim);
    Vec3 slack(magnitudeSlack(b));
    return Bounds3{b.lo - slack, b.hi + slack};
}

float magnitudeSlack(const Bounds3& b) {
    return 4.0f * gamma(3) * maxComponent(glm::max(glm::abs(b.lo), glm::abs(b.hi)));
}

Bounds3 clipPrimitive(const Geometry& geometry, uint32_t prim, const Bounds3& box) {
    PrimKind kind = geometry.kind(prim);
    if (kind == PrimKind::Sphere) return overlap(fuzzyBounds(geometry, prim), box);
    Vec3 buffers[2][12];
    Vec3* poly = buffers[0];
    Vec3* spare = buffers[1];
    int n = 0;
    uint32_t i = geometry.localIndex(prim);
    if (kind == PrimKind::Quad) {
        for (const Vec3& v : geometry.quads()[i].v) poly[n++] = v;
    } else {
        const glm::uvec3& t = geometry.triangles()[i];
        for (int k = 0; k < 3; ++k) poly[n++] = geometry.positions()[t[k]];
    }
    // These bounds are the primitive's own (Geometry::bounds extends them by the same vertices).
    Bounds3 own;
    for (int k = 0; k < n; ++k) own.extend(poly[k]);
    // The float intersection test sees a primitive only to a few ulps of its own coordinates: clip
    // against the box grown by that much, and grow the result by it, so that no reference is
    // dropped from a node where the test would hit it.
    const float fuzz = magnitudeSlack(own);
    const Bounds3 grown{box.lo - Vec3(fuzz), box.hi + Vec3(fuzz)};
    // Only the planes that cut the primitive's own bounds can clip it (a straddling reference
    // usually crosses one or two of the six): the others would copy the polygon unchanged. The
    // vertices that clipping interpolates stay within those bounds but for rounding, which the
    // slack below covers.
    for (int axis = 0; axis < 3 && n > 0; ++axis) {
        const float lo = component(grown.lo, axis), hi = component(grown.hi, axis);
        if (component(own.lo, axis) < lo) {
            n = clipPolygon(poly, n, spare, axis, lo, 1.0f);
            std::swap(poly, spare);
        }
        if (n > 0 && component(own.hi, axis) > hi) {
            n = clipPolygon(poly, n, spare, axis, hi, -1.0f);
            std::swap(poly, spare);
        }
    }
    Bounds3 b;
    for (int k = 0; k < n; ++k) b.extend(poly[k]);
    if (b.empty()) return b;
    // Grow by the rounding error of the interpolation (a few ulps of the coordinates), then keep
    // it inside the box.
    Vec3 slack = gamma(4) * glm::max(glm::abs(b.lo), glm::abs(b.hi)) + Vec3(fuzz);
    return overlap(Bounds3{b.lo - slack, b.hi + slack}, box);
}

}  // namespace caustic
