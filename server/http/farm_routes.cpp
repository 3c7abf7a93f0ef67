// Scale-out routes (store/task.h): GET /api/workers lists the worker processes' threads that a
// shared store has seen lately, with the task each renders; POST /api/jobs/{id}/requeue puts a
// failed or cancelled split job back in the queue with the passes it has.
#include "http/job_json.h"
#include "http/problem.h"
#include "http/routes.h"

namespace caustic::server {
namespace {

Json workerJson(const WorkerInfo& w) {
    Json task = nullptr;
    if (w.current)
        task = {{"job", w.current->jobId},
                {"first_pass", w.current->firstPass},
                {"last_pass", w.current->lastPass}};
    return {{"id", w.id},
            {"host", w.host},
            {"cores", w.cores},
            {"threads", w.threads},
            {"started_at", w.startedAt},
            {"last_heartbeat", w.lastSeen},
            {"seconds_since_heartbeat", w.secondsSinceSeen},
            {"task", task},
            {"tasks_done", w.tasksDone},
            {"tasks_failed", w.tasksFailed}};
}

}  // namespace

void registerFarmRoutes(httplib::Server& http, ApiContext& api) {
    using Req = const httplib::Request&;
    using Res = httplib::Response&;
    http.Get("/api/workers", [&api](Req, Res res) {
        Json workers = Json::array();
        if (api.farm)
            for (const WorkerInfo& w : api.farm->listWorkers(kWorkerAliveSeconds))
                workers.push_back(workerJson(w));
        sendJson(res, 200, {{"store", api.farm ? "postgresql" : "sqlite"}, {"workers", workers}});
    });
    http.Post("/api/jobs/([0-9a-f]{32})/requeue", [&api](Req req, Res res) {
        const std::string id = req.matches[1];
        if (!api.farm)
            return sendProblem(res, 409,
                               "re-queueing a job needs the PostgreSQL store (serve --store "
                               "postgresql://...); submit the job again");
        std::optional<Job> job = api.farm->requeue(id);
        if (!job) return sendProblem(res, 404, "no job " + id);
        if (job->state != JobState::Queued)
            return sendProblem(res, 409,
                               "job " + id + " is " + toString(job->state) +
                                   ": only a failed or cancelled job is re-queued");
        api.jobs.notifyQueued();
        sendJson(res, 202, jobJson(*job, std::nullopt));
    });
}

}  // namespace caustic::server
