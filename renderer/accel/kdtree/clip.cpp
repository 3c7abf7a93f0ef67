#include "accel/kdtree/clip.h"

#include <algorithm>

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

// A convex polygon being clipped plane by plane.
struct Polygon {
    Vec3 v[12];
    int n = 0;

    // Keeps the part with sign * (p[axis] - plane) >= 0. Only a plane that cuts the primitive's
    // own bounds `own` can clip it (a straddling reference usually crosses one or two of a box's
    // six): the others would copy the polygon unchanged.
    void clip(const Bounds3& own, int axis, float plane, float sign) {
        const bool cuts =
            sign > 0.0f ? component(own.lo, axis) < plane : component(own.hi, axis) > plane;
        if (!cuts || n == 0) return;
        Vec3 out[12];
        n = clipPolygon(v, n, out, axis, plane, sign);
        std::copy(out, out + n, v);
    }

    // Its bounds grown by the rounding error of the interpolation (a few ulps of the coordinates)
    // and by `fuzz`, kept inside `box`; empty when nothing is left.
    Bounds3 bounds(float fuzz, const Bounds3& box) const {
        Bounds3 b;
        for (int k = 0; k < n; ++k) b.extend(v[k]);
        if (b.empty()) return b;
        Vec3 slack = gamma(4) * glm::max(glm::abs(b.lo), glm::abs(b.hi)) + Vec3(fuzz);
        return overlap(Bounds3{b.lo - slack, b.hi + slack}, box);
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

void clipPrimitiveToChildren(const Geometry& geometry, uint32_t prim, const Bounds3& box, int axis,
                             float pos, Bounds3& below, Bounds3& above) {
    Bounds3 belowBox = box, aboveBox = box;
    setComponent(belowBox.hi, axis, pos);
    setComponent(aboveBox.lo, axis, pos);
    const PrimKind kind = geometry.kind(prim);
    if (kind == PrimKind::Sphere) {
        const Bounds3 b = fuzzyBounds(geometry, prim);
        below = overlap(b, belowBox);
        above = overlap(b, aboveBox);
        return;
    }
    Polygon poly;
    const uint32_t i = geometry.localIndex(prim);
    if (kind == PrimKind::Quad) {
        for (const Vec3& v : geometry.quads()[i].v) poly.v[poly.n++] = v;
    } else {
        const glm::uvec3& t = geometry.triangles()[i];
        for (int k = 0; k < 3; ++k) poly.v[poly.n++] = geometry.positions()[t[k]];
    }
    // These bounds are the primitive's own (Geometry::bounds extends them by the same vertices).
    Bounds3 own;
    for (int k = 0; k < poly.n; ++k) own.extend(poly.v[k]);
    // The float intersection test sees a primitive only to a few ulps of its own coordinates: clip
    // against each child box grown by that much, and grow the result by it, so that no reference
    // is dropped from a node where the test would hit it. The four planes the children share are
    // clipped once; each side then takes its two on the split axis. The vertices that clipping
    // interpolates stay within the own bounds but for rounding, which the slack covers.
    const float fuzz = magnitudeSlack(own);
    for (int a = 0; a < 3; ++a) {
        if (a == axis) continue;
        poly.clip(own, a, component(box.lo, a) - fuzz, 1.0f);
        poly.clip(own, a, component(box.hi, a) + fuzz, -1.0f);
    }
    Polygon side = poly;
    side.clip(own, axis, component(box.lo, axis) - fuzz, 1.0f);
    side.clip(own, axis, pos + fuzz, -1.0f);
    below = side.bounds(fuzz, belowBox);
    poly.clip(own, axis, pos - fuzz, 1.0f);
    poly.clip(own, axis, component(box.hi, axis) + fuzz, -1.0f);
    above = poly.bounds(fuzz, aboveBox);
}

}  // namespace caustic
