// The scale-out half of the PostgreSQL store: tasks, their leases and hand-ins, and the workers
// (store/task.h). The consolidation of results: store/postgres/consolidation.cpp.
#include "store/postgres/job_store.h"
#include "store/postgres/transaction.h"

namespace caustic::server {
namespace postgres {

double dbNow(pqxx::work& tx) {
    return tx.exec1(std::string("SELECT ") + kNow)[0].as<double>();
}

bool failJobRow(pqxx::work& tx, const std::string& id, double now, const std::string& error) {
    return tx.exec_params(
                 "UPDATE jobs SET state = 'failed', finished_at = $2, error = $3 WHERE "
                 "id = $1 AND state IN ('queued', 'running')",
                 id, now, error)
               .affected_rows() > 0;
}

// A job with nothing left to render is not: its consolidation ends it, succeeded.
bool endCancelledJobs(pqxx::work& tx, double now) {
    return tx.exec_params(
                 "UPDATE jobs SET state = 'cancelled', finished_at = $1, error = 'cancelled' "
                 "WHERE state = 'running' AND cancel_requested AND task_passes > 0 AND NOT "
                 "EXISTS (SELECT 1 FROM tasks WHERE tasks.job_id = jobs.id AND tasks.state = "
                 "'running') AND EXISTS (SELECT 1 FROM tasks WHERE tasks.job_id = jobs.id AND "
                 "tasks.state = 'queued')",
                 now)
               .affected_rows() > 0;
}

}  // namespace postgres

using postgres::dbNow;
using postgres::endCancelledJobs;
using postgres::failJobRow;
using postgres::getJob;
using postgres::notifyJobs;
using postgres::transact;

namespace {

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

// A PostgreSQL integer array literal ("{1,2,3}") of field(item) for each item (not empty).
template <class T, class F>
std::string arrayOf(const std::vector<T>& items, F field) {
    std::string out = "{";
    for (const T& item : items) out += std::to_string(field(item)) + ",";
    out.back() = '}';
    return out;
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

std::optional<ClaimedTask> PostgresJobStore::claimTask(const std::string& worker,
                                                       const FarmPolicy& policy,
                                                       const std::string& prefer) {
    return transact(*pool_, [&](pqxx::work& tx) -> std::optional<ClaimedTask> {
        const double now = dbNow(tx);
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
            "f.worker_id = $1 AND f.failures >= $2) ORDER BY j.priority DESC, t.job_id = $3 "
            "DESC, j.seq, t.first_pass LIMIT 1 FOR UPDATE OF t SKIP LOCKED",
            worker, policy.blockAfterFailures, prefer);
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
        claimed.elapsedSeconds = std::max(0.0, now - claimed.job.startedAt);
        claimed.workersOnJob = std::max(
            1, tx.exec_params1("SELECT COUNT(DISTINCT lease_owner) FROM tasks WHERE job_id = $1 "
                               "AND state = 'running'",
                               task.jobId)[0]
                   .as<int>());
        return claimed;
    });
}

LeaseStatus PostgresJobStore::heartbeatTasks(const std::vector<Task>& tasks, double leaseSeconds) {
    return transact(*pool_, [&](pqxx::work& tx) {
        const double now = dbNow(tx);
        if (tasks.empty()) return LeaseStatus::Held;
        // One statement for every task held (of one job): a row a task, each fenced by attempt.
        const std::string firsts = arrayOf(tasks, [](const Task& t) { return t.firstPass; });
        const std::string attempts = arrayOf(tasks, [](const Task& t) { return t.attempt; });
        // Rows a hand-in of this worker's holds are skipped, not waited for (it locks them all
        // first): neither waits for the other, and a claim's sweep skips them too.
        const pqxx::result r = tx.exec_params(
            "WITH held AS (SELECT t.first_pass FROM tasks t JOIN unnest($2::integer[], "
            "$3::integer[]) AS h(first_pass, attempt) ON t.first_pass = h.first_pass AND "
            "t.attempt = h.attempt WHERE t.job_id = $1 AND t.state = 'running' FOR UPDATE OF t "
            "SKIP LOCKED) UPDATE tasks SET lease_expires = $4 FROM held WHERE tasks.job_id = $1 "
            "AND tasks.first_pass = held.first_pass RETURNING tasks.first_pass",
            tasks.front().jobId, firsts, attempts, now + leaseSeconds);
        // Another attempt has one of them: stop. (One skipped is being handed in: still held.)
        if (r.size() != tasks.size() &&
            tx.exec_params1("SELECT COUNT(*) FROM tasks t JOIN unnest($2::integer[], "
                            "$3::integer[]) AS h(first_pass, attempt) ON t.first_pass = "
                            "h.first_pass AND t.attempt = h.attempt WHERE t.job_id = $1 AND "
                            "t.state IN ('running', 'done')",
                            tasks.front().jobId, firsts, attempts)[0]
                    .as<size_t>() != tasks.size())
            return LeaseStatus::Lost;
        // The job ended (failed, cancelled, done): stop.
        const pqxx::row job = tx.exec_params1(
            "SELECT state, cancel_requested FROM jobs WHERE id = $1", tasks.front().jobId);
        if (job[0].as<std::string>() != "running") return LeaseStatus::Lost;
        const bool cancelRequested = job[1].as<bool>();
        // The holder is alive (GET /api/workers).
        tx.exec_params(
            "UPDATE workers SET last_seen = $3 WHERE id = (SELECT lease_owner FROM tasks "
            "WHERE job_id = $1 AND first_pass = $2)",
            tasks.front().jobId, tasks.front().firstPass, now);
        return cancelRequested ? LeaseStatus::CancelRequested : LeaseStatus::Held;
    });
}

namespace {

// Thrown inside a hand-in's transaction to roll it back: one of its tasks was fenced.
struct Fenced {};

}  // namespace

TaskCommit PostgresJobStore::completeTasks(const std::vector<TaskDone>& tasks,
                                           const std::string& result) {
    if (tasks.empty()) return TaskCommit::Fenced;
    // Made outside the transaction: it holds no lock while the bytes are copied.
    const pqxx::binarystring stored(result);
    const Task& holder = tasks.front().task;
    try {
        return transact(*pool_, [&](pqxx::work& tx) {
            // Every row first, in one statement and in order: a heartbeat skips them from here
            // on, and no two transactions take them in different orders.
            const std::string firsts =
                arrayOf(tasks, [](const TaskDone& d) { return d.task.firstPass; });
            tx.exec_params(
                "SELECT 1 FROM tasks WHERE job_id = $1 AND first_pass = ANY($2::integer[]) ORDER "
                "BY first_pass FOR UPDATE",
                holder.jobId, firsts);
            for (const TaskDone& done : tasks) {
                const Task& t = done.task;
                endHoldersTask(tx, t, /*done=*/true);
                // The result in the first task's row; the others point at it.
                const char* update =
                    "UPDATE tasks SET state = 'done', lease_owner = '', passes_done = $4, rays = "
                    "$5, render_seconds = $6, result = $7, result_task = $8, merged = FALSE "
                    "WHERE job_id = $1 AND first_pass = $2 AND attempt = $3 AND state = "
                    "'running' AND EXISTS (SELECT 1 FROM jobs WHERE id = $1 AND state = "
                    "'running')";
                const bool first = &done == &tasks.front();
                const pqxx::result r =
                    first ? tx.exec_params(update, t.jobId, t.firstPass, t.attempt, done.passesDone,
                                           int64_t(done.rays), done.renderSeconds, stored, nullptr)
                          : tx.exec_params(update, t.jobId, t.firstPass, t.attempt, done.passesDone,
                                           int64_t(done.rays), done.renderSeconds, nullptr,
                                           holder.firstPass);
                if (r.affected_rows() == 0) throw Fenced{};
            }
            // A job cancelled while these tasks rendered ends once none renders it (their result
            // stays, for a re-queue).
            if (endCancelledJobs(tx, dbNow(tx))) notifyJobs(tx);
            return TaskCommit::Accepted;
        });
    } catch (const Fenced&) {
        return TaskCommit::Fenced;  // rolled back: none of them is handed in
    }
}

void PostgresJobStore::releaseTasks(const std::vector<Task>& tasks) {
    transact(*pool_, [&](pqxx::work& tx) {
        for (const Task& task : tasks) requeueTask(tx, task);
        endCancelledJobs(tx, dbNow(tx));
        notifyJobs(tx);
        return 0;
    });
}

bool PostgresJobStore::failTask(const Task& task, const std::string& worker,
                                const std::string& error, const FarmPolicy& policy) {
    return transact(*pool_, [&](pqxx::work& tx) {
        const double now = dbNow(tx);
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

bool PostgresJobStore::failJob(const Task& task, const std::string& error) {
    return transact(*pool_, [&](pqxx::work& tx) {
        if (!requeueTask(tx, task)) return false;
        notifyJobs(tx);
        return failJobRow(tx, task.jobId, dbNow(tx), error);
    });
}

std::optional<Job> PostgresJobStore::requeue(const std::string& id) {
    return transact(*pool_, [&](pqxx::work& tx) -> std::optional<Job> {
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
            // Nothing left to render (every task was handed in before it ended): no claim will
            // start it, its consolidation ends it.
            tx.exec_params(
                "UPDATE jobs SET state = 'running', started_at = $2 WHERE id = $1 AND NOT EXISTS "
                "(SELECT 1 FROM tasks WHERE job_id = $1 AND state <> 'done')",
                id, dbNow(tx));
            notifyJobs(tx);
        }
        return getJob(tx, id);
    });
}

void PostgresJobStore::workerSeen(const WorkerInfo& w) {
    transact(*pool_, [&](pqxx::work& tx) {
        const double now = dbNow(tx);
        const Task none{"", -1, -1, 0};
        const Task& t = w.current ? *w.current : none;
        tx.exec_params(
            "INSERT INTO workers (id, host, cores, threads, started_at, last_seen, job_id, "
            "first_pass, last_pass) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9) ON CONFLICT (id) "
            "DO UPDATE SET last_seen = excluded.last_seen, job_id = excluded.job_id, first_pass "
            "= excluded.first_pass, last_pass = excluded.last_pass",
            w.id, w.host, w.cores, w.threads, w.startedAt, now, t.jobId, t.firstPass, t.lastPass);
        // Rows of workers killed without a goodbye go after a day.
        tx.exec_params("DELETE FROM workers WHERE last_seen < $1", now - 86400);
        return 0;
    });
}

void PostgresJobStore::workerGone(const std::string& id) {
    transact(*pool_, [&](pqxx::work& tx) {
        tx.exec_params("DELETE FROM workers WHERE id = $1", id);
        return 0;
    });
}

std::vector<WorkerInfo> PostgresJobStore::listWorkers(double aliveSeconds) {
    return transact(*pool_, [&](pqxx::work& tx) {
        const double now = dbNow(tx);
        std::vector<WorkerInfo> workers;
        for (const pqxx::row& r : tx.exec_params(
                 "SELECT id, host, cores, threads, started_at, last_seen, job_id, first_pass, "
                 "last_pass, tasks_done, tasks_failed FROM workers WHERE last_seen >= $1 ORDER "
                 "BY id",
                 now - aliveSeconds)) {
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
            w.secondsSinceSeen = std::max(0.0, now - w.lastSeen);
            workers.push_back(std::move(w));
        }
        return workers;
    });
}

int64_t PostgresJobStore::queuedTasks() {
    return transact(*pool_, [&](pqxx::work& tx) {
        const double now = dbNow(tx);
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
