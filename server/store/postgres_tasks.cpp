// The scale-out half of the PostgreSQL store: tasks, their leases and results, the merge of
// results into the job's film, and the workers (store/task.h).
#include <cmath>
#include <memory>

#include "film/image_io.h"
#include "render/settings.h"
#include "render/stopping.h"
#include "store/pass_images.h"
#include "store/postgres_job_store.h"
#include "store/postgres_transaction.h"

namespace caustic::server {
using postgres::getJob;
using postgres::notifyJobs;
using postgres::transact;

namespace {

// The job's film of merged passes between tasks (a file of the job, as the images).
constexpr const char* kMergedFilm = "film.bin";

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

// Adds to `film` the passes of finished tasks that follow its passes, in index order, checking
// the target error after each (as one process does); true once it is reached. A task cut short
// by the time limit leaves a gap that nothing fills: the merge stops there.
bool mergeInOrder(pqxx::work& tx, const std::string& id, Film& film, double targetError) {
    const size_t pixels = size_t(film.width()) * size_t(film.height());
    while (true) {
        pqxx::result next = tx.exec_params(
            "SELECT first_pass, last_pass, passes_done, result FROM tasks WHERE job_id = $1 AND "
            "first_pass = $2 AND state = 'done' AND result IS NOT NULL",
            id, film.passSet().end());
        if (next.empty()) return false;
        const int first = next[0][0].as<int>(), last = next[0][1].as<int>();
        bool reached = false;
        for (PassImage& p : readPassImages(pqxx::binarystring(next[0][3]).str(), pixels)) {
            film.addPass(p.index, p.image, p.dropped);
            if (reachedTargetError(film, targetError)) {
                reached = true;
                break;
            }
        }
        tx.exec_params("UPDATE tasks SET result = NULL WHERE job_id = $1 AND first_pass = $2", id,
                       first);
        if (reached) return true;
        if (next[0][2].as<int>() < last - first) return false;
    }
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
            {"relative_error", std::isfinite(error) ? Json(error) : Json()},
            {"dropped_samples", film.droppedSamples()},
            {"clamped_values", film.clampedValues()},
            {"tasks", sums[2].as<int64_t>()},
            {"stop_reason", toString(reason)}};
}

// The holder of the task's current attempt renders it no more: its row in the workers list says
// so in the transaction that ends the task, not at its next heartbeat (a job that ended is never
// listed as rendered). Call before the task's row loses its lease owner.
void endHoldersTask(pqxx::work& tx, const Task& task, bool done) {
    tx.exec_params(
        "UPDATE workers SET job_id = '', first_pass = -1, last_pass = -1, tasks_done = tasks_done "
        "+ $4 WHERE id = (SELECT lease_owner FROM tasks WHERE job_id = $1 AND first_pass = $2 "
        "AND attempt = $3 AND state = 'running')",
        task.jobId, task.firstPass, task.attempt, done ? 1 : 0);
}

// Puts a task its holder gives back in the queue; false when the holder's attempt is not the
// task's current one.
bool requeueTask(pqxx::work& tx, const Task& task) {
    endHoldersTask(tx, task, /*done=*/false);
    return tx.exec_params(
                 "UPDATE tasks SET state = 'queued', lease_owner = '' WHERE job_id = $1 "
                 "AND first_pass = $2 AND attempt = $3 AND state = 'running'",
                 task.jobId, task.firstPass, task.attempt)
               .affected_rows() > 0;
}

// Fails a job that has not ended; false when it had.
bool failJobRow(pqxx::work& tx, const std::string& id, double now, const std::string& error) {
    return tx.exec_params(
                 "UPDATE jobs SET state = 'failed', finished_at = $2, error = $3 WHERE "
                 "id = $1 AND state IN ('queued', 'running')",
                 id, now, error)
               .affected_rows() > 0;
}

// The render's forecast (render/forecast.h) from the job's convergence log and the pass just
// merged: the rest of its passes at the pace so far, the time limit, or the target error; -1
// before the first pass. A target error counts only once the merged passes are a prefix.
double etaSeconds(const Job& job, const RenderSettings& settings, const Film& film,
                  const Json& point) {
    std::vector<ProgressPoint> history = progressPoints(job.convergence);
    history.push_back(progressPoints(Json::array({point})).front());
    std::optional<StopForecast> f =
        forecastStop(history, job.passesTotal,
                     film.passSet().isPrefix() ? settings.targetError : 0.0, settings.timeLimit);
    return f ? f->secondsLeft : -1.0;
}

// Ends a cancelled split job once no task renders it any more.
void endCancelledJobs(pqxx::work& tx, double now) {
    tx.exec_params(
        "UPDATE jobs SET state = 'cancelled', finished_at = $1, error = 'cancelled' WHERE state "
        "= 'running' AND cancel_requested AND task_passes > 0 AND NOT EXISTS (SELECT 1 FROM "
        "tasks WHERE tasks.job_id = jobs.id AND tasks.state = 'running')",
        now);
}

// Fails job `id` once the workers blocked from it (store/task.h, "Faults") are
// `failAfterWorkers`, or every worker alive; `error` is the last failure's. False when it goes on.
bool failIfBlocked(pqxx::work& tx, const std::string& id, double now, const FarmPolicy& policy,
                   const std::string& error) {
    pqxx::row counts = tx.exec_params1(
        "SELECT (SELECT COUNT(*) FROM task_failures WHERE job_id = $1 AND failures >= $2), "
        "(SELECT COUNT(*) FROM workers WHERE last_seen >= $3)",
        id, policy.blockAfterFailures, now - kWorkerAliveSeconds);
    const int blocked = counts[0].as<int>();
    const int alive = std::max(1, counts[1].as<int>());
    return blocked >= std::min(policy.failAfterWorkers, alive) &&
           failJobRow(
               tx, id, now,
               "its tasks failed on " + std::to_string(blocked) + " workers; the last: " + error);
}

}  // namespace

