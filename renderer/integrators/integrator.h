// Integrators estimate the radiance arriving at the camera along a ray. The render loop
// (render/render_session.h) owns pixels, passes and threads; an integrator owns only light
// transport.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "core/interrupt.h"
#include "core/sampler.h"
#include "core/trace_settings.h"
#include "lights/light.h"
#include "scene/scene.h"
#include "scene/visibility.h"

namespace caustic {

/// What one pixel sample carries through an integrator: its random numbers and its counters.
/// One per thread, re-seeded per sample; never shared.
struct SampleContext {
    Sampler sampler;
    uint64_t rays = 0;
    /// Whether Li adds the emission its camera ray sees first; false when the render loop
    /// estimates that over more camera rays (render/seen_emission.h).
    bool cameraEmission = true;
    /// The render's stop request: loops whose length the settings control poll it, and the
    /// sample's result is discarded once it asks to stop.
    InterruptPoller interrupt;
    /// Where textured materials become the material at one point (Integrator::shade), and the
    /// share of a pixel their lookups filter over (the render's 1 / sqrt(spp), as pbrt-v4).
    MaterialScratch scratch[2];
    float footprintScale = 1.0f;
    /// Whether the render keeps each sample's bias (Integrator::estimatesBias); Li adds to
    /// `bias` the bias of its estimate as it estimates it, in the units of its result.
    bool trackBias = false;
    Color bias = Color(0.0f);

    bool interrupted() { return interrupt.poll(); }
};

class Integrator {
public:
    Integrator(const Scene& scene, const Accelerator& accel) : scene_(scene), accel_(accel) {}
    virtual ~Integrator() = default;

    /// Prepares pass `pass` before any Li of that pass (photon tracing, for example); returns the
    /// rays it traced. Called from one thread (it may run its own parallel loops); deterministic
    /// in (seed, pass) so that passes can run on different workers. When interrupt() asks to
    /// stop, it returns early and the pass must be abandoned.
    virtual uint64_t beginPass(uint32_t /*pass*/) { return 0; }
    /// One sample of the radiance arriving at the camera along `ray` (world space, unit direction),
    /// in W/(m^2 sr) per linear RGB channel. Thread-safe.
    virtual Color Li(const Ray& ray, SampleContext& ctx) const = 0;
    /// Whether Li estimates its own bias (SampleContext::bias): the photon maps' density
    /// estimates, whose bias the error estimate then includes (film/film.h, the bias layer).
    virtual bool estimatesBias() const { return false; }
    /// Bytes of the integrator's own structures (photon maps); zero for those that keep none.
    virtual size_t memoryBytes() const { return 0; }
    /// Throws InputError naming the setting at fault when the integrator's own structures would
    /// need more than `budgetBytes` at their peak; called before the first pass.
    virtual void checkMemory(size_t /*budgetBytes*/) const {}

    /// The stop request that beginPass and checkMemory poll (may be null; it must outlive their
    /// calls). Call it only while neither runs.
    void setInterrupt(const Interrupt* interrupt) { interrupt_ = interrupt; }
    const Interrupt* interrupt() const { return interrupt_; }

protected:
    /// Closest hit along the ray, counting it.
    std::optional<Hit> intersect(const Ray& ray, SampleContext& ctx) const {
        ++ctx.rays;
        return intersectVisible(scene_, accel_, ray, kInfinity, ctx.rays);
    }
    /// The material at si as shading sees it (Scene::shade), in the context's scratch `slot`: a
    /// caller that holds one point's material while it shades another uses a second slot.
    const Material& shade(SurfaceInteraction& si, SampleContext& ctx, int slot = 0) const {
        return scene_.shade(si, ctx.scratch[slot], ctx.footprintScale);
    }
    /// A ray leaving surface point si in unit direction w, offset past the surface's rounding
    /// error.
    static Ray spawnRay(const SurfaceInteraction& si, const Vec3& w) {
        return Ray{rayOrigin(si, w), w};
    }
    /// Whether nothing blocks the segment from si to the light sample's point.
    bool unoccluded(const SurfaceInteraction& si, const LightSample& ls, SampleContext& ctx) const;
    /// Light arriving at si from one light chosen by power and reflected towards wo, with a shadow
    /// ray: an unbiased estimate of direct lighting (pbrt-v4 13.2). Zero for specular materials.
    /// With `mis`, area-light samples carry their power-heuristic weight against BSDF sampling,
    /// and the caller adds the BSDF-sampled share (pbrt-v4 13.4).
    Color sampleDirectLight(const SurfaceInteraction& si, const Vec3& wo, const Material& m,
                            SampleContext& ctx, bool mis = false) const;

    const Scene& scene_;
    const Accelerator& accel_;
    const Interrupt* interrupt_ = nullptr;
};

}  // namespace caustic
