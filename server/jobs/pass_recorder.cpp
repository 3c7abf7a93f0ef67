#include "jobs/pass_recorder.h"

#include <cmath>

namespace caustic::server {

using SteadyClock = std::chrono::steady_clock;

double secondsRendered(const Job& job) {
    if (!job.convergence.empty() && job.convergence.back().contains("seconds"))
        return job.convergence.back()["seconds"].get<double>();
    return 0;
}

PassRecorder::PassRecorder(JobStore& store, const JobFiles& files, JobEvents& events,
                           LeaseKeeper& lease, const Job& job, const RenderSettings& settings,
                           int passesTotal, std::atomic<uint64_t>& passCounter)
    : store_(store),
      files_(files),
      events_(events),
      lease_(lease),
      job_(job),
      settings_(settings),
      passesTotal_(passesTotal),
      passCounter_(passCounter),
      priorSeconds_(secondsRendered(job)),
      started_(SteadyClock::now()),
      lastPreview_(started_ - std::chrono::hours(1)) {}

bool PassRecorder::record(const Film& film, double seconds, double eta) {
    double error = film.relativeError();
    Json point{{"pass", film.passes()},
               {"seconds", seconds},
               {"relative_error", std::isfinite(error) ? Json(error) : Json(nullptr)}};
    return store_.recordPass(job_.id, job_.attempt, double(film.passes()) / passesTotal_,
                             film.passes(), passesTotal_, error, eta, point);
}

void PassRecorder::catchUp(const Film& checkpoint) {
    if (checkpoint.passes() > job_.passesDone && !record(checkpoint, priorSeconds_, -1))
        lease_.lost = lease_.cancel = true;
}

void PassRecorder::onProgress(const RenderProgress& p) {
    // The render's forecast (render/forecast.h): the pass budget, the time limit or the target
    // error, whichever it expects first.
    events_.setLive(job_.id, LiveProgress{p.fraction, p.passesTotal, p.relativeError, p.etaSeconds,
                                          p.etaReason});
}

void PassRecorder::onPass(const Film& film) {
    if (lease_.lost) return;
    files_.writeCheckpoint(job_.id, job_.attempt, film);
    if (SteadyClock::now() - lastPreview_ > std::chrono::milliseconds(500)) {
        files_.writeImage(job_.id, job_.attempt, "preview.png", film, settings_.exposure);
        lastPreview_ = SteadyClock::now();
    }
    std::optional<LiveProgress> live = events_.live(job_.id);
    double seconds =
        priorSeconds_ + std::chrono::duration<double>(SteadyClock::now() - started_).count();
    if (!record(film, seconds, live ? live->etaSeconds : -1)) {
        lease_.lost = lease_.cancel = true;
        return;
    }
    ++passCounter_;
    events_.notify();
}

RenderCallbacks PassRecorder::callbacks() {
    RenderCallbacks c;
    c.cancel = &lease_.cancel;
    // A job's time limit bounds all its attempts, and a first pass too.
    c.timeLimit = {.secondsBefore = priorSeconds_, .strict = true};
    c.onProgress = [this](const RenderProgress& p) { onProgress(p); };
    c.onPass = [this](const Film& film) { onPass(film); };
    return c;
}

}  // namespace caustic::server
