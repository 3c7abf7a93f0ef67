// A photon map: stored photons, a PhotonKdTree over their positions, and the density estimate of
// reflected radiance (Jensen 2001, eq. 7.6): L(x, wo) ~ sum_p f(wo, wi_p) Phi_p K(|x - x_p|) over
// the k nearest photons or those within a fixed radius, with a normalized kernel K.
#pragma once

#include <memory>
#include <vector>

#include "materials/material.h"
#include "photons/photon_kdtree.h"
#include "photons/photon_tracer.h"

namespace caustic {

/// Density-estimation kernels, each normalized to integrate to 1 over its disk (Jensen 2001, 7.2;
/// Silverman 1986 for the biweight, which photon-mapping texts call Simpson's kernel).
enum class PhotonKernel { Box, Cone, Simpson };

struct PhotonEstimate {
    int k = 50;           ///< Photons per estimate, when radius is 0.
    float radius = 0.0f;  ///< Fixed search radius; 0 uses the k nearest.
    PhotonKernel kernel = PhotonKernel::Cone;
    /// Photons that landed after more scattering events are left out (Photon::bounces), so that
    /// a camera path and the photon paths it looks up stay within max_depth together.
    int maxBounces = 255;
};

/// The bias of a density estimate at radius r, from the same photons read at a radius s r as
/// well (s^2 = kBiasRadiusScale2): where the photon density is smooth, a kernel estimate's bias
/// grows as r^2 (Silverman 1986, 3.3.1: b(r) = r^2 k2 / 2 times the density's Laplacian, k2 the
/// kernel's second moment; the reason progressive photon mapping shrinks its radius, Hachisuka et
/// al. 2008), so L(r) - L(s r) estimates b(r) (1 - s^2). The smaller disk holds half the photons:
/// the difference is noisy, and a caller averages it over the passes like the image.
inline constexpr float kBiasRadiusScale2 = 0.5f;

/// Which photon paths an estimate counts (a bit per PhotonPath).
using PhotonPathMask = unsigned;
constexpr PhotonPathMask maskOf(PhotonPath p) {
    return 1u << unsigned(p);
}
constexpr PhotonPathMask kAllPhotonPaths = 7u;

/// The neighbour index behind a map: ours, or every photon for every look-up (the baseline of the
/// seed's Table 1, and the reference the tree is tested against).
enum class PhotonLookup { KdTree, BruteForce };

class PhotonMap {
public:
    explicit PhotonMap(std::vector<Photon> photons, PhotonLookup lookup = PhotonLookup::KdTree);

    /// Radiance reflected towards wo at si by material m from the photons around si.p whose path
    /// is in `mask`. The radius is that of the k nearest of all photons (or the fixed one), so the
    /// mask selects a component of one density estimate. `scratch` is reused between calls.
    /// With `bias`, also the estimate's bias there (see kBiasRadiusScale2).
    Color reflected(const SurfaceInteraction& si, const Vec3& wo, const Material& m,
                    const PhotonEstimate& estimate, PhotonPathMask mask,
                    std::vector<Neighbor>& scratch, Color* bias = nullptr) const;

    size_t size() const { return photons_.size(); }
    /// 40 bytes a photon plus 16 in the tree (12 in the brute-force index).
    size_t memoryBytes() const {
        return photons_.capacity() * sizeof(Photon) + index_->memoryBytes();
    }

private:
    std::vector<Photon> photons_;
    std::unique_ptr<NeighborIndex> index_;
};

}  // namespace caustic
