// What every photon-mapping pass shares, whoever reads the maps (the photon integrators, the path
// tracer's progressive maps): its tracing options, the progressive radius of pass i, and the
// peak memory of its tracing and maps with the refusal when it exceeds the budget.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/bounds.h"
#include "core/trace_settings.h"
#include "photons/photon_tracer.h"

namespace caustic {

/// The photon tracing of pass `pass`: `photons` paths; max_depth, seed and threads from `trace`.
PhotonTracingOptions photonTracingOptions(const TraceSettings& trace, uint64_t photons,
                                          uint32_t pass, bool causticOnly,
                                          const Interrupt* interrupt);

/// The radius of pass `pass` (0-based) for initial radius r0: r_i^2 = r_0^2 prod_{j=1..i}
/// (j - 1 + alpha) / j (Knaus & Zwicker 2011, eq. 20), which depends on the pass index alone.
float progressiveRadius(float r0, float alpha, uint32_t pass);
/// The first pass's radius of a progressive estimate: `radius`, or 1/500 of the diagonal of
/// `sceneBounds` when it is 0.
float firstProgressiveRadius(double radius, const Bounds3& sceneBounds);

/// The most paths of a pilot tracing, from which a pass's peak memory is estimated (a few
/// milliseconds).
inline constexpr uint64_t kPilotPhotonPaths = 8192;
/// Peak bytes of one pass that stores `storedPhotons` photons (its maps and their tracing).
size_t photonPassPeakBytes(double storedPhotons);
/// Throws InputError at `setting` when `needBytes` of photon maps exceed `budgetBytes`.
void checkPhotonPeak(size_t needBytes, size_t budgetBytes, const char* setting);

}  // namespace caustic
