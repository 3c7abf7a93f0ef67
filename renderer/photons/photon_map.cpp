#include "photons/photon_map.h"

#include "photons/brute_force_neighbors.h"

namespace caustic {
namespace {

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
    : photons_(std::move(photons)) {
    if (lookup == PhotonLookup::KdTree)
        index_ = std::make_unique<PhotonKdTree>(positions(photons_));
    else
        index_ = std::make_unique<BruteForceNeighbors>(positions(photons_));
}

Color PhotonMap::reflected(const SurfaceInteraction& si, const Vec3& wo, const Material& m,
                           const PhotonEstimate& estimate, PhotonPathMask mask,
                           std::vector<Neighbor>& scratch) const {
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
    Color L(0.0f);
    for (const Neighbor& n : scratch) {
        const Photon& p = photons_[n.id];
        if (!(mask & maskOf(p.path)) || p.bounces > estimate.maxBounces) continue;
        // f is zero for a photon from the other side of a thin surface: it lights only its side.
        L += m.f(wo, p.wi, si.n) * p.power * kernel(estimate.kernel, n.dist2, r2);
    }
    return L;
}

}  // namespace caustic
