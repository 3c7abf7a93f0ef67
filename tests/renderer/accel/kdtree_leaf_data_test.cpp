// A kd-tree leaf tests eight triangles' edge functions at once (accel/kdtree/leaf_data.h) and
// passes only the lanes it keeps to intersectTriangle. It must keep exactly the lanes whose
// triangles intersectTriangle's own float edge test keeps, bit for bit: one lane dropped is a hit
// the kd-tree misses and brute force finds; one kept too many costs only time, but would mean the
// two tests compute different edge functions.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "accel/kdtree/leaf_data.h"
#include "core/rng.h"

namespace caustic {
namespace {

using Triangle = std::array<Vec3, 3>;

// The scalar edge test: intersectTriangle's first step, with the helpers it uses.
bool scalarMayHit(const WatertightRay& wr, const Triangle& p) {
    float x[3], y[3];
    for (int v = 0; v < 3; ++v)
        shearVertex(wr, component(p[v], wr.kx), component(p[v], wr.ky), component(p[v], wr.kz),
                    x[v], y[v]);
    return edgeTestMayHit(differenceOfProducts(x[1], y[2], y[1], x[2]),
                          differenceOfProducts(x[2], y[0], y[2], x[0]),
                          differenceOfProducts(x[0], y[1], y[0], x[1]));
}

Vec3 randomVec(Rng& rng, float scale) {
    return scale * Vec3(2.0f * rng.uniform() - 1.0f, 2.0f * rng.uniform() - 1.0f,
                        2.0f * rng.uniform() - 1.0f);
}

// A triangle for a lane, of one of the kinds that matter: near the ray, anywhere, with a vertex
// or an edge on the ray (edge functions of zero), of zero area, tiny (edge functions below the
// normal floats), or all zero (padding, or a primitive other than a triangle).
void randomTriangle(Rng& rng, const Ray& ray, float scale, Triangle& p) {
    const Vec3 onRay = ray.o + (scale * 4.0f * rng.uniform()) * ray.d;
    for (Vec3& v : p) v = onRay + randomVec(rng, scale * 0.1f);
    switch (rng.nextUint() % 7) {
        case 0:
            break;
        case 1:
            for (Vec3& v : p) v = randomVec(rng, scale * 4.0f);
            break;
        case 2:
            p[rng.nextUint() % 3] = onRay;
            break;
        case 3:
            p[0] = onRay - scale * 0.1f * rng.uniform() * (p[1] - onRay);
            break;
        case 4:
            p[1] = p[0];
            break;
        case 5:
            for (Vec3& v : p) v = onRay + randomVec(rng, 1e-30f);
            break;
        default:
            p[0] = p[1] = p[2] = Vec3(0.0f);
    }
}

// A scale from 1e-4 to 1e4, and a ray at that scale: its direction along an axis when
// `axisAligned` (zero components), else random; false for the rare zero direction.
float randomScale(Rng& rng) {
    return std::pow(10.0f, float(int(rng.nextUint() % 9) - 4));
}

bool randomRay(Rng& rng, float scale, bool axisAligned, Ray& ray) {
    ray = Ray{randomVec(rng, scale), randomVec(rng, 1.0f)};
    if (axisAligned) {
        ray.d = Vec3(0.0f);
        setComponent(ray.d, int(rng.nextUint() % 3), -1.0f);
    }
    if (!(glm::length(ray.d) > 0.0f)) return false;
    ray.d = glm::normalize(ray.d);
    return true;
}

TEST(KdLeaf, KeepsExactlyTheLanesTheScalarEdgeTestKeeps) {
    Rng rng(17);
    uint64_t lanes = 0, kept = 0, hits = 0;
    for (int trial = 0; trial < 10000; ++trial) {
        const float scale = randomScale(rng);
        Ray ray;
        if (!randomRay(rng, scale, trial % 5 == 0, ray)) continue;
        const WatertightRay wr(ray);

        // A leaf of 1 to 20 triangles, so that lanes past its end read the next coordinate's
        // words and, for the last coordinate and the last block, the primitive indices and the
        // padding after them, with garbage that must be masked off.
        const uint32_t n = 1 + rng.nextUint() % 20;
        std::vector<Triangle> tri(n);
        std::vector<uint32_t> leaf(kd_leaf::words(n) + kd_leaf::kPadWords);
        for (uint32_t i = 0; i < n; ++i) {
            randomTriangle(rng, ray, scale, tri[i]);
            leaf[kd_leaf::primitives(n) + i] = rng.nextUint();
            for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a)
                    leaf[kd_leaf::coordinate(n, v, a) + i] =
                        std::bit_cast<uint32_t>(component(tri[i][v], a));
        }
        for (uint32_t w = kd_leaf::primitives(n) + n; w < leaf.size(); ++w) leaf[w] = 0;
        for (uint32_t first = 0; first < n; first += kd_leaf::kLanes) {
            const uint32_t mask = mayHitLanes(leaf.data(), n, first, wr);
            for (uint32_t l = 0; l < uint32_t(kd_leaf::kLanes); ++l) {
                const bool lane = (mask >> l) & 1u;
                const uint32_t i = first + l;
                if (i >= n) {
                    ASSERT_FALSE(lane) << "trial " << trial << ": lane " << i << " of " << n;
                    continue;
                }
                const Triangle& p = tri[i];
                ASSERT_EQ(lane, scalarMayHit(wr, p)) << "trial " << trial << ", lane " << i;
                const bool hit =
                    intersectTriangle(wr, std::numeric_limits<float>::infinity(), p[0], p[1], p[2])
                        .has_value();
                ASSERT_TRUE(lane || !hit) << "trial " << trial << ", lane " << i;
                ++lanes;
                kept += lane;
                hits += hit;
            }
        }
    }
    // Both outcomes occur often, so the comparison above means something.
    EXPECT_GT(hits, lanes / 10);
    EXPECT_LT(kept, lanes * 3 / 4);
}

// A leaf culls its blocks of eight by their boxes, eight boxes at once (meetsBlocks). It must keep
// exactly the blocks whose boxes clipToBox says the ray meets within [0, tMax], bit for bit: a
// block culled wrongly is a hit the kd-tree misses. Boxes of every kind that matters: around the
// ray, anywhere, flat on an axis (a triangle in an axis plane), with the origin on a face (a NaN
// slab for a zero direction component), and empty ones.
TEST(KdLeaf, CullsExactlyTheBlocksClipToBoxRejects) {
    Rng rng(29);
    uint64_t blocks = 0, met = 0;
    for (int trial = 0; trial < 10000; ++trial) {
        const float scale = randomScale(rng);
        Ray ray;
        if (!randomRay(rng, scale, trial % 5 == 0, ray)) continue;
        const Vec3 invDir = 1.0f / ray.d;
        const uint32_t negative = directionSignBits(ray.d);
        const BlockRay blockRay(ray.o, invDir, negative);
        const float tMax = rng.nextUint() % 2 ? kInfinity : scale * 4.0f * rng.uniform();

        // A leaf of 1 to 140 primitives: 1 to 18 blocks, so that a second group of eight boxes
        // and lanes past the last block (reading the padding, which must be masked off) occur.
        const uint32_t n = 1 + rng.nextUint() % 140, b = kd_leaf::blocks(n);
        std::vector<Bounds3> box(b);
        std::vector<uint32_t> leaf(kd_leaf::words(n) + kd_leaf::kPadWords, 0x7fc00000u);
        for (uint32_t k = 0; k < b; ++k) {
            const Vec3 onRay = ray.o + (scale * 4.0f * rng.uniform()) * ray.d;
            const Vec3 c = rng.nextUint() % 2 ? onRay + randomVec(rng, scale * 0.2f)
                                              : randomVec(rng, scale * 4.0f);
            const Vec3 h = glm::abs(randomVec(rng, scale * 0.2f));
            box[k] = Bounds3{c - h, c + h};
            const int axis = int(rng.nextUint() % 3);
            switch (rng.nextUint() % 5) {
                case 0:  // flat
                    setComponent(box[k].hi, axis, component(box[k].lo, axis));
                    break;
                case 1:  // the origin on a face
                    setComponent(box[k].lo, axis, component(ray.o, axis));
                    break;
                case 2:  // empty
                    std::swap(box[k].lo, box[k].hi);
                    break;
                default:
                    break;
            }
            storeBoxInRows(leaf.data() + kd_leaf::blockBound(n, 0, 0), b, k, box[k]);
        }
        for (uint32_t first = 0; first < b; first += kd_leaf::kLanes) {
            const uint32_t mask = meetsBlocks(leaf.data(), n, first, blockRay, tMax);
            for (uint32_t l = 0; l < uint32_t(kd_leaf::kLanes); ++l) {
                const bool lane = (mask >> l) & 1u;
                const uint32_t k = first + l;
                if (k >= b) {
                    ASSERT_FALSE(lane) << "trial " << trial << ": block " << k << " of " << b;
                    continue;
                }
                float t0 = 0.0f, t1 = tMax;
                ASSERT_EQ(lane, clipToBox(box[k], ray.o, invDir, negative, t0, t1))
                    << "trial " << trial << ", block " << k;
                ++blocks;
                met += lane;
            }
        }
    }
    // Both outcomes occur often, so the comparison above means something.
    EXPECT_GT(met, blocks / 20);
    EXPECT_LT(met, blocks * 3 / 4);
}

}  // namespace
}  // namespace caustic
