#include "http/routes.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

#include "core/error.h"
#include "http/job_json.h"
#include "http/openapi.h"
#include "http/problem.h"
#include "jobs/submission.h"
#include "render/settings.h"

namespace caustic::server {
namespace {

constexpr const char* kJson = "application/json";
constexpr const char* kIdPattern = "([0-9a-f]{32})";

struct TooDeep {};

// Parses a request body, refusing nesting deeper than `maxDepth` before it costs anything.
Json parseBody(const std::string& body, int maxDepth) {
    return Json::parse(body, [maxDepth](int depth, Json::parse_event_t, Json&) {
        if (depth > maxDepth) throw TooDeep{};
        return true;
    });
}

std::string newJobId() {
    static thread_local std::mt19937_64 rng{std::random_device{}() ^
                                            (uint64_t(std::random_device{}()) << 32)};
    char buf[33];
    std::snprintf(buf, sizeof buf, "%016llx%016llx", (unsigned long long)rng(),
                  (unsigned long long)rng());
    return buf;
}

// FNV-1a, 64 bits: identifies a request body for Idempotency-Key retries.
std::string bodyHash(const std::string& body) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : body) h = (h ^ c) * 1099511628211ull;
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return buf;
}

bool mutating(const std::string& method) {
    return method == "POST" || method == "PUT" || method == "PATCH" || method == "DELETE";
}

// Compares without an early exit, so that timing does not tell how much of a token was right.
bool sameToken(const std::string& given, const std::string& token) {
    if (given.size() != token.size() || token.empty()) return false;
    unsigned char diff = 0;
    for (size_t i = 0; i < token.size(); ++i) diff |= uint8_t(given[i] ^ token[i]);
    return diff == 0;
}

void sendJson(httplib::Response& res, int status, const Json& body) {
    res.status = status;
    res.set_content(body.dump(), kJson);
}

std::optional<Job> findJob(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<Job> job = api.store.get(req.matches[1]);
    if (!job) sendProblem(res, 404, "no job " + std::string(req.matches[1]));
    return job;
}

std::string metricsText(ApiContext& api) {
    std::map<JobState, int64_t> counts = api.store.countByState();
    std::ostringstream out;
    out << "# HELP caustic_queue_depth Jobs waiting for a worker.\n"
           "# TYPE caustic_queue_depth gauge\n"
        << "caustic_queue_depth " << counts[JobState::Queued] << "\n"
        << "# HELP caustic_jobs Jobs in the store by state.\n# TYPE caustic_jobs gauge\n";
    for (const auto& [state, n] : counts)
        out << "caustic_jobs{state=\"" << toString(state) << "\"} " << n << "\n";
    out << "# HELP caustic_rays_total Rays traced by finished renders.\n"
           "# TYPE caustic_rays_total counter\n"
        << "caustic_rays_total " << api.counters.rays.load() << "\n"
        << "# HELP caustic_rays_per_second Throughput of the last finished render.\n"
           "# TYPE caustic_rays_per_second gauge\n"
        << "caustic_rays_per_second " << api.counters.lastRaysPerSecond.load() << "\n"
        << "# HELP caustic_render_seconds_total Wall seconds spent rendering passes.\n"
           "# TYPE caustic_render_seconds_total counter\n"
        << "caustic_render_seconds_total " << api.counters.renderSeconds.load() << "\n"
        << "# HELP caustic_passes_total Passes finished.\n# TYPE caustic_passes_total counter\n"
        << "caustic_passes_total " << api.counters.passes.load() << "\n"
        << "# HELP caustic_event_streams Open Server-Sent Events connections.\n"
           "# TYPE caustic_event_streams gauge\n"
        << "caustic_event_streams " << api.eventStreams.load() << "\n";
    return out.str();
}

