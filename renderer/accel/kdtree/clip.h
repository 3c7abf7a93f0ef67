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

/// Conservative bounds of the primitive's parts in the two children of `box` split by the plane at
/// `pos` on `axis`, below and above it, each grown by a few ulps so that rounding in the clipping
/// never loses a sliver of the primitive; empty where the primitive misses a child. Spheres use
/// their bounding box.
void clipPrimitiveToChildren(const Geometry& geometry, uint32_t prim, const Bounds3& box, int axis,
                             float pos, Bounds3& below, Bounds3& above);

}  // namespace caustic
