// What an intersection query returns, and the local geometry at a hit point that shading needs.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace caustic {

/// A ray's closest hit, as every accelerator returns it.
struct Hit {
    float t = kInfinity;  ///< Distance along the ray, in units of |d|.
    uint32_t prim = 0;    ///< Primitive index in the scene's Geometry.
    Vec2 uv{0.0f};        ///< Surface parameters: quad (s, t); triangle barycentrics (b1, b2) of
                          ///< vertices 1 and 2; sphere (0, 0) (Sphere::uv gives its parameters).
    Vec3 n{0.0f};         ///< Unit geometric normal on the primitive's front side (not flipped
                          ///< towards the ray).
};

/// The surface at a hit point, reconstructed from a Hit.
struct SurfaceInteraction {
    Vec3 p;       ///< Hit point, computed from the surface parameters, not from o + t d.
    Vec3 pError;  ///< Absolute error bound of p, per component (for ray spawning).
    Vec3 n;       ///< Unit geometric normal, front side.
    Vec2 uv;
    uint32_t prim = 0;
    uint32_t material = 0;
};

/// A point sampled on a surface, with its density per unit area.
struct SurfaceSample {
    Vec3 p;
    Vec3 pError;
    Vec3 n;
    float pdfArea = 0.0f;
};

}  // namespace caustic