std::optional<ClaimedTask> PostgresJobStore::claimTask(const std::string& worker, double now,
                                                       const FarmPolicy& policy) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) -> std::optional<ClaimedTask> {
        // Expired leases: the task goes back to the queue; a job one of whose tasks stalled too
        // often fails. Rows others hold are skipped: they settle them, or the next claim does.
        pqxx::result stalled = tx.exec_params(
            "UPDATE tasks SET state = 'queued', lease_owner = '', stalled_leases = "
            "stalled_leases + 1 WHERE (job_id, first_pass) IN (SELECT job_id, first_pass FROM "
            "tasks WHERE state = 'running' AND lease_expires <= $1 FOR UPDATE SKIP LOCKED) "
            "RETURNING job_id, stalled_leases",
            now);
        for (const pqxx::row& r : stalled)
            if (r[1].as<int>() >= policy.maxStalledLeases)
                failJobRow(tx, r[0].as<std::string>(), now,
                           "a task of it stopped " + std::to_string(r[1].as<int>()) +
                               " times in a row before it finished (its workers' leases "
                               "expired); it is not retried again");
        if (!stalled.empty()) {
            endCancelledJobs(tx, now);
            notifyJobs(tx);
        }
        pqxx::result pick = tx.exec_params(
            "SELECT t.job_id, t.first_pass FROM tasks t JOIN jobs j ON j.id = t.job_id WHERE "
            "t.state = 'queued' AND j.state IN ('queued', 'running') AND NOT j.cancel_requested "
            "AND NOT EXISTS (SELECT 1 FROM task_failures f WHERE f.job_id = t.job_id AND "
            "f.worker_id = $1 AND f.failures >= $2) ORDER BY j.priority DESC, j.seq, "
            "t.first_pass LIMIT 1 FOR UPDATE OF t SKIP LOCKED",
            worker, policy.blockAfterFailures);
        if (pick.empty()) {
            // Idle: a job this worker is blocked from fails once every worker alive is (those
            // free to render it when the last failure was counted may have gone since).
            bool failed = false;
            for (const pqxx::row& r : tx.exec_params(
                     "SELECT f.job_id, f.last_error FROM task_failures f JOIN jobs j ON j.id = "
                     "f.job_id WHERE f.worker_id = $1 AND f.failures >= $2 AND j.state IN "
                     "('queued', 'running') ORDER BY f.job_id FOR UPDATE OF j",
                     worker, policy.blockAfterFailures))
                failed |=
                    failIfBlocked(tx, r[0].as<std::string>(), now, policy, r[1].as<std::string>());
            if (failed) {
                endCancelledJobs(tx, now);
                notifyJobs(tx);
            }
            return std::nullopt;
        }
        ClaimedTask claimed;
        Task& task = claimed.task;
        task.jobId = pick[0][0].as<std::string>();
        task.firstPass = pick[0][1].as<int>();
        pqxx::row r = tx.exec_params1(
            "UPDATE tasks SET state = 'running', attempt = attempt + 1, lease_owner = $3, "
            "lease_expires = $4 WHERE job_id = $1 AND first_pass = $2 RETURNING last_pass, "
            "attempt",
            task.jobId, task.firstPass, worker, now + policy.leaseSeconds);
        task.lastPass = r[0].as<int>();
        task.attempt = r[1].as<int>();
        if (tx.exec_params("UPDATE jobs SET state = 'running', started_at = CASE WHEN started_at "
                           "= 0 THEN $2 ELSE started_at END, eta_seconds = -1 WHERE id = $1 AND "
                           "state = 'queued'",
                           task.jobId, now)
                .affected_rows() > 0)
            notifyJobs(tx);
        std::optional<Job> job = getJob(tx, task.jobId);
        if (!job) return std::nullopt;
        claimed.job = std::move(*job);
        return claimed;
    });
}

