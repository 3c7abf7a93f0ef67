// A render job as the service stores it: what was asked (scene and settings), where it is in its
// life (state, lease), and what it has produced so far (progress, convergence log, stats).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/forecast.h"

namespace caustic::server {

using Json = nlohmann::json;

/// queued -> running -> succeeded | failed | cancelled; running -> queued when a lease expires.
enum class JobState { Queued, Running, Succeeded, Failed, Cancelled };

std::string toString(JobState s);
std::optional<JobState> parseJobState(std::string_view s);
inline bool isTerminal(JobState s) {
    return s == JobState::Succeeded || s == JobState::Failed || s == JobState::Cancelled;
}

/// A job's convergence log as the render forecast reads it (render/forecast.h).
inline std::vector<ProgressPoint> progressPoints(const Json& convergence) {
    std::vector<ProgressPoint> points;
    for (const Json& p : convergence)
        if (p.is_object() && p.contains("pass") && p.contains("seconds"))
            points.push_back({p["pass"].get<int>(), p["seconds"].get<double>(),
                              p.value("relative_error", Json()).is_number()
                                  ? p["relative_error"].get<double>()
                                  : std::nan("")});
    return points;
}

struct Job {
    std::string id;
    int64_t seq = 0;  ///< Submission order, assigned by the store.
    JobState state = JobState::Queued;
    Json scene;     ///< The scene object to render (an example name is resolved at submission).
    Json settings;  ///< The complete, validated settings.
    std::string sceneName;            ///< The example scene's name when one was asked for by name.
    std::vector<std::string> assets;  ///< Distinct asset ids its scene names; read back by get().
    /// What its preset chose for the scene and why (render/presets.h presetChoice); null if none.
    Json presetChoice;
    double createdAt = 0, startedAt = 0, finishedAt = 0;  ///< Unix seconds; 0 for not yet.

    // The lease protocol (store/job_store.h).
    int attempt = 0;  ///< Leases granted so far; every write of a lease holder names it.
    std::string leaseOwner;
    double leaseExpires = 0;
    int stalledLeases = 0;  ///< Leases in a row that expired before their holder finished a pass.
    bool cancelRequested = false;
    // Scale-out (PostgreSQL, store/task.h): a job's passes are cut into tasks of `taskPasses`,
    // claimed by higher `priority` first, then in submission order.
    int priority = 0;
    int taskPasses = 0;  ///< Passes per task; 0 where jobs are not split (SQLite).

    // Progress of the current (or last) attempt, and the result.
    double progress = 0;  ///< Of the spp budget, in [0, 1].
    int passesDone = 0, passesTotal = 0;
    double relativeError = 0;          ///< NaN before two passes.
    double etaSeconds = -1;            ///< -1 while unknown.
    Json convergence = Json::array();  ///< [{pass, seconds, relative_error}], one per pass.
    Json stats;                        ///< RenderStats::toJson() of the finished render.
    std::string error;                 ///< Why it failed or was cancelled.
};

}  // namespace caustic::server
