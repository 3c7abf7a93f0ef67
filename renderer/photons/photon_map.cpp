#include "photons/photon_map.h"

#include <algorithm>

#include "materials/surface_bsdf.h"
#include "photons/brute_force_neighbors.h"

namespace caustic {
namespace {

// The bits of a 10-bit integer spread to every third bit (Karras 2012, "Thinking parallel, part
// III").
uint32_t spreadBits(uint32_t v) {
    v = (v * 0x00010001u) & 0xFF0000FFu;
    v = (v * 0x00000101u) & 0x0F00F00Fu;
    v = (v * 0x00000011u) & 0xC30C30C3u;
    v = (v * 0x00000005u) & 0x49249249u;
    return v;
}

// The photons in the Morton order of their positions (ties in emission order), so that the photons
// of a kd-tree leaf, and of the leaves around it, lie close in memory: an estimate reads them from
// a few cache lines instead of one line a photon, as emission order would scatter them.
std::vector<Photon> mortonOrdered(std::vector<Photon> photons) {
    Bounds3 bounds;
    for (const Photon& p : photons) bounds.extend(p.p);
    const Vec3 extent = bounds.diagonal();
    const float scale = 1023.0f / std::max({extent.x, extent.y, extent.z, 1e-30f});
    auto cell = [&](float v, float lo) {
        return uint32_t(std::clamp((v - lo) * scale, 0.0f, 1023.0f));
    };
    std::vector<uint64_t> keys(photons.size());
    for (size_t i = 0; i < photons.size(); ++i) {
        const Vec3& p = photons[i].p;
        const uint32_t code = spreadBits(cell(p.x, bounds.lo.x)) << 2 |
                              spreadBits(cell(p.y, bounds.lo.y)) << 1 |
                              spreadBits(cell(p.z, bounds.lo.z));
        keys[i] = uint64_t(code) << 32 | i;
    }
    std::sort(keys.begin(), keys.end());
    std::vector<Photon> ordered(photons.size());
    for (size_t i = 0; i < keys.size(); ++i) ordered[i] = photons[uint32_t(keys[i])];
    return ordered;
}

std::vector<Vec3> positions(const std::vector<Photon>& photons) {
    std::vector<Vec3> p(photons.size());
    for (size_t i = 0; i < photons.size(); ++i) p[i] = photons[i].p;
    return p;
}

// K(d) for a photon at squared distance d2 in a disk of squared radius r2, normalized so that
// its integral over the disk is 1.
float kernel(PhotonKernel k, float d2, float r2) {
    switch (k) {
        case PhotonKernel::Box:
            return 1.0f / (kPi * r2);
        case PhotonKernel::Cone:
            // w = 1 - d / r integrates to pi r^2 / 3.
            return 3.0f * (1.0f - std::sqrt(d2 / r2)) / (kPi * r2);
        case PhotonKernel::Simpson: {
            // w = (1 - d^2 / r^2)^2 integrates to pi r^2 / 3.
            float t = 1.0f - d2 / r2;
            return 3.0f * t * t / (kPi * r2);
        }
    }
    return 0.0f;
}

}  // namespace

PhotonMap::PhotonMap(std::vector<Photon> photons, PhotonLookup lookup)
    : photons_(mortonOrdered(std::move(photons))) {
    if (lookup == PhotonLookup::KdTree)
        index_ = std::make_unique<PhotonKdTree>(positions(photons_));
    else
        index_ = std::make_unique<BruteForceNeighbors>(positions(photons_));
}

Color PhotonMap::reflected(const SurfaceInteraction& si, const Vec3& wo, const Material& m,
                           const PhotonEstimate& estimate, PhotonPathMask mask,
                           std::vector<Neighbor>& scratch, Color* bias) const {
    if (bias) *bias = Color(0.0f);
    if (photons_.empty()) return Color(0.0f);
    float r2 = estimate.radius * estimate.radius;
    if (estimate.radius > 0.0f) {
        index_->withinRadius(si.p, r2, scratch);
    } else {
        index_->nearest(si.p, estimate.k, kInfinity, scratch);
        if (scratch.empty()) return Color(0.0f);
        r2 = scratch.back().dist2;
    }
    if (!(r2 > 0.0f)) return Color(0.0f);
    // A Lambertian f is the same for every photon on wo's side (Diffuse::f's test) and zero for
    // the others: it is applied once, to the sum.
    const std::optional<Color> lambertian = m.lambertian();
    const SurfaceBsdf bsdf(m, si);
    const Vec3& ns = bsdf.shadingNormal();
    const float side = glm::dot(wo, ns);
    // The estimate at radius r, and (for the bias) at the smaller radius s r.
    const float small2 = kBiasRadiusScale2 * r2;
    Color L(0.0f), Lsmall(0.0f);
    for (const Neighbor& n : scratch) {
        const Photon& p = photons_[n.id];
        if (!(mask & maskOf(p.path)) || p.bounces > estimate.maxBounces) continue;
        // A photon that landed on the other side of a thin surface reaches this side only by
        // transmission, whatever a shading normal says.
        if (!bsdf.agreesWithGeometry(wo, p.wi)) continue;
        Color flux;
        if (!lambertian)
            flux = bsdf.f(wo, p.wi) * p.power;
        else if (side * glm::dot(p.wi, ns) > 0.0f)
            flux = p.power;
        else
            continue;
        L += flux * kernel(estimate.kernel, n.dist2, r2);
        if (bias && n.dist2 < small2) Lsmall += flux * kernel(estimate.kernel, n.dist2, small2);
    }
    if (lambertian) {
        L *= *lambertian;
        Lsmall *= *lambertian;
    }
    if (bias) *bias = (L - Lsmall) / (1.0f - kBiasRadiusScale2);
    return L;
}

}  // namespace caustic