LeaseStatus PostgresJobStore::heartbeatTask(const Task& task, double now, double leaseSeconds) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) {
        pqxx::result r = tx.exec_params(
            "UPDATE tasks SET lease_expires = $4 WHERE job_id = $1 AND first_pass = $2 AND "
            "attempt = $3 AND state = 'running' RETURNING (SELECT cancel_requested FROM jobs "
            "WHERE id = $1)",
            task.jobId, task.firstPass, task.attempt, now + leaseSeconds);
        if (r.empty()) return LeaseStatus::Lost;
        // The holder is alive (GET /api/workers).
        tx.exec_params(
            "UPDATE workers SET last_seen = $3 WHERE id = (SELECT lease_owner FROM tasks WHERE "
            "job_id = $1 AND first_pass = $2)",
            task.jobId, task.firstPass, now);
        return r[0][0].as<bool>() ? LeaseStatus::CancelRequested : LeaseStatus::Held;
    });
}

TaskCommit PostgresJobStore::completeTask(const Task& task, const TaskResult& result, double now) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) {
        // The job's row lock serializes the merges of one job's results.
        std::optional<Job> job = getJob(tx, task.jobId, /*lock=*/true);
        if (!job || job->state != JobState::Running) return TaskCommit::Fenced;
        const RenderSettings settings = parseSettings(job->settings);
        const bool inOrder = settings.targetError > 0;
        endHoldersTask(tx, task, /*done=*/true);
        pqxx::binarystring images(result.passImages);
        if (tx.exec_params("UPDATE tasks SET state = 'done', lease_owner = '', passes_done = $4, "
                           "rays = $5, render_seconds = $6, result = CASE WHEN $7::boolean THEN "
                           "$8::bytea ELSE NULL END WHERE job_id = $1 AND first_pass = $2 AND "
                           "attempt = $3 AND "
                           "state = 'running'",
                           task.jobId, task.firstPass, task.attempt, result.passesDone,
                           int64_t(result.rays), result.renderSeconds, inOrder, images)
                .affected_rows() == 0)
            return TaskCommit::Fenced;

        std::unique_ptr<Film> film;
        if (std::optional<std::string> bytes = readFile(tx, job->id, kMergedFilm))
            film = Film::fromBytes(*bytes, result.width, result.height);
        if (!film) film = std::make_unique<Film>(result.width, result.height);
        bool reachedTarget = false;
        if (inOrder) {
            reachedTarget = mergeInOrder(tx, job->id, *film, settings.targetError);
        } else if (std::unique_ptr<Film> part =
                       Film::fromBytes(result.film, result.width, result.height)) {
            film->merge(*part);
        } else {
            throw std::runtime_error("a task's film of job " + job->id + " does not decode");
        }
        const bool timeUp = settings.timeLimit > 0 && job->startedAt > 0 &&
                            now >= job->startedAt + settings.timeLimit;
        if (reachedTarget || timeUp)
            // Running tasks too at the target: their heartbeats find them lost and stop.
            tx.exec_params(
                "UPDATE tasks SET state = 'dropped', lease_owner = '', result = NULL WHERE job_id "
                "= $1 AND (state = 'queued' OR (state = 'running' AND $2))",
                job->id, reachedTarget);
        const int left = tx.exec_params1(
                               "SELECT COUNT(*) FROM tasks WHERE job_id = $1 AND state "
                               "IN ('queued', 'running')",
                               job->id)[0]
                             .as<int>();
        const double error = film->relativeError();
        const Json point{{"pass", film->passes()},
                         {"seconds", now - job->startedAt},
                         {"relative_error", std::isfinite(error) ? Json(error) : Json()}};
        const std::string preview = encode(*film, "png", settings.exposure);
        writeFile(tx, job->id, "preview.png", preview);
        const double progress =
            job->passesTotal > 0 ? std::min(1.0, double(film->passes()) / job->passesTotal) : 0;
        tx.exec_params(
            "UPDATE jobs SET progress = $2, passes_done = $3, relative_error = $4, stalled_leases "
            "= 0, convergence = convergence || jsonb_build_array($5::jsonb), eta_seconds = $6 "
            "WHERE id = $1",
            job->id, progress, film->passes(), std::isfinite(error) ? error : NAN, point.dump(),
            etaSeconds(*job, settings, *film, point));
        notifyJobs(tx);
        if (left > 0) {
            writeFile(tx, job->id, kMergedFilm, film->toBytes());
            // A job cancelled while this task rendered ends once none renders it.
            endCancelledJobs(tx, now);
            return TaskCommit::Merged;
        }
        // Nothing left to render: the job ends with what is merged.
        tx.exec_params("DELETE FROM job_files WHERE job_id = $1 AND name = $2", job->id,
                       kMergedFilm);
        if (film->passes() == 0) {
            failJobRow(tx, job->id, now,
                       "/settings/time_limit: no pass finished within the time limit of " +
                           Json(settings.timeLimit).dump() + " s");
            return TaskCommit::Finished;
        }
        writeFile(tx, job->id, "image.exr", encode(*film, "exr", 0.0));
        writeFile(tx, job->id, "image.png", preview);
        const StopReason reason = reachedTarget ? StopReason::TargetError
                                  : timeUp      ? StopReason::TimeLimit
                                                : StopReason::Spp;
        tx.exec_params(
            "UPDATE jobs SET state = 'succeeded', finished_at = $2, stats = $3, progress = 1, "
            "eta_seconds = 0 WHERE id = $1",
            job->id, now, farmStats(tx, *job, *film, settings, reason, now).dump());
        return TaskCommit::Finished;
    });
}

