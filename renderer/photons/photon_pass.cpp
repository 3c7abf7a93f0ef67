#include "photons/photon_pass.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace caustic {

PhotonTracingOptions photonTracingOptions(const TraceSettings& trace, uint64_t photons,
                                          uint32_t pass, bool causticOnly,
                                          const Interrupt* interrupt) {
    PhotonTracingOptions o;
    o.photons = photons;
    o.maxDepth = trace.maxDepth;
    o.seed = trace.seed;
    o.pass = pass;
    o.threads = trace.threads;
    o.causticOnly = causticOnly;
    o.interrupt = interrupt;
    return o;
}

float progressiveRadius(float r0, float alpha, uint32_t pass) {
    double r2 = double(r0) * double(r0);
    for (uint32_t j = 1; j <= pass; ++j) r2 *= (double(j) - 1.0 + double(alpha)) / double(j);
    return float(std::sqrt(r2));
}

float firstProgressiveRadius(double radius, const Bounds3& sceneBounds) {
    return radius > 0 ? float(radius) : 0.002f * glm::length(sceneBounds.hi - sceneBounds.lo);
}

size_t photonPassPeakBytes(double storedPhotons) {
    // Tracing holds each photon twice while it joins the chunks (80 bytes); a map then holds 40
    // bytes a photon, and while its tree builds 12 of positions, 16 of the build's working copy,
    // and the tree's 16 and at most 1 of splits (photons/photon_kdtree.h): 85. A 10% margin
    // covers the pilot's sampling error.
    return size_t(1.1 * 85.0 * storedPhotons);
}

void checkPhotonPeak(size_t needBytes, size_t budgetBytes, const char* setting) {
    if (needBytes <= budgetBytes) return;
    auto mib = [](size_t b) { return std::to_string((b + (1u << 20) - 1) >> 20) + " MiB"; };
    throw InputError(setting, "the photon maps of a pass would need about " + mib(needBytes) +
                                  " (estimated from a pilot tracing), more than the " +
                                  mib(budgetBytes) + " the memory limit leaves; lower it or " +
                                  "raise memory_limit");
}

}  // namespace caustic
