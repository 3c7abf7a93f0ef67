// Ray-scene intersection. Implementations: "bruteforce" (the reference: every primitive, every
// ray), "kdtree" and "embree". Built once per render over a Geometry, then queried const.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/bounds.h"
#include "core/ray.h"
#include "geometry/geometry.h"

namespace caustic {

class Accelerator {
public:
    virtual ~Accelerator() = default;

    /// The closest hit with t in (0, tMax), world space, t in units of |ray.d|; nullopt on a miss.
    /// Thread-safe.
    virtual std::optional<Hit> intersect(const Ray& ray, float tMax) const = 0;
    /// Whether any primitive is hit with t in (0, tMax). Thread-safe; may stop at the first hit.
    virtual bool occluded(const Ray& ray, float tMax) const = 0;
    /// Bounds of every primitive.
    virtual Bounds3 bounds() const = 0;
    /// Bytes the structure holds beyond the Geometry itself.
    virtual size_t memoryBytes() const = 0;
};

/// The accelerator names `createAccelerator` accepts.
const std::vector<std::string>& acceleratorNames();

/// Builds the named accelerator over `geometry`, which must outlive it. Throws InputError (path
/// "/settings/accelerator") for an unknown name, listing the valid ones.
std::unique_ptr<Accelerator> createAccelerator(const std::string& name, const Geometry& geometry);

}  // namespace caustic
