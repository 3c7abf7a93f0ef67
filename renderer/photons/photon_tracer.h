// Photon tracing (Jensen 1996; pbrt-v4 15.1 for the weights): photons leave the lights in
// proportion to their power, scatter through every material with importance transport (no 1/eta^2
// on refraction), are ended by Russian roulette, and are stored where they land on a non-specular
// surface. Each stored photon is tagged by the path that brought it, so that an integrator can
// take each part of the light once: direct (L D), caustic (L S+ D) and indirect (the rest).
#pragma once

#include <cstdint>
#include <vector>

#include "accel/accelerator.h"
#include "core/interrupt.h"
#include "scene/scene.h"

namespace caustic {

enum class PhotonPath : uint8_t { Direct, Caustic, Indirect };

/// A photon stored on a surface: 40 bytes (plus about 17 in a PhotonKdTree).
struct Photon {
    Vec3 p;
    Vec3 wi;      ///< Unit direction it came from (pointing away from the surface).
    Color power;  ///< Flux it carries, in watts per channel.
    PhotonPath path;
    /// Scattering events before it landed (0: straight from the light), saturating at 255: a
    /// camera path that looks it up must not make the whole path longer than max_depth.
    uint8_t bounces;
};

struct PhotonTracingOptions {
    uint64_t photons = 100000;  ///< Photon paths emitted.
    int maxDepth = 16;          ///< Most scattering events on a photon path.
    uint64_t seed = 0;
    uint32_t pass = 0;  ///< Photon tracing of pass p is independent of every other pass.
    int threads = 0;    ///< 0 uses every core. The photons do not depend on it.
    /// Store caustic photons only, and end each path at its first non-specular hit (after which it
    /// can carry no caustic): a cheap, separate caustic map. Its random numbers are independent of
    /// the full tracing's with the same seed and pass.
    bool causticOnly = false;
    /// Surfaces whose lobeRoughness() is below this are followed as specular ones are: no photon
    /// is stored on them, and a path that met only such surfaces before it lands is a caustic.
    /// 0: only specular surfaces (the path tracer's photon maps, whose own paths sample every
    /// other surface).
    float followedRoughness = 0.0f;
    /// Polled per path and every few hundred bounces; when it asks to stop, tracing returns
    /// early with `interrupted` set (may be null).
    const Interrupt* interrupt = nullptr;
};

struct PhotonTracing {
    std::vector<Photon> photons;  ///< In emission order: the same for any thread count.
    uint64_t emitted = 0;         ///< Paths emitted (every one, stored or not).
    DVec3 emittedPower{0.0};      ///< Sum of the flux the paths left the lights with.
    uint64_t rays = 0;
    bool interrupted = false;  ///< Stopped early by options.interrupt: the photons are partial.
};

/// Traces `options.photons` photon paths from the scene's lights (none when nothing emits, nor
/// caustic-only ones in a scene without a specular material, where no caustic can be).
PhotonTracing tracePhotons(const Scene& scene, const Accelerator& accel,
                           const PhotonTracingOptions& options);

}  // namespace caustic
