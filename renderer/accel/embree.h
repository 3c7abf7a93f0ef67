// Intel Embree 3 behind the Accelerator interface: triangles and quads native, spheres as user
// geometry that calls Sphere::intersect, so that every accelerator returns the same hit record.
// Scene built with RTC_SCENE_FLAG_ROBUST (watertight, no culling of rays along edges).
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "accel/accelerator.h"

namespace caustic {

class EmbreeAccel final : public Accelerator {
public:
    /// Builds a device and a scene over `geometry` (which must outlive it). Throws
    /// std::runtime_error with Embree's message if Embree reports an error.
    explicit EmbreeAccel(const Geometry& geometry);

    std::optional<Hit> intersect(const Ray& ray, float tMax) const override;
    bool occluded(const Ray& ray, float tMax) const override;
    Bounds3 bounds() const override { return bounds_; }
    size_t memoryBytes() const override;

    /// Called by the sphere user geometry (Embree's C callbacks).
    const Geometry& geometry() const { return geometry_; }
    uint32_t spherePrim(uint32_t local) const { return spherePrims_[local]; }

private:
    struct DeviceDeleter {
        void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
    };
    struct SceneDeleter {
        void operator()(RTCScene s) const { rtcReleaseScene(s); }
    };

    void addTriangles();
    void addQuads();
    void addSpheres();
    void throwIfError(const char* what) const;
    /// The scene primitive index of each primitive of one kind, by its index within that kind.
    std::vector<uint32_t> primsOfKind(PrimKind kind, size_t count) const;
    /// Commits and attaches a geometry whose primitives are `prims`, and releases our reference.
    void attach(RTCGeometry g, std::vector<uint32_t> prims, const char* what);
    uint32_t primOf(unsigned geomID, unsigned primID) const;

    const Geometry& geometry_;
    // Bytes the device holds, by its memory monitor; declared first, released last.
    std::atomic<int64_t> deviceBytes_{0};
    // Released in reverse order: the scene before its device.
    std::unique_ptr<RTCDeviceTy, DeviceDeleter> device_;
    std::unique_ptr<RTCSceneTy, SceneDeleter> scene_;
    std::string error_;  // last message from the device's error callback
    // Embree geometry ID -> the scene primitive index of each of its primitives: `first` plus the
    // Embree primitive ID when they are consecutive (one geometry holds every primitive of a kind,
    // so a kind's are when no other shape lies between them in the scene: one mesh's triangles
    // always), which saves a cache miss a hit; else looked up in `table`.
    struct GeometryPrims {
        uint32_t first = 0;
        std::vector<uint32_t> table;
    };
    std::vector<GeometryPrims> primsByGeometry_;
    std::vector<uint32_t> spherePrims_;
    Bounds3 bounds_;
};

}  // namespace caustic
