// GET /api/jobs/{id}/events: a job's resource as Server-Sent Events (WHATWG HTML, "Server-sent
// events"), one `progress` event per change, then `end` (or `deleted`), on one request thread.
#include <chrono>
#include <cstring>

#include "http/job_json.h"
#include "http/problem.h"
#include "http/routes.h"

namespace caustic::server {

void streamJobEvents(ApiContext& api, const std::string& id, httplib::Response& res) {
    // Counted before it is checked: two requests at the limit cannot both pass.
    if (api.eventStreams.fetch_add(1) >= api.config.limits.maxEventStreams) {
        --api.eventStreams;
        res.set_header("Retry-After", "5");
        return sendProblem(res, 429, "too many event streams are open");
    }
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider(
        "text/event-stream",
        [&api, id, last = std::string(), seen = uint64_t(0)](size_t,
                                                             httplib::DataSink& sink) mutable {
            if (api.stopping) return false;
            std::optional<Job> now = api.jobs.get(id);
            if (!now) {
                std::string m = "event: deleted\ndata: {\"id\":\"" + id + "\"}\n\n";
                sink.write(m.data(), m.size());
                sink.done();
                return true;
            }
            std::string data = jobJson(*now, api.jobs.live(id)).dump();
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
            if (!api.jobs.waitForChange(seen, std::chrono::milliseconds(15000))) {
                const char* ping = ": keep-alive\n\n";
                if (!sink.write(ping, std::strlen(ping))) return false;
            }
            return sink.is_writable();
        },
        [&api](bool) { --api.eventStreams; });
}

}  // namespace caustic::server
