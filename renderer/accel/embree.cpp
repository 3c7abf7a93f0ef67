#include "accel/embree.h"

#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace caustic {
namespace {

void errorCallback(void* user, RTCError code, const char* message) {
    auto* error = static_cast<std::string*>(user);
    *error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
             (message ? message : "(no message)");
}

// Embree reports each allocation (bytes > 0) and release (bytes < 0) of its BVH and buffers, from
// any thread (Embree 3 API, rtcSetDeviceMemoryMonitorFunction).
bool countMemory(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<std::atomic<int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
    return true;
}

// Embree reads the ray in 16-byte loads: origin and tnear, direction and time, then tfar, mask,
// id and flags. Each is written here by one 16-byte store: written field by field, a load that
// spans several stores waits until they have all reached the cache (the store-to-load forward
// fails), and in a path tracer about 3% of the time sat on those waits (perf annotate).
void setRay(RTCRay& r, const Ray& ray, float tMax) {
    _mm_store_ps(&r.org_x, _mm_setr_ps(ray.o.x, ray.o.y, ray.o.z, 0.0f));
    _mm_store_ps(&r.dir_x, _mm_setr_ps(ray.d.x, ray.d.y, ray.d.z, 0.0f));
    _mm_store_si128(reinterpret_cast<__m128i*>(&r.tfar),
                    _mm_setr_epi32(std::bit_cast<int>(tMax), -1, 0, 0));
}

// User geometry callbacks for spheres: Embree passes N rays with a validity mask.
void sphereBounds(const RTCBoundsFunctionArguments* args) {
    auto* self = static_cast<const EmbreeAccel*>(args->geometryUserPtr);
    Bounds3 b = self->geometry().bounds(self->spherePrim(args->primID));
    *args->bounds_o = RTCBounds{b.lo.x, b.lo.y, b.lo.z, 0.0f, b.hi.x, b.hi.y, b.hi.z, 0.0f};
}

Ray rayAt(RTCRayN* rays, unsigned n, unsigned i) {
    return Ray{
        Vec3(RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i), RTCRayN_org_z(rays, n, i)),
        Vec3(RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i), RTCRayN_dir_z(rays, n, i))};
}

void sphereIntersect(const RTCIntersectFunctionNArguments* args) {
    auto* self = static_cast<const EmbreeAccel*>(args->geometryUserPtr);
    const Sphere& sphere = self->geometry().spheres()[args->primID];
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        Ray ray = rayAt(rays, args->N, i);
        float& tfar = RTCRayN_tfar(rays, args->N, i);
        auto t = sphere.intersect(ray, tfar);
        if (!t || *t < RTCRayN_tnear(rays, args->N, i)) continue;
        tfar = *t;
        // No normal or uv: finish() computes the normal of the closest hit only, from our data.
        RTCHitN_Ng_x(hits, args->N, i) = 0.0f;
        RTCHitN_Ng_y(hits, args->N, i) = 0.0f;
        RTCHitN_Ng_z(hits, args->N, i) = 0.0f;
        RTCHitN_u(hits, args->N, i) = 0.0f;
        RTCHitN_v(hits, args->N, i) = 0.0f;
        RTCHitN_primID(hits, args->N, i) = args->primID;
        RTCHitN_geomID(hits, args->N, i) = args->geomID;
        RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
    }
}

void sphereOccluded(const RTCOccludedFunctionNArguments* args) {
    auto* self = static_cast<const EmbreeAccel*>(args->geometryUserPtr);
    const Sphere& sphere = self->geometry().spheres()[args->primID];
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        float& tfar = RTCRayN_tfar(args->ray, args->N, i);
        auto t = sphere.intersect(rayAt(args->ray, args->N, i), tfar);
        if (t && *t >= RTCRayN_tnear(args->ray, args->N, i)) tfar = -kInfinity;
    }
}

}  // namespace

EmbreeAccel::EmbreeAccel(const Geometry& geometry) : geometry_(geometry) {
    device_.reset(rtcNewDevice(nullptr));
    if (!device_) throw std::runtime_error("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(device_.get(), errorCallback, &error_);
    rtcSetDeviceMemoryMonitorFunction(device_.get(), countMemory, &deviceBytes_);
    scene_.reset(rtcNewScene(device_.get()));
    rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);
    addTriangles();
    addQuads();
    addSpheres();
    rtcCommitScene(scene_.get());
    throwIfError("building the scene");
    RTCBounds b;
    rtcGetSceneBounds(scene_.get(), &b);
    if (geometry.size() > 0)
        bounds_ =
            Bounds3{Vec3(b.lower_x, b.lower_y, b.lower_z), Vec3(b.upper_x, b.upper_y, b.upper_z)};
}