void PostgresJobStore::releaseTask(const Task& task, double now) {
    transact(*connection_, mutex_, [&](pqxx::work& tx) {
        requeueTask(tx, task);
        endCancelledJobs(tx, now);
        notifyJobs(tx);
        return 0;
    });
}

bool PostgresJobStore::failTask(const Task& task, const std::string& worker,
                                const std::string& error, double now, const FarmPolicy& policy) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) {
        // The job's row lock serializes the failures of its tasks: two counted at once would
        // each miss the other's block, and the job would wait for workers it has none of.
        tx.exec_params("SELECT 1 FROM jobs WHERE id = $1 FOR UPDATE", task.jobId);
        if (!requeueTask(tx, task)) return false;
        tx.exec_params("UPDATE workers SET tasks_failed = tasks_failed + 1 WHERE id = $1", worker);
        tx.exec_params(
            "INSERT INTO task_failures (job_id, worker_id, failures, last_error) VALUES ($1, $2, "
            "1, $3) ON CONFLICT (job_id, worker_id) DO UPDATE SET failures = "
            "task_failures.failures + 1, last_error = excluded.last_error",
            task.jobId, worker, error);
        const bool failed = failIfBlocked(tx, task.jobId, now, policy, error);
        endCancelledJobs(tx, now);
        notifyJobs(tx);
        return failed;
    });
}

