// What a worker does with each finished pass of a job: the checkpoint, the preview (at most twice
// a second, and before the pass is recorded, so that a client told of a pass finds its preview),
// the pass in the store (progress, ETA, a convergence point), and the live progress between
// passes. Clients see the passes in the store, so a checkpoint ahead of it is recorded first.
#pragma once

#include <atomic>
#include <chrono>
#include <string>

#include "film/film.h"
#include "jobs/job_events.h"
#include "jobs/lease_keeper.h"
#include "render/render_session.h"
#include "render/settings.h"
#include "store/job_files.h"
#include "store/job_store.h"

namespace caustic::server {

/// Seconds earlier attempts of `job` rendered (from its convergence log).
double secondsRendered(const Job& job);

class PassRecorder {
public:
    /// The convergence log's seconds run on from secondsRendered(job). `passCounter` counts every
    /// recorded pass (for /metrics).
    PassRecorder(JobStore& store, const JobFiles& files, JobEvents& events, LeaseKeeper& lease,
                 const Job& job, const RenderSettings& settings, int passesTotal,
                 std::atomic<uint64_t>& passCounter);

    /// Records a checkpoint that is ahead of the store's pass count (a kill came between the
    /// two writes), so that passes_done never goes back.
    void catchUp(const Film& checkpoint);
    /// The callbacks that report a render's progress and passes.
    RenderCallbacks callbacks();

private:
    bool record(const Film& film, double seconds, double eta);
    void onProgress(const RenderProgress& p);
    void onPass(const Film& film);

    JobStore& store_;
    const JobFiles& files_;
    JobEvents& events_;
    LeaseKeeper& lease_;
    const Job& job_;
    const RenderSettings& settings_;
    int passesTotal_;
    std::atomic<uint64_t>& passCounter_;
    double priorSeconds_ = 0;
    std::chrono::steady_clock::time_point started_, lastPreview_;
};

}  // namespace caustic::server
