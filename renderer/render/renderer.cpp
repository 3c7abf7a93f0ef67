#include "render/renderer.h"

#include <chrono>

#include "core/error.h"

namespace caustic {
namespace {

using Clock = Interrupt::Clock;

}  // namespace

RenderStats renderPasses(RenderSession& session, Film& film, const RenderCallbacks& callbacks) {
    const Camera& camera = session.scene().camera;
    if (film.width() != camera.width() || film.height() != camera.height())
        throw InputError("/scene/camera", "the checkpoint to resume is " +
                                              std::to_string(film.width()) + "x" +
                                              std::to_string(film.height()) + ", the camera " +
                                              std::to_string(camera.width()) + "x" +
                                              std::to_string(camera.height()));
    RangeResult range =
        session.renderRange(film.passSet().end(), session.passesTotal(), film, callbacks);

    RenderStats stats;
    stats.acceleratorSeconds = session.acceleratorSeconds();
    stats.integratorSeconds = session.integratorSeconds();
    stats.setupSeconds = stats.acceleratorSeconds + stats.integratorSeconds;
    stats.renderSeconds = range.renderSeconds;
    stats.passSetupSeconds = range.passSetupSeconds;
    stats.rays = range.rays;
    stats.stopReason = range.stopReason;
    stats.threads = session.threads();
    stats.passes = film.passes();
    stats.sppReached = film.passes() * session.sppPerPass();
    stats.samples = uint64_t(stats.sppReached) * uint64_t(camera.width()) * camera.height();
    stats.raysPerSecond = stats.renderSeconds > 0 ? double(stats.rays) / stats.renderSeconds : 0;
    stats.relativeError = film.relativeError();
    stats.relativeNoise = film.relativeNoise();
    stats.relativeBias = film.relativeBias();
    stats.droppedSamples = film.droppedSamples();
    stats.clampedValues = film.clampedValues();
    stats.memory = session.memory(film);
    stats.built = session.scene().built.parts();
    return stats;
}

RenderResult render(const Scene& scene, const RenderSettings& settings,
                    const RenderCallbacks& callbacks) {
    auto t0 = Clock::now();
    // The memory check's pilot stops at a cancel, and at a strict time limit.
    Interrupt setup(callbacks.cancel);
    if (callbacks.timeLimit.strict && settings.timeLimit > 0)
        setup.setDeadline(fromNow(settings.timeLimit - callbacks.timeLimit.secondsBefore));
    RenderSession session(scene, settings, &setup);
    RenderResult result;
    result.film = session.makeFilm();
    result.stats = renderPasses(session, *result.film, callbacks);
    result.stats.totalSeconds = secondsSince(t0);
    return result;
}

}  // namespace caustic