void submitJob(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    const std::string key = req.get_header_value("Idempotency-Key");
    const std::string hash = bodyHash(req.body);
    auto replay = [&](const StoredResponse& stored) {
        if (stored.requestHash != hash)
            return sendProblem(res, 409,
                               "Idempotency-Key \"" + key + "\" was used with another body");
        res.status = stored.status;
        res.set_header("Location", "/api/jobs/" + stored.jobId);
        res.set_content(stored.body, kJson);
    };
    if (key.size() > 200) return sendProblem(res, 400, "Idempotency-Key is over 200 characters");
    if (!key.empty())
        if (std::optional<StoredResponse> stored = api.store.storedResponse(key))
            return replay(*stored);

    // nlohmann::json takes a NUL byte for the end of its input, so whatever followed one would
    // pass unread; JSON text has none (RFC 8259).
    if (size_t nul = req.body.find('\0'); nul != std::string::npos)
        return sendProblem(res, 400, "malformed JSON: a NUL byte at offset " + std::to_string(nul));
    Json body;
    try {
        body = parseBody(req.body, api.config.limits.maxJsonDepth);
    } catch (const TooDeep&) {
        return sendProblem(res, 400,
                           "JSON nested deeper than " +
                               std::to_string(api.config.limits.maxJsonDepth) + " levels");
    } catch (const Json::exception& e) {
        return sendProblem(res, 400, std::string("malformed JSON: ") + e.what());
    }
    const int64_t queued = api.store.countByState()[JobState::Queued];
    if (queued >= api.config.limits.maxQueuedJobs) {
        res.set_header("Retry-After", "30");
        return sendProblem(res, 429,
                           "the queue is full (" + std::to_string(queued) + " jobs waiting)");
    }
    Job job;
    try {
        job = prepareJob(body, api.config);
    } catch (const InputError& e) {
        return sendProblem(res, 422, e.what(), e.path());
    }
    job.id = newJobId();
    job.createdAt = unixNow();
    const std::string responseBody = jobJson(job, std::nullopt).dump();
    if (std::optional<StoredResponse> raced =
            api.store.insert(job, key, StoredResponse{hash, 202, responseBody, job.id}))
        return replay(*raced);
    api.workers.wake();
    api.events.notify();
    res.status = 202;
    res.set_header("Location", "/api/jobs/" + job.id);
    res.set_content(responseBody, kJson);
}