bool PostgresJobStore::failJob(const Task& task, const std::string& error, double now) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) {
        if (!requeueTask(tx, task)) return false;
        notifyJobs(tx);
        return failJobRow(tx, task.jobId, now, error);
    });
}

std::optional<Job> PostgresJobStore::requeue(const std::string& id) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) -> std::optional<Job> {
        // Its time limit counts again from the next claim (started_at 0): counted from the
        // first start, a limit that passed while the job waited would end it after one task.
        if (tx.exec_params("UPDATE jobs SET state = 'queued', error = '', finished_at = 0, "
                           "started_at = 0, cancel_requested = FALSE, stalled_leases = 0, "
                           "eta_seconds = -1 WHERE id = $1 AND state IN ('failed', 'cancelled') "
                           "AND task_passes > 0",
                           id)
                .affected_rows() > 0) {
            tx.exec_params(
                "UPDATE tasks SET state = 'queued', lease_owner = '', stalled_leases = 0 WHERE "
                "job_id = $1 AND state <> 'done'",
                id);
            tx.exec_params("DELETE FROM task_failures WHERE job_id = $1", id);
            notifyJobs(tx);
        }
        return getJob(tx, id);
    });
}

void PostgresJobStore::workerSeen(const WorkerInfo& w) {
    transact(*connection_, mutex_, [&](pqxx::work& tx) {
        const Task none{"", -1, -1, 0};
        const Task& t = w.current ? *w.current : none;
        tx.exec_params(
            "INSERT INTO workers (id, host, cores, threads, started_at, last_seen, job_id, "
            "first_pass, last_pass) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9) ON CONFLICT (id) "
            "DO UPDATE SET last_seen = excluded.last_seen, job_id = excluded.job_id, first_pass "
            "= excluded.first_pass, last_pass = excluded.last_pass",
            w.id, w.host, w.cores, w.threads, w.startedAt, w.lastSeen, t.jobId, t.firstPass,
            t.lastPass);
        // Rows of workers killed without a goodbye go after a day.
        tx.exec_params("DELETE FROM workers WHERE last_seen < $1", w.lastSeen - 86400);
        return 0;
    });
}

void PostgresJobStore::workerGone(const std::string& id) {
    transact(*connection_, mutex_, [&](pqxx::work& tx) {
        tx.exec_params("DELETE FROM workers WHERE id = $1", id);
        return 0;
    });
}

std::vector<WorkerInfo> PostgresJobStore::listWorkers(double seenSince) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) {
        std::vector<WorkerInfo> workers;
        for (const pqxx::row& r : tx.exec_params(
                 "SELECT id, host, cores, threads, started_at, last_seen, job_id, first_pass, "
                 "last_pass, tasks_done, tasks_failed FROM workers WHERE last_seen >= $1 ORDER "
                 "BY id",
                 seenSince)) {
            WorkerInfo w;
            w.id = r[0].as<std::string>();
            w.host = r[1].as<std::string>();
            w.cores = r[2].as<int>();
            w.threads = r[3].as<int>();
            w.startedAt = r[4].as<double>();
            w.lastSeen = r[5].as<double>();
            if (!r[6].as<std::string>().empty())
                w.current = Task{r[6].as<std::string>(), r[7].as<int>(), r[8].as<int>(), 0};
            w.tasksDone = r[9].as<int64_t>();
            w.tasksFailed = r[10].as<int64_t>();
            workers.push_back(std::move(w));
        }
        return workers;
    });
}

int64_t PostgresJobStore::queuedTasks(double now) {
    return transact(*connection_, mutex_, [&](pqxx::work& tx) {
        return tx
            .exec_params1(
                "SELECT COUNT(*) FROM tasks t JOIN jobs j ON j.id = t.job_id WHERE (t.state = "
                "'queued' OR (t.state = 'running' AND t.lease_expires <= $1)) AND j.state IN "
                "('queued', 'running') AND NOT j.cancel_requested",
                now)[0]
            .as<int64_t>();
    });
}

}  // namespace caustic::server
