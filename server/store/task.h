// Scale-out on PostgreSQL: a job's passes [0, passes_total) are cut into tasks, pass ranges of
// `task_passes`, that worker processes on any machine claim and render with the job's seed.
//
// Protocol. A worker claims the queued task of the highest-priority job, oldest job first, lowest
// range first, with a lease (FOR UPDATE SKIP LOCKED: claimers never wait for each other). It
// renews the lease by heartbeats, which also carry a cancellation or the job's end, and hands in
// the task's result fenced by the task's attempt: a result whose attempt is no longer the task's
// current one changes nothing, so no pass is ever counted twice. A hand-in only stores the result
// in the task's row (its film, compactly: film/film_bytes.cpp); it never reads the job's film nor
// locks the job. Results are consolidated off the workers' path (farm/consolidator.h): one
// process at a time per job (an advisory lock) merges the results waiting, in batches, into the
// job's film exactly (film/exact_sum.h), so the merged film is bit-identical to one process's
// whatever the split and the order; previews and progress follow each batch (about one a second).
// A job with a target error merges passes in index order and checks the error after each, as one
// process does (render/target_error_merge.h), so it stops at the same pass. The batch that merges
// the last pass writes the images and ends the job. Every time (leases, time limits, liveness) is
// the database's clock, never a worker's.
//
// Faults. A lease that expires (the worker was killed, its machine or network went) puts the task
// back in the queue; a task whose leases expire `maxStalledLeases` times in a row fails the job. A
// worker whose render of a job's task fails (an exception) is blocked from that job after
// `blockAfterFailures` failures; the job fails once `failAfterWorkers` distinct workers failed it
// (a broken node must not fail everyone's jobs), or every worker alive is blocked from it (checked
// at each failure, and by each idle blocked worker's claims: the workers that were still free to
// render it may have gone since). Bad input (an InputError) fails the job at once.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/job.h"

namespace caustic::server {

/// A task as its holder knows it: every write names (jobId, firstPass, attempt).
struct Task {
    std::string jobId;
    int firstPass = 0, lastPass = 0;  ///< Passes [firstPass, lastPass).
    int attempt = 0;
};

struct ClaimedTask {
    Task task;
    Job job;
    double elapsedSeconds = 0;  ///< Since the job started, by the database's clock.
    int workersOnJob = 1;       ///< Workers holding the job's tasks, this one included.
};

/// The rules of claims and failures (store/task.h, "Faults").
struct FarmPolicy {
    double leaseSeconds = 10;
    int maxStalledLeases = 3;
    int blockAfterFailures = 2;
    int failAfterWorkers = 3;
};

/// What a worker hands in.
struct TaskResult {
    int width = 0, height = 0;  ///< The film's.
    std::string film;        ///< Film::toBytes() of the passes rendered (a job without a target).
    std::string passImages;  ///< Each pass's image (store/pass_images.h), for a target error.
    int passesDone = 0;      ///< Fewer than the range when a time limit cut it.
    uint64_t rays = 0;
    double renderSeconds = 0;
};

/// One task of a hand-in, as its worker rendered it.
struct TaskDone {
    Task task;
    int passesDone = 0;  ///< Fewer than the range when a time limit cut it.
    uint64_t rays = 0;
    double renderSeconds = 0;
};

/// What handing in did.
enum class TaskCommit {
    Fenced,    ///< Not the task's current attempt (or the job ended): nothing changed.
    Accepted,  ///< Stored, for the job's consolidation.
};

/// What a consolidation batch did.
enum class Consolidation {
    Busy,      ///< Another process consolidates the job.
    Nothing,   ///< No result could be merged (none waiting, or the job is not running).
    Merged,    ///< Results merged; the job goes on.
    More,      ///< Results merged, and more wait than one batch takes: call again.
    Finished,  ///< The job ended: its images are written (or it failed: no pass in time).
};

/// How much one consolidation batch merges: at most `results` results and, past the first,
/// stops after `seconds` of merging (a transaction that holds a job's results stays short).
struct ConsolidationLimits {
    int results = 64;
    double seconds = 5;
};

/// A worker renews its row every second or so: one not seen for this long is gone.
inline constexpr double kWorkerAliveSeconds = 30;

/// A worker process's thread as the store knows it (GET /api/workers).
struct WorkerInfo {
    std::string id;
    std::string host;
    int cores = 0, threads = 0;
    double startedAt = 0, lastSeen = 0;
    double secondsSinceSeen = 0;  ///< By the database's clock.
    std::optional<Task> current;  ///< The task it renders (attempt 0), if any.
    int64_t tasksDone = 0, tasksFailed = 0;
};

}  // namespace caustic::server
