// The jobs resource: POST /api/jobs, GET /api/jobs[/{id}[/events|/image.png|...]], cancel, DELETE.
#include <fstream>
#include <string>

#include "http/job_json.h"
#include "http/problem.h"
#include "http/routes.h"

namespace caustic::server {
namespace {

constexpr const char* kIdPattern = "([0-9a-f]{32})";

struct TooDeep {};

// Parses a request body, refusing nesting deeper than `maxDepth` before it costs anything.
// Answers 400 and returns nothing when the body is not JSON.
std::optional<Json> parseBody(const std::string& text, int maxDepth, httplib::Response& res) {
    // nlohmann::json takes a NUL byte for the end of its input, so whatever followed one would
    // pass unread; JSON text has none (RFC 8259).
    if (size_t nul = text.find('\0'); nul != std::string::npos) {
        sendProblem(res, 400, "malformed JSON: a NUL byte at offset " + std::to_string(nul));
        return std::nullopt;
    }
    try {
        return Json::parse(text, [maxDepth](int depth, Json::parse_event_t, Json&) {
            if (depth > maxDepth) throw TooDeep{};
            return true;
        });
    } catch (const TooDeep&) {
        sendProblem(res, 400, "JSON nested deeper than " + std::to_string(maxDepth) + " levels");
    } catch (const Json::exception& e) {
        sendProblem(res, 400, std::string("malformed JSON: ") + e.what());
    }
    return std::nullopt;
}

void sendSubmission(httplib::Response& res, const Submission& s) {
    using Outcome = Submission::Outcome;
    switch (s.outcome) {
        case Outcome::Accepted:
        case Outcome::Replayed:
            res.status = s.response.status;
            res.set_header("Location", "/api/jobs/" + s.response.jobId);
            res.set_content(s.response.body, "application/json");
            return;
        case Outcome::KeyReused:
            return sendProblem(res, 409, s.detail);
        case Outcome::BadKey:
            return sendProblem(res, 400, s.detail);
        case Outcome::QueueFull:
            res.set_header("Retry-After", "30");
            return sendProblem(res, 429, s.detail);
        case Outcome::Invalid:
            return sendProblem(res, 422, s.detail, s.pointer);
        case Outcome::DiskFull:
            return sendProblem(res, 507, s.detail);
    }
}

void submitJob(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    const std::string key = req.get_header_value("Idempotency-Key");
    if (std::optional<Submission> earlier = api.jobs.replay(key, req.body))
        return sendSubmission(res, *earlier);
    std::optional<Json> body = parseBody(req.body, api.config.limits.maxJsonDepth, res);
    if (!body) return;
    sendSubmission(res, api.jobs.submit(*body, req.body, key, [](const Job& job) {
        return jobJson(job, std::nullopt).dump();
    }));
}

void listJobs(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<JobState> state;
    if (req.has_param("state")) {
        state = parseJobState(req.get_param_value("state"));
        if (!state)
            return sendProblem(res, 400,
                               "state must be queued, running, succeeded, failed or cancelled");
    }
    std::optional<int64_t> limit = integerParam(req, res, "limit", 1, 100, 20);
    if (!limit) return;
    std::optional<int64_t> cursor = integerParam(req, res, "cursor", 1, INT64_MAX, INT64_MAX);
    if (!cursor) return;
    JobPage page = api.jobs.list(state, int(*limit), *cursor);
    Json jobs = Json::array();
    for (const Job& j : page.jobs) {
        Json item = jobJson(j, api.jobs.live(j.id));
        item.erase("convergence");  // the list stays small; the job resource has it
        jobs.push_back(std::move(item));
    }
    Json body{{"jobs", jobs}, {"next_cursor", page.next ? Json(*page.next) : Json(nullptr)}};
    sendJson(res, 200, body);
}

std::optional<Job> findJob(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<Job> job = api.jobs.get(req.matches[1]);
    if (!job) sendProblem(res, 404, "no job " + std::string(req.matches[1]));
    return job;
}

void sendImage(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<Job> job = findJob(api, req, res);
    if (!job) return;
    const std::string name = req.matches[2];
    const bool preview = name == "preview.png";
    if (!preview && job->state != JobState::Succeeded)
        return sendProblem(res, 409,
                           "job " + job->id + " is " + toString(job->state) +
                               ": its image exists once it has succeeded (preview.png shows the "
                               "film so far)");
    std::optional<std::string> bytes = api.jobs.file(job->id, name);
    if (!bytes) return sendProblem(res, 404, "no " + name + " yet for job " + job->id);
    res.set_header("Cache-Control", preview ? "no-store" : "max-age=31536000, immutable");
    res.set_content(*bytes, name.ends_with(".exr") ? "image/x-exr" : "image/png");
}

}  // namespace

std::optional<int64_t> integerParam(const httplib::Request& req, httplib::Response& res,
                                    const char* name, int64_t lo, int64_t hi, int64_t fallback) {
    if (!req.has_param(name)) return fallback;
    const std::string text = req.get_param_value(name);
    size_t used = 0;
    int64_t v = 0;
    try {
        v = std::stoll(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != 0 && used == text.size() && v >= lo && v <= hi) return v;
    sendProblem(res, 400,
                std::string(name) + " must be an integer in [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]");
    return std::nullopt;
}

void registerJobRoutes(httplib::Server& http, ApiContext& api) {
    using Req = const httplib::Request&;
    using Res = httplib::Response&;
    const std::string job = std::string("/api/jobs/") + kIdPattern;
    http.Post("/api/jobs", [&api](Req req, Res res) { submitJob(api, req, res); });
    http.Get("/api/jobs", [&api](Req req, Res res) { listJobs(api, req, res); });
    http.Get(job, [&api](Req req, Res res) {
        if (std::optional<Job> j = findJob(api, req, res))
            sendJson(res, 200, jobJson(*j, api.jobs.live(j->id)));
    });
    http.Get(job + "/events", [&api](Req req, Res res) {
        if (std::optional<Job> j = findJob(api, req, res)) streamJobEvents(api, j->id, res);
    });
    http.Get(job + "/(image\\.png|image\\.exr|preview\\.png)",
             [&api](Req req, Res res) { sendImage(api, req, res); });
    http.Post(job + "/cancel", [&api](Req req, Res res) {
        std::optional<Job> j = api.jobs.cancel(req.matches[1]);
        if (!j) return sendProblem(res, 404, "no job " + std::string(req.matches[1]));
        sendJson(res, 202, jobJson(*j, api.jobs.live(j->id)));
    });
    http.Delete(job, [&api](Req req, Res res) {
        if (!api.jobs.remove(req.matches[1]))
            return sendProblem(res, 404, "no job " + std::string(req.matches[1]));
        res.status = 204;
    });
}

}  // namespace caustic::server
