// /healthz and /metrics (Prometheus text exposition format 0.0.4).
#include <sstream>

#include "http/routes.h"

namespace caustic::server {
namespace {

std::string metricsText(ApiContext& api) {
    std::map<JobState, int64_t> counts = api.jobs.countByState();
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
        << "caustic_event_streams " << api.eventStreams.load() << "\n"
        << "# HELP caustic_mesh_scans_total Mesh files scanned for their counts by admission (a "
           "new or changed file each).\n"
           "# TYPE caustic_mesh_scans_total counter\n"
        << "caustic_mesh_scans_total " << api.jobs.meshScans() << "\n";
    return out.str();
}

}  // namespace

void registerHealthRoutes(httplib::Server& http, ApiContext& api) {
    http.Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
        sendJson(res, 200, {{"status", "ok"}});
    });
    http.Get("/metrics", [&api](const httplib::Request&, httplib::Response& res) {
        res.set_content(metricsText(api), "text/plain; version=0.0.4");
    });
}

}  // namespace caustic::server
