// Consolidation of a split job's results (store/task.h): a batch merges the results that wait
// into the job's film (film.bin between batches), writes the preview and progress, and ends the
// job once nothing is left to render. One process at a time per job: the batch's transaction
// holds an advisory lock on the job, and a process killed mid-batch rolls it back whole (nothing
// merged twice, nothing lost: the results stay until a batch's commit marks them merged).
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>

#include "film/image_io.h"
#include "render/forecast.h"
#include "render/settings.h"
#include "render/stopping.h"
#include "store/pass_images.h"
#include "store/postgres/job_store.h"
#include "store/postgres/transaction.h"

namespace caustic::server {
using postgres::dbNow;
using postgres::failJobRow;
using postgres::getJob;
using postgres::notifyJobs;
using postgres::transact;

namespace {

// The job's film of merged passes between batches (a file of the job, as the images).
constexpr const char* kMergedFilm = "film.bin";
// pg_try_advisory_xact_lock's first key for consolidations ("cons"); the second is the job's.
constexpr int32_t kConsolidationLock = 0x636f6e73;

std::optional<std::string> readFile(pqxx::work& tx, const std::string& id,
                                    const std::string& name) {
    pqxx::result r =
        tx.exec_params("SELECT data FROM job_files WHERE job_id = $1 AND name = $2", id, name);
    if (r.empty()) return std::nullopt;
    return pqxx::binarystring(r[0][0]).str();
}

void writeFile(pqxx::work& tx, const std::string& id, const std::string& name,
               const std::string& bytes) {
    tx.exec_params(
        "INSERT INTO job_files (job_id, name, data) VALUES ($1, $2, $3) ON CONFLICT (job_id, "
        "name) DO UPDATE SET data = excluded.data",
        id, name, pqxx::binarystring(bytes));
}

std::string encode(const Film& film, const char* format, double exposure) {
    return encodeImage(RgbImage{film.width(), film.height(), film.meanRgb()}, format, exposure);
}

using Clock = std::chrono::steady_clock;

// What one batch merged.
struct Batch {
    int merged = 0;
    bool reachedTarget = false;
    bool more = false;        ///< Results wait that this batch left for the next.
    std::string undecodable;  ///< A result that is no film: the job fails with this.
};

bool pastBudget(const Batch& batch, Clock::time_point start, const ConsolidationLimits& limits) {
    return batch.merged >= limits.results ||
           std::chrono::duration<double>(Clock::now() - start).count() >= limits.seconds;
}

// The result in task `firstPass`'s row is merged: that task's and those handed in with it.
void markMerged(pqxx::work& tx, const std::string& id, int firstPass) {
    tx.exec_params(
        "UPDATE tasks SET merged = TRUE, result = NULL WHERE job_id = $1 AND (first_pass = $2 OR "
        "result_task = $2)",
        id, firstPass);
}

// Reads the result in task `firstPass`'s row (nothing when it is gone).
using ReadResult = std::function<std::optional<std::string>(int firstPass)>;

// Merges the waiting films of a job without a target error, in any order (exact sums).
Batch mergeWaiting(pqxx::work& tx, const std::string& id, std::unique_ptr<Film>& film,
                   const ConsolidationLimits& limits, const ReadResult& read) {
    Batch batch;
    const auto start = Clock::now();
    // One result in memory at a time: the list first, then each result.
    for (const pqxx::row& row : tx.exec_params(
             "SELECT first_pass FROM tasks WHERE job_id = $1 AND state = 'done' AND NOT merged "
             "AND result IS NOT NULL ORDER BY first_pass",
             id)) {
        if (pastBudget(batch, start, limits)) {
            batch.more = true;
            break;
        }
        const int first = row[0].as<int>();
        const std::optional<std::string> stored = read(first);
        if (!stored) continue;
        const std::string& bytes = *stored;
        std::optional<std::pair<int, int>> size = Film::sizeOf(bytes);
        std::unique_ptr<Film> part =
            size ? Film::fromBytes(bytes, size->first, size->second) : nullptr;
        if (!part ||
            (film && (film->width() != part->width() || film->height() != part->height()))) {
            batch.undecodable =
                "the result of its task " + std::to_string(first) + " is no film of the job's";
            return batch;
        }
        if (!film) film = std::make_unique<Film>(part->width(), part->height(), part->tracksBias());
        if (film->tracksBias() != part->tracksBias()) {
            batch.undecodable = "the result of its task " + std::to_string(first) +
                                " has another film layout than the job's";
            return batch;
        }
        film->merge(*part);
        markMerged(tx, id, first);
        ++batch.merged;
    }
    return batch;
}

// Merges the waiting pass images of a job with a target error that follow the film's passes, in
// index order, checking the target after each (as one process does). A task cut short by the time
// limit leaves a gap that nothing fills: the merge stops there.
Batch mergeInOrder(pqxx::work& tx, const std::string& id, std::unique_ptr<Film>& film,
                   double targetError, const ConsolidationLimits& limits) {
    Batch batch;
    const auto start = Clock::now();
    while (true) {
        pqxx::result next = tx.exec_params(
            "SELECT first_pass, last_pass, passes_done, result FROM tasks WHERE job_id = $1 AND "
            "first_pass = $2 AND state = 'done' AND NOT merged",
            id, film ? film->passSet().end() : 0);
        if (next.empty()) return batch;
        if (pastBudget(batch, start, limits)) {
            batch.more = true;
            return batch;
        }
        const int first = next[0][0].as<int>(), last = next[0][1].as<int>();
        std::optional<PassImages> passes = readPassImages(pqxx::binarystring(next[0][3]).str());
        if (!passes ||
            (film && (film->width() != passes->width || film->height() != passes->height))) {
            batch.undecodable =
                "the pass images of its task " + std::to_string(first) + " do not decode";
            return batch;
        }
        if (!film)
            film = std::make_unique<Film>(passes->width, passes->height, passes->layers == 2);
        if (film->tracksBias() != (passes->layers == 2)) {
            batch.undecodable = "the pass images of its task " + std::to_string(first) +
                                " have another layout than the job's";
            return batch;
        }
        for (PassImage& p : passes->passes) {
            film->addPass(p.index, p.image, p.dropped);
            if (reachedTargetError(*film, targetError)) {
                batch.reachedTarget = true;
                break;
            }
        }
        markMerged(tx, id, first);
        ++batch.merged;
        if (batch.reachedTarget || next[0][2].as<int>() < last - first) return batch;
    }
}

Json finiteOrNull(double v) {
    return std::isfinite(v) ? Json(v) : Json();
}

// The stats of a finished split job, in RenderStats::toJson()'s terms where they apply.
Json farmStats(pqxx::work& tx, const Job& job, const Film& film, const RenderSettings& settings,
               StopReason reason, double now) {
    pqxx::row sums = tx.exec_params1(
        "SELECT COALESCE(SUM(rays), 0)::BIGINT, COALESCE(SUM(render_seconds), 0), COUNT(*) "
        "FROM tasks WHERE job_id = $1 AND state = 'done'",
        job.id);
    const auto rays = sums[0].as<int64_t>();
    const double renderSeconds = sums[1].as<double>();
    const double wall = std::max(0.0, now - job.startedAt);
    const double error = film.relativeError();
    return {{"render_seconds", renderSeconds},
            {"total_seconds", wall},
            {"rays", rays},
            {"rays_per_second", wall > 0 ? double(rays) / wall : 0.0},
            {"passes", film.passes()},
            {"spp", film.passes() * settings.resolvedSppPerPass()},
            {"relative_error", finiteOrNull(error)},
            {"relative_noise", finiteOrNull(film.relativeNoise())},
            {"relative_bias", finiteOrNull(film.relativeBias())},
            {"dropped_samples", film.droppedSamples()},
            {"clamped_values", film.clampedValues()},
            {"tasks", sums[2].as<int64_t>()},
            {"stop_reason", toString(reason)}};
}

// The render's forecast (render/forecast.h) from the job's convergence log and the batch just
// merged: the rest of its passes at the pace so far, the time limit, or the target error; -1
// before the first pass. A target error counts only once the merged passes are a prefix.
double etaSeconds(const Job& job, const RenderSettings& settings, const Film& film,
                  const Json& point) {
    std::vector<ProgressPoint> history = progressPoints(job.convergence);
    history.push_back(progressPoints(Json::array({point})).front());
    std::optional<StopForecast> f = forecastStop(
        history, job.passesTotal, film.passSet().isPrefix() ? settings.targetError : 0.0,
        settings.timeLimit, minPassesForTarget(film));
    return f ? f->secondsLeft : -1.0;
}

// A finished job's images, encoded before its row is locked.
struct Images {
    std::string exr, png;
};

Images encodeImages(const Film& film, const RenderSettings& settings) {
    return {encode(film, "exr", 0.0), encode(film, "png", settings.exposure)};
}

// Ends a job whose batches merged everything there is: its images, or a failure when no pass
// finished in time.
void endJob(pqxx::work& tx, const Job& job, const RenderSettings& settings, const Film* film,
            const Images& images, StopReason reason, double now) {
    tx.exec_params("DELETE FROM job_files WHERE job_id = $1 AND name = $2", job.id, kMergedFilm);
    // Results past a target or a gap are no longer wanted.
    tx.exec_params("UPDATE tasks SET result = NULL WHERE job_id = $1 AND result IS NOT NULL",
                   job.id);
    if (!film || film->passes() == 0) {
        failJobRow(tx, job.id, now,
                   "/settings/time_limit: no pass finished within the time limit of " +
                       Json(settings.timeLimit).dump() + " s");
        return;
    }
    writeFile(tx, job.id, "image.exr", images.exr);
    writeFile(tx, job.id, "image.png", images.png);
    tx.exec_params(
        "UPDATE jobs SET state = 'succeeded', finished_at = $2, stats = $3, progress = 1, "
        "eta_seconds = 0 WHERE id = $1",
        job.id, now, farmStats(tx, job, *film, settings, reason, now).dump());
}

}  // namespace

Consolidation PostgresJobStore::consolidate(const std::string& id,
                                            const ConsolidationLimits& limits) {
    return transact(*pool_, [&](pqxx::work& tx) {
        if (!tx.exec_params1("SELECT pg_try_advisory_xact_lock($1, hashtext($2))",
                             kConsolidationLock, id)[0]
                 .as<bool>())
            return Consolidation::Busy;
        std::optional<Job> job = getJob(tx, id);
        if (!job || job->state != JobState::Running) return Consolidation::Nothing;
        const RenderSettings settings = parseSettings(job->settings);
        const bool inOrder = settings.targetError > 0;
        std::unique_ptr<Film> film;
        if (std::optional<std::string> bytes = readFile(tx, id, kMergedFilm))
            if (std::optional<std::pair<int, int>> size = Film::sizeOf(*bytes))
                film = Film::fromBytes(*bytes, size->first, size->second);
        // Results are read apart, in binary: a waiting result never changes (only a batch, under
        // the lock this one holds, marks it merged).
        const ReadResult read = [&](int first) {
            return pool_->readBytes(
                "SELECT result FROM tasks WHERE job_id = $1 AND first_pass = $2::integer",
                {id, std::to_string(first)});
        };
        const Batch batch = inOrder ? mergeInOrder(tx, id, film, settings.targetError, limits)
                                    : mergeWaiting(tx, id, film, limits, read);
        const double now = dbNow(tx);
        // The job's row is written last (its lock held for the writes only, after the encoding).
        const auto paced = [&] {
            tx.exec_params("UPDATE jobs SET consolidated_at = $2 WHERE id = $1", id, now);
        };
        if (!batch.undecodable.empty()) {
            failJobRow(tx, id, now, batch.undecodable);
            notifyJobs(tx);
            return Consolidation::Finished;
        }
        const bool timeUp = settings.timeLimit > 0 && job->startedAt > 0 &&
                            now >= job->startedAt + settings.timeLimit;
        if (batch.reachedTarget || timeUp)
            // Running tasks too at the target: their heartbeats find them lost and stop.
            tx.exec_params(
                "UPDATE tasks SET state = 'dropped', lease_owner = '', result = NULL WHERE job_id "
                "= $1 AND (state = 'queued' OR (state = 'running' AND $2))",
                id, batch.reachedTarget);
        // Left: tasks to render, and (without a target) results to merge. A target error's
        // results past a gap wait for a task that renders; with none, the job ends.
        const bool left =
            batch.more ||
            tx.exec_params1(
                  "SELECT EXISTS (SELECT 1 FROM tasks WHERE job_id = $1 AND (state IN "
                  "('queued', 'running') OR (NOT $2 AND state = 'done' AND NOT "
                  "merged)))",
                  id, inOrder)[0]
                .as<bool>();
        if (batch.merged == 0 && left) {
            paced();
            return Consolidation::Nothing;
        }
        notifyJobs(tx);
        // The batch's point on the convergence log, and the progress.
        const auto recordProgress = [&] {
            if (!film || batch.merged == 0) return;
            const double error = film->relativeError();
            const Json point{{"pass", film->passes()},
                             {"seconds", now - job->startedAt},
                             {"relative_error", std::isfinite(error) ? Json(error) : Json()}};
            const double progress =
                job->passesTotal > 0 ? std::min(1.0, double(film->passes()) / job->passesTotal) : 0;
            tx.exec_params(
                "UPDATE jobs SET progress = $2, passes_done = $3, relative_error = $4, "
                "stalled_leases = 0, convergence = convergence || jsonb_build_array($5::jsonb), "
                "eta_seconds = $6, consolidated_at = $7 WHERE id = $1",
                id, progress, film->passes(), std::isfinite(error) ? error : NAN, point.dump(),
                etaSeconds(*job, settings, *film, point), now);
        };
        if (!left) {
            const StopReason reason = batch.reachedTarget ? StopReason::TargetError
                                      : timeUp            ? StopReason::TimeLimit
                                                          : StopReason::Spp;
            const Images images =
                film && film->passes() > 0 ? encodeImages(*film, settings) : Images{};
            recordProgress();
            endJob(tx, *job, settings, film.get(), images, reason, now);
        } else {
            const std::string preview = encode(*film, "png", settings.exposure);
            const std::string bytes = film->toBytes();
            writeFile(tx, id, "preview.png", preview);
            writeFile(tx, id, kMergedFilm, bytes);
            recordProgress();
        }
        if (!left) return Consolidation::Finished;
        return batch.more ? Consolidation::More : Consolidation::Merged;
    });
}

std::vector<std::string> PostgresJobStore::jobsToConsolidate(double intervalSeconds) {
    return transact(*pool_, [&](pqxx::work& tx) {
        std::vector<std::string> ids;
        for (const pqxx::row& r : tx.exec_params(
                 "SELECT j.id FROM jobs j WHERE j.state = 'running' AND j.task_passes > 0 AND "
                 "EXISTS (SELECT 1 FROM tasks t WHERE t.job_id = j.id AND t.state = 'done' AND "
                 "NOT t.merged) AND (j.consolidated_at <= $1 OR NOT EXISTS (SELECT 1 FROM tasks "
                 "t WHERE t.job_id = j.id AND t.state IN ('queued', 'running'))) ORDER BY "
                 "j.priority DESC, j.seq",
                 dbNow(tx) - intervalSeconds))
            ids.push_back(r[0].as<std::string>());
        return ids;
    });
}

}  // namespace caustic::server
