// /healthz and /metrics (Prometheus text exposition format 0.0.4).
#include <sstream>

#include "http/routes.h"
#include "jobs/clock.h"
#include "store/disk_space.h"
#include "store/farm_store.h"

namespace caustic::server {
namespace {

// The data folder: its use (measured by the retention sweep, a walk of the folder), the free space
// and size of its file system (statvfs, now), and what retention removed.
void storageMetrics(ApiContext& api, std::ostream& out) {
    const DiskSpace space = diskSpace(api.config.dataDir).value_or(DiskSpace{});
    out << "# HELP caustic_data_bytes Disk space the data folder takes (job store, job files), "
           "measured at the last retention sweep.\n"
           "# TYPE caustic_data_bytes gauge\n"
        << "caustic_data_bytes " << api.storage.dataBytes.load() << "\n"
        << "# HELP caustic_data_filesystem_avail_bytes Free space on the data folder's file "
           "system (POST /api/jobs answers 507 under --min-free-mib).\n"
           "# TYPE caustic_data_filesystem_avail_bytes gauge\n"
        << "caustic_data_filesystem_avail_bytes " << space.freeBytes << "\n"
        << "# HELP caustic_data_filesystem_size_bytes Size of the data folder's file system.\n"
           "# TYPE caustic_data_filesystem_size_bytes gauge\n"
        << "caustic_data_filesystem_size_bytes " << space.totalBytes << "\n"
        << "# HELP caustic_retention_sweeps_total Retention sweeps run (--sweep-seconds).\n"
           "# TYPE caustic_retention_sweeps_total counter\n"
        << "caustic_retention_sweeps_total " << api.storage.sweeps.load() << "\n"
        << "# HELP caustic_retention_jobs_removed_total Finished jobs removed with their files, by "
           "the rule that removed them.\n"
           "# TYPE caustic_retention_jobs_removed_total counter\n"
        << "caustic_retention_jobs_removed_total{reason=\"keep_days\"} "
        << api.storage.jobsRemovedTooOld.load() << "\n"
        << "caustic_retention_jobs_removed_total{reason=\"max_stored_jobs\"} "
        << api.storage.jobsRemovedOverCount.load() << "\n"
        << "# HELP caustic_retention_assets_removed_total Uploaded assets removed, unused by any "
           "job for --keep-days.\n"
           "# TYPE caustic_retention_assets_removed_total counter\n"
        << "caustic_retention_assets_removed_total " << api.storage.assetsRemoved.load() << "\n";
}

// A store shared with worker processes (PostgreSQL): the work waiting for them, and how many are
// alive, to scale workers on.
void farmMetrics(FarmStore& farm, std::ostream& out) {
    out << "# HELP caustic_queued_tasks Tasks (pass ranges of split jobs) waiting for a worker, "
           "expired leases included.\n"
           "# TYPE caustic_queued_tasks gauge\n"
        << "caustic_queued_tasks " << farm.queuedTasks() << "\n"
        << "# HELP caustic_workers Worker threads of every process that renewed their row in the "
           "last 30 s (GET /api/workers).\n"
           "# TYPE caustic_workers gauge\n"
        << "caustic_workers " << farm.listWorkers(kWorkerAliveSeconds).size() << "\n";
}

// The connections (http/connection_gate.h): open, on a thread, refused and cut.
void connectionMetrics(const ConnectionCounters& c, std::ostream& out) {
    out << "# HELP caustic_http_connections Connections open, waiting for their request or "
           "served.\n# TYPE caustic_http_connections gauge\n"
        << "caustic_http_connections " << c.open.load() << "\n"
        << "# HELP caustic_http_busy_threads Request threads serving a connection.\n"
           "# TYPE caustic_http_busy_threads gauge\n"
        << "caustic_http_busy_threads " << c.busyThreads.load() << "\n"
        << "# HELP caustic_http_connections_accepted_total Connections accepted.\n"
           "# TYPE caustic_http_connections_accepted_total counter\n"
        << "caustic_http_connections_accepted_total " << c.accepted.load() << "\n"
        << "# HELP caustic_http_connections_refused_total Connections refused on arrival, by "
           "limit.\n# TYPE caustic_http_connections_refused_total counter\n"
        << "caustic_http_connections_refused_total{reason=\"per_client\"} "
        << c.refusedPerClient.load() << "\n"
        << "caustic_http_connections_refused_total{reason=\"max_connections\"} "
        << c.refusedFull.load() << "\n"
        << "# HELP caustic_http_requests_cut_total Requests cut for coming too slowly, or "
           "kept-alive "
           "connections closed while others waited for a thread.\n"
           "# TYPE caustic_http_requests_cut_total counter\n"
        << "caustic_http_requests_cut_total{reason=\"head\"} " << c.cutHead.load() << "\n"
        << "caustic_http_requests_cut_total{reason=\"body\"} " << c.cutBody.load() << "\n"
        << "caustic_http_requests_cut_total{reason=\"idle\"} " << c.cutIdle.load() << "\n";
}

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
    if (api.farm) farmMetrics(*api.farm, out);
    storageMetrics(api, out);
    connectionMetrics(api.connections, out);
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
