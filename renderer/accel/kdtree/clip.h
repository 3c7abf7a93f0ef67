// Bounds of the part of a primitive that lies inside a box, for the kd-tree's "perfect splits":
// a triangle that straddles a split plane is clipped to each child's box, so that deeper splits see
// its true extent there (Havran 2000, "Heuristic Ray Shooting Algorithms", section 4.7; Wald &
// Havran 2006, section 4.3).
#pragma once

#include "core/bounds.h"
#include "geometry/geometry.h"

namespace caustic {

/// Slack for a primitive with bounds b: a few ulps of its largest coordinate, how far the float
/// intersection test may hit outside its exact surface.
float magnitudeSlack(const Bounds3& b);
/// A primitive's bounds grown by its magnitude slack.
Bounds3 fuzzyBounds(const Geometry& geometry, uint32_t prim);

/// Conservative bounds of primitive ∩ box, grown by a few ulps so that rounding in the clipping
/// never loses a sliver of the primitive; empty when the primitive misses the box. Spheres use
/// their bounding box.
Bounds3 clipPrimitive(const Geometry& geometry, uint32_t prim, const Bounds3& box);

}  // namespace caustic
