// The reference accelerator: tests every primitive. O(N) per ray; for checking the others and for
// scenes of a handful of primitives.
#pragma once

#include "accel/accelerator.h"

namespace caustic {

class BruteForceAccel final : public Accelerator {
public:
    explicit BruteForceAccel(const Geometry& geometry) : geometry_(geometry) {}

    std::optional<Hit> intersect(const Ray& ray, float tMax) const override;
    bool occluded(const Ray& ray, float tMax) const override;
    Bounds3 bounds() const override { return geometry_.bounds(); }
    size_t memoryBytes() const override { return 0; }

private:
    const Geometry& geometry_;
};

}  // namespace caustic