void listJobs(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<JobState> state;
    if (req.has_param("state")) {
        state = parseJobState(req.get_param_value("state"));
        if (!state)
            return sendProblem(res, 400,
                               "state must be queued, running, succeeded, failed or cancelled");
    }
    auto integerParam = [&](const char* name, int64_t lo, int64_t hi,
                            int64_t fallback) -> std::optional<int64_t> {
        if (!req.has_param(name)) return fallback;
        const std::string text = req.get_param_value(name);
        size_t used = 0;
        int64_t v = 0;
        try {
            v = std::stoll(text, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != text.size() || v < lo || v > hi) {
            sendProblem(res, 400,
                        std::string(name) + " must be an integer in [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "]");
            return std::nullopt;
        }
        return v;
    };
    std::optional<int64_t> limit = integerParam("limit", 1, 100, 20);
    if (!limit) return;
    std::optional<int64_t> cursor = integerParam("cursor", 1, INT64_MAX, INT64_MAX);
    if (!cursor) return;
    JobPage page = api.store.list(state, int(*limit), *cursor);
    Json jobs = Json::array();
    for (const Job& j : page.jobs) {
        Json item = jobJson(j, api.events.live(j.id));
        item.erase("convergence");  // the list stays small; the job resource has it
        jobs.push_back(std::move(item));
    }
    Json body{{"jobs", jobs}, {"next_cursor", page.next ? Json(*page.next) : Json(nullptr)}};
    sendJson(res, 200, body);
}

void streamEvents(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    std::optional<Job> job = findJob(api, req, res);
    if (!job) return;
    if (api.eventStreams.load() >= api.config.limits.maxEventStreams) {
        res.set_header("Retry-After", "5");
        return sendProblem(res, 429, "too many event streams are open");
    }
    ++api.eventStreams;
    const std::string id = job->id;
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider(
        "text/event-stream",
        [&api, id, last = std::string(), seen = uint64_t(0)](size_t,
                                                             httplib::DataSink& sink) mutable {
            if (api.stopping) return false;
            std::optional<Job> now = api.store.get(id);
            if (!now) {
                std::string m = "event: deleted\ndata: {\"id\":\"" + id + "\"}\n\n";
                sink.write(m.data(), m.size());
                sink.done();
                return true;
            }
            std::string data = jobJson(*now, api.events.live(id)).dump();
            if (data != last) {
                std::string m =
                    "event: " + std::string(isTerminal(now->state) ? "end" : "progress") +
                    "\ndata: " + data + "\n\n";
                if (!sink.write(m.data(), m.size())) return false;
                last = std::move(data);
            }
            if (isTerminal(now->state)) {
                sink.done();
                return true;
            }
            // Wait for any change; a comment every 15 s keeps proxies from closing the stream.
            if (!api.events.wait(seen, std::chrono::milliseconds(15000))) {
                const char* ping = ": keep-alive\n\n";
                if (!sink.write(ping, std::strlen(ping))) return false;
            }
            return sink.is_writable();
        },
        [&api](bool) { --api.eventStreams; });
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
    std::ifstream in(api.files.image(job->id, name), std::ios::binary);
    if (!in) return sendProblem(res, 404, "no " + name + " yet for job " + job->id);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    res.set_header("Cache-Control", preview ? "no-store" : "max-age=31536000, immutable");
    res.set_content(bytes, name.ends_with(".exr") ? "image/x-exr" : "image/png");
}

// An example scene's file as written (its layout and key order, for an editor): the JSON that a job
// naming the scene renders.
void sendExampleScene(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    const std::string name = req.matches[1];
    const std::vector<std::string> names = exampleSceneNames(api.config.scenesDir);
    if (std::find(names.begin(), names.end(), name) == names.end())
        return sendProblem(res, 404, "no example scene \"" + name + "\"");
    std::ifstream in(api.config.scenesDir / (name + ".json"), std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!Json::accept(text))
        return sendProblem(res, 500, "the example scene \"" + name + "\" is not valid JSON");
    res.set_content(text, kJson);
}

}  // namespace

