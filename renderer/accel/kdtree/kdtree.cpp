// Front-to-back traversal (pbrt-v3 4.4.3), made robust for the cases of section 4.4 of Havran 2000:
// direction components of zero, rays lying in a split plane, and hits exactly on a plane.
#include "accel/kdtree/kdtree.h"

#include <bit>

namespace caustic {
namespace {

// Plane crossings are compared with the slack of box slabs (core/bounds.h).
constexpr float kSlack = kRayBoxSlack;

}  // namespace

template <bool AnyHit>
bool KdTreeAccel::traverse(const Ray& ray, float tMax, uint32_t& bestPrim, PrimHit& best) const {
    if (nodes_.empty()) return false;
    // Locals whose address is never taken, and the arrays' data pointers, which stores through
    // `best` could otherwise alias: the loop keeps them in registers instead of reloading them.
    const Vec3 org = ray.o;
    const Vec3 invDir = 1.0f / ray.d;
    // Bit a: the direction's component a is negative. In a register, not an array: the lookup
    // is on the chain of dependent loads from one node to the next.
    const uint32_t negative = directionSignBits(ray.d);
    float tMin = 0.0f, tEnd = tMax;
    if (!clipToBox(bounds_, org, invDir, negative, tMin, tEnd)) return false;
    const BlockRay blockRay(org, invDir, negative);
    const Node* nodes = nodes_.data();
    const uint32_t* leafData = leafData_.data();

    struct Todo {
        uint32_t node;
        float tMin, tMax;
    };
    Todo todo[kMaxDepth + 4 + KdTopCells::kMaxCells];
    int todoCount = 0;
    // The top cells whose boxes the ray meets, each with the ray's range in its box, pushed the
    // farthest first so that they are popped front to back (top_cells.h).
    const KdTopCells::Octant& top = top_.octants[negative];
    for (uint32_t group = top.stride; group != 0;) {
        group -= kd_leaf::kLanes;
        const BoxHits cells =
            meetsBoxes(top.bounds.data(), top.stride, top.count, group, blockRay, tMin, tEnd);
        for (uint32_t met = cells.mask; met != 0;) {
            const int lane = 31 - std::countl_zero(met);
            met &= ~(1u << lane);
            todo[todoCount++] =
                Todo{top.roots[group + uint32_t(lane)], cells.tNear[lane], cells.tFar[lane]};
        }
    }
    if (todoCount == 0) return false;
    const WatertightRay wr(ray);
    float closest = tMax;
    bool found = false;
    while (todoCount != 0) {
        --todoCount;
        uint32_t index = todo[todoCount].node;
        tMin = todo[todoCount].tMin;
        tEnd = todo[todoCount].tMax;
        // Everything left lies beyond the closest hit.
        if (closest < tMin * (1.0f - kSlack)) break;
        while (true) {
            const Node& node = nodes[index];
            if (node.isLeaf()) break;
            // The near child, which the ray enters first, is the one below the plane when the
            // direction's component is positive, above it when negative. A zero component puts
            // the plane at -inf or +inf, the far or the near child alone, or at NaN when the ray
            // lies in the plane, where both tests fail and both children are visited (with a
            // NaN range, which only widens what the subtree visits). Branches, not masks: for
            // coherent rays the processor predicts them and runs ahead into the next node (steps
            // free of branches are 1.3 to 1.85 times as slow on primary rays, and at most 1.17
            // times as fast on random ones: bench/accel_rays_ab.sh, bench/README.md).
            const int axis = node.axis();
            const float tPlane = (node.split - component(org, axis)) * component(invDir, axis);
            const uint32_t below = index + 1, above = node.aboveChild();
            const bool nearAbove = (negative >> axis) & 1u;
            const uint32_t nearChild = nearAbove ? above : below;
            const uint32_t farChild = nearAbove ? below : above;
            if (tPlane > tEnd * (1.0f + kSlack)) {
                index = nearChild;
            } else if (tPlane < tMin * (1.0f - kSlack)) {
                index = farChild;
            } else {
                todo[todoCount++] = Todo{farChild, tPlane, tEnd};
                index = nearChild;
                tEnd = tPlane;
            }
        }

        // Test the leaf's blocks against the closest hit so far, eight boxes at once; then the
        // primitives of each block the ray meets, eight lanes at once; then each lane that may
        // hit by itself.
        const Node& node = nodes[index];
        const uint32_t count = node.primCount();
        const uint32_t* leaf = leafData + node.leafOffset;
        const uint32_t blocks = kd_leaf::blocks(count);
        for (uint32_t group = 0; group < blocks; group += kd_leaf::kLanes) {
            for (uint32_t met = meetsBlocks(leaf, count, group, blockRay, closest); met != 0;
                 met &= met - 1u) {
                const uint32_t first = (group + uint32_t(std::countr_zero(met))) * kd_leaf::kLanes;
                for (uint32_t lanes = mayHitLanes(leaf, count, first, wr); lanes != 0;
                     lanes &= lanes - 1u) {
                    const uint32_t i = first + uint32_t(std::countr_zero(lanes));
                    const uint32_t word = leaf[kd_leaf::primitives(count) + i];
                    const uint32_t prim = word & ~kd_leaf::kOtherKind;
                    const auto vertex = [&](int v) {
                        Vec3 p;
                        for (int a = 0; a < 3; ++a)
                            setComponent(
                                p, a,
                                std::bit_cast<float>(leaf[kd_leaf::coordinate(count, v, a) + i]));
                        return p;
                    };
                    auto h = word & kd_leaf::kOtherKind
                                 ? geometry_.intersect(prim, wr, closest)
                                 : Geometry::intersectVertices(wr, closest, vertex(0), vertex(1),
                                                               vertex(2));
                    if (h) {
                        if constexpr (AnyHit) return true;
                        closest = h->t;
                        best = *h;
                        bestPrim = prim;
                        found = true;
                    }
                }
            }
        }
    }
    return found;
}

std::optional<Hit> KdTreeAccel::intersect(const Ray& ray, float tMax) const {
    uint32_t prim = 0;
    PrimHit best{};
    std::optional<Hit> hit;  // one return of one object, written in place (Geometry::finish)
    if (traverse<false>(ray, tMax, prim, best)) geometry_.finish(prim, ray, best, hit.emplace());
    return hit;
}

bool KdTreeAccel::occluded(const Ray& ray, float tMax) const {
    uint32_t prim = 0;
    PrimHit hit{};
    return traverse<true>(ray, tMax, prim, hit);
}

}  // namespace caustic
