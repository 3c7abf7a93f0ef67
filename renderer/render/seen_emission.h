// The emission a pixel sees directly, estimated over more camera rays than the pixel's samples.
//
// A lamp in view is the brightest thing in the image and its edges the noisiest pixels: a pixel
// the edge crosses is worth its covered fraction of the lamp's radiance, which n samples resolve
// to about 1/n (stratified) of a radiance ten or a hundred times the scene's. On the bunny at
// 256² these few hundred pixels held half of the squared error at every spp from 16 to 256
// (bench/README.md, "Lamp edges"). The pixel's value is the emission its camera rays see first
// plus the light reflected at their first hits; the render loop estimates the first term with k
// rays per sample (splitting: each term's own unbiased estimate, as Arnold's camera samples are
// split from its shading samples) and the integrator the second with the sample's own path. A
// ray can only see emission if it meets an emitter's bounding box, so a ray that meets none costs
// a few box tests and no traversal, and a pixel none of whose rays can meet one (the boxes'
// outlines on the screen) costs nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "accel/accelerator.h"
#include "core/bounds.h"
#include "scene/scene.h"

namespace caustic {

class SeenEmission {
public:
    /// Boxes at most this many emissive primitives one by one; more share one box.
    static constexpr size_t kMaxBoxes = 64;

    SeenEmission(const Scene& scene, const Accelerator& accel);

    /// Whether anything in the scene has emission to see (area lights).
    bool any() const { return !boxes_.empty(); }
    /// Whether a camera ray through pixel (x, y) may meet an emitter's box; false only when none
    /// can.
    bool mayBeSeenIn(int x, int y) const {
        for (const Rect& r : outlines_)
            if (float(x) + 1.0f >= r.x0 && float(x) <= r.x1 && float(y) + 1.0f >= r.y0 &&
                float(y) <= r.y1)
                return true;
        return false;
    }
    /// The emission of the first surface along `ray` towards its origin, or black when it emits
    /// nothing or there is none (the background stays the sample's own ray's: it has no bounds
    /// to test against). Counts the ray it traces into `rays`. An emissive texture is filtered
    /// over `footprintScale` of a pixel's footprint (Scene::shade). Thread-safe.
    Color along(const Ray& ray, uint64_t& rays, float footprintScale) const;

private:
    bool mayHitEmitter(const Ray& ray) const;

    // A box's outline in raster space, one pixel wider on every side than its corners' (the
    // rounding of the projection).
    struct Rect {
        float x0, y0, x1, y1;
    };
    static Rect outline(const Bounds3& box, const Camera& camera);

    const Scene& scene_;
    const Accelerator& accel_;
    std::vector<Bounds3> boxes_;
    std::vector<Rect> outlines_;
};

}  // namespace caustic