void registerRoutes(httplib::Server& http, ApiContext& api) {
    http.set_payload_max_length(api.config.limits.maxRequestBytes);

    http.set_pre_routing_handler([&api](const httplib::Request& req, httplib::Response& res) {
        // Answered here, before cpp-httplib reads the body: the client must close the
        // connection, or its next request on it would be read from the body left unread.
        auto refuse = [&res](int status, const std::string& detail) {
            res.set_header("Connection", "close");
            sendProblem(res, status, detail);
            return httplib::Server::HandlerResponse::Handled;
        };
        // A decoded %00 would cut a static file's name short ("/index.html%00.png").
        if (req.path.find('\0') != std::string::npos) return refuse(400, "the path has a NUL byte");
        // Only a Content-Length holds a body to --max-request-bytes: cpp-httplib reads chunked
        // and compressed bodies whole, whatever their size, and a POST with neither header until
        // the connection closes.
        if (req.has_header("Transfer-Encoding"))
            return refuse(411, "send the body with a Content-Length, not chunked");
        if (const std::string coding = req.get_header_value("Content-Encoding");
            !coding.empty() && coding != "identity")
            return refuse(415, "compressed bodies (Content-Encoding) are not accepted");
        // A request with neither header has no body (RFC 9112, section 6.3), as in
        // `curl -X POST .../cancel`. `req` is the server's own, not a const object.
        if (!req.has_header("Content-Length"))
            const_cast<httplib::Request&>(req).set_header("Content-Length", "0");

        if (api.config.token.empty() || !mutating(req.method))
            return httplib::Server::HandlerResponse::Unhandled;
        const std::string auth = req.get_header_value("Authorization");
        // The scheme is case-insensitive (RFC 9110, section 11.1); the token is not.
        const std::string prefix = "bearer ";
        if (auth.size() >= prefix.size() &&
            std::equal(prefix.begin(), prefix.end(), auth.begin(),
                       [](char a, char b) { return a == std::tolower((unsigned char)b); }) &&
            sameToken(auth.substr(prefix.size()), api.config.token))
            return httplib::Server::HandlerResponse::Unhandled;
        res.set_header("WWW-Authenticate", "Bearer");
        return refuse(401, "this server needs \"Authorization: Bearer <token>\" to change jobs");
    });
    // Every error without a body of its own (unknown routes, a body over the limit) gets one.
    http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
        if (res.body.empty()) {
            std::string detail = res.status == 413   ? "the request body is over the size limit"
                                 : res.status == 404 ? "no such resource"
                                                     : statusTitle(res.status);
            sendProblem(res, res.status, detail);
        }
    });
    http.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
            std::string what = "internal error";
            try {
                std::rethrow_exception(ep);
            } catch (const std::exception& e) {
                what = std::string("internal error: ") + e.what();
            } catch (...) {
            }
            sendProblem(res, 500, what);
        });

    http.Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
        sendJson(res, 200, {{"status", "ok"}});
    });
    http.Get("/metrics", [&api](const httplib::Request&, httplib::Response& res) {
        res.set_content(metricsText(api), "text/plain; version=0.0.4");
    });
    http.Get("/api/openapi.json", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(openApiDocument(), kJson);
    });
    http.Get("/api/settings", [](const httplib::Request&, httplib::Response& res) {
        sendJson(res, 200, settingsSchemaJson());
    });
    http.Get("/api/scenes", [&api](const httplib::Request&, httplib::Response& res) {
        sendJson(res, 200, {{"scenes", exampleSceneNames(api.config.scenesDir)}});
    });
    http.Get("/api/scenes/([^/]+)", [&api](const httplib::Request& req, httplib::Response& res) {
        sendExampleScene(api, req, res);
    });
    http.Post("/api/jobs", [&api](const httplib::Request& req, httplib::Response& res) {
        submitJob(api, req, res);
    });
    http.Get("/api/jobs", [&api](const httplib::Request& req, httplib::Response& res) {
        listJobs(api, req, res);
    });
    http.Get(std::string("/api/jobs/") + kIdPattern,
             [&api](const httplib::Request& req, httplib::Response& res) {
                 if (std::optional<Job> job = findJob(api, req, res))
                     sendJson(res, 200, jobJson(*job, api.events.live(job->id)));
             });
    http.Get(std::string("/api/jobs/") + kIdPattern + "/events",
             [&api](const httplib::Request& req, httplib::Response& res) {
                 streamEvents(api, req, res);
             });
    http.Get(
        std::string("/api/jobs/") + kIdPattern + "/(image\\.png|image\\.exr|preview\\.png)",
        [&api](const httplib::Request& req, httplib::Response& res) { sendImage(api, req, res); });
    http.Post(std::string("/api/jobs/") + kIdPattern + "/cancel",
              [&api](const httplib::Request& req, httplib::Response& res) {
                  std::optional<Job> job = api.store.cancel(req.matches[1], unixNow());
                  if (!job) return sendProblem(res, 404, "no job " + std::string(req.matches[1]));
                  api.events.notify();
                  sendJson(res, 202, jobJson(*job, api.events.live(job->id)));
              });
    http.Delete(std::string("/api/jobs/") + kIdPattern,
                [&api](const httplib::Request& req, httplib::Response& res) {
                    const std::string id = req.matches[1];
                    // A running job is asked to stop first; its fenced writes then change nothing.
                    api.store.cancel(id, unixNow());
                    if (!api.store.remove(id)) return sendProblem(res, 404, "no job " + id);
                    api.files.remove(id);
                    api.events.notify();
                    res.status = 204;
                });
    if (!api.config.webDir.empty()) http.set_mount_point("/", api.config.webDir.string());
}

}  // namespace caustic::server