void EmbreeAccel::throwIfError(const char* what) const {
    if (!error_.empty()) throw std::runtime_error(error_ + " (" + what + ")");
}

void EmbreeAccel::addTriangles() {
    const auto& positions = geometry_.positions();
    const auto& triangles = geometry_.triangles();
    if (triangles.empty()) return;
    RTCGeometry g = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
    for (size_t i = 0; i < positions.size(); ++i)
        for (int c = 0; c < 3; ++c) v[3 * i + size_t(c)] = positions[i][c];
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles.size()));
    for (size_t i = 0; i < triangles.size(); ++i)
        for (int c = 0; c < 3; ++c) idx[3 * i + size_t(c)] = triangles[i][c];
    attach(g, primsOfKind(PrimKind::Triangle, triangles.size()), "adding triangles");
}

std::vector<uint32_t> EmbreeAccel::primsOfKind(PrimKind kind, size_t count) const {
    std::vector<uint32_t> prims(count);
    for (uint32_t prim = 0; prim < geometry_.size(); ++prim)
        if (geometry_.kind(prim) == kind) prims[geometry_.localIndex(prim)] = prim;
    return prims;
}

void EmbreeAccel::attach(RTCGeometry g, std::vector<uint32_t> prims, const char* what) {
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(scene_.get(), g);
    rtcReleaseGeometry(g);
    primsByGeometry_.resize(id + 1);
    GeometryPrims& mapped = primsByGeometry_[id];
    mapped.first = prims.empty() ? 0 : prims[0];
    for (size_t k = 0; k < prims.size(); ++k) {
        if (prims[k] != mapped.first + k) {
            mapped.table = std::move(prims);
            break;
        }
    }
    throwIfError(what);
}

void EmbreeAccel::addQuads() {
    const auto& quads = geometry_.quads();
    if (quads.empty()) return;
    RTCGeometry g = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_QUAD);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4 * quads.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), quads.size()));
    for (size_t q = 0; q < quads.size(); ++q) {
        for (int k = 0; k < 4; ++k) {
            for (int c = 0; c < 3; ++c) v[12 * q + 3 * size_t(k) + size_t(c)] = quads[q].v[k][c];
            idx[4 * q + size_t(k)] = unsigned(4 * q + size_t(k));
        }
    }
    attach(g, primsOfKind(PrimKind::Quad, quads.size()), "adding quads");
}

void EmbreeAccel::addSpheres() {
    const auto& spheres = geometry_.spheres();
    if (spheres.empty()) return;
    spherePrims_ = primsOfKind(PrimKind::Sphere, spheres.size());
    RTCGeometry g = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, unsigned(spheres.size()));
    rtcSetGeometryUserData(g, const_cast<EmbreeAccel*>(this));
    rtcSetGeometryBoundsFunction(g, sphereBounds, const_cast<EmbreeAccel*>(this));
    rtcSetGeometryIntersectFunction(g, sphereIntersect);
    rtcSetGeometryOccludedFunction(g, sphereOccluded);
    attach(g, spherePrims_, "adding spheres");
}

uint32_t EmbreeAccel::primOf(unsigned geomID, unsigned primID) const {
    const GeometryPrims& g = primsByGeometry_[geomID];
    return g.table.empty() ? g.first + primID : g.table[primID];
}

std::optional<Hit> EmbreeAccel::intersect(const Ray& ray, float tMax) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    setRay(rh.ray, ray, tMax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_.get(), &context, &rh);
    // One return of one object, so that it is the caller's (and finish() writes into it).
    std::optional<Hit> hit;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        // The normal comes from the scene's own data, as with every accelerator.
        geometry_.finish(primOf(rh.hit.geomID, rh.hit.primID), ray,
                         PrimHit{rh.ray.tfar, Vec2(rh.hit.u, rh.hit.v)}, hit.emplace());
    }
    return hit;
}

bool EmbreeAccel::occluded(const Ray& ray, float tMax) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    setRay(r, ray, tMax);
    rtcOccluded1(scene_.get(), &context, &r);
    return r.tfar < 0.0f;
}

size_t EmbreeAccel::memoryBytes() const {
    // What the device holds (BVH and vertex buffers, as its monitor reports), and our index.
    size_t index = 0;
    for (const GeometryPrims& g : primsByGeometry_) index += g.table.capacity() * sizeof(uint32_t);
    return size_t(std::max<int64_t>(0, deviceBytes_.load())) + index +
           spherePrims_.capacity() * sizeof(uint32_t);
}

}  // namespace caustic
