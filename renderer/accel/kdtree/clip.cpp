#include "accel/kdtree/clip.h"

namespace caustic {
namespace {

// Intersection of two boxes; empty when they do not overlap.
Bounds3 overlap(const Bounds3& a, const Bounds3& b) {
    return Bounds3{glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)};
}

// A convex polygon, clipped in place (Sutherland & Hodgman 1974): a triangle or quad clipped by six
// planes has at most 4 + 6 vertices.
struct Polygon {
    Vec3 v[12];
    int n = 0;

    // Keeps the part with sign * (p[axis] - plane) >= 0.
    void clip(int axis, float plane, float sign) {
        Vec3 out[12];
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const Vec3& a = v[i];
            const Vec3& b = v[(i + 1) % n];
            float da = sign * (component(a, axis) - plane),
                  db = sign * (component(b, axis) - plane);
            if (da >= 0.0f) out[m++] = a;
            if ((da < 0.0f) != (db < 0.0f)) {
                Vec3 p = a + (b - a) * (da / (da - db));
                p[axis] = plane;  // exactly on the plane, whatever the rounding
                out[m++] = p;
            }
        }
        n = m;
        for (int i = 0; i < n; ++i) v[i] = out[i];
    }
};

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
    // The float intersection test sees a primitive only to a few ulps of its own coordinates: clip
    // against the box grown by that much, and grow the result by it, so that no reference is
    // dropped from a node where the test would hit it.
    float fuzz = magnitudeSlack(geometry.bounds(prim));
    Bounds3 grown{box.lo - Vec3(fuzz), box.hi + Vec3(fuzz)};

    Polygon poly;
    uint32_t i = geometry.localIndex(prim);
    if (kind == PrimKind::Quad) {
        for (const Vec3& v : geometry.quads()[i].v) poly.v[poly.n++] = v;
    } else {
        const glm::uvec3& t = geometry.triangles()[i];
        for (int k = 0; k < 3; ++k) poly.v[poly.n++] = geometry.positions()[t[k]];
    }
    // Only the planes that cut the primitive's own bounds can clip it (a straddling reference
    // usually crosses one or two of the six): the others would copy the polygon unchanged. The
    // vertices that clipping interpolates stay within those bounds but for rounding, which the
    // slack below covers.
    Bounds3 own;
    for (int k = 0; k < poly.n; ++k) own.extend(poly.v[k]);
    for (int axis = 0; axis < 3 && poly.n > 0; ++axis) {
        if (own.lo[axis] < grown.lo[axis]) poly.clip(axis, grown.lo[axis], 1.0f);
        if (poly.n > 0 && own.hi[axis] > grown.hi[axis]) poly.clip(axis, grown.hi[axis], -1.0f);
    }
    Bounds3 b;
    for (int k = 0; k < poly.n; ++k) b.extend(poly.v[k]);
    if (b.empty()) return b;
    // Grow by the rounding error of the interpolation (a few ulps of the coordinates), then keep
    // it inside the box.
    Vec3 slack = gamma(4) * glm::max(glm::abs(b.lo), glm::abs(b.hi)) + Vec3(fuzz);
    return overlap(Bounds3{b.lo - slack, b.hi + slack}, box);
}

}  // namespace caustic
