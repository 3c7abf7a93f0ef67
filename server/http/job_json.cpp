#include "http/job_json.h"

#include <cmath>
#include <ctime>

#include "integrators/integrator.h"
#include "render/integrator_factory.h"

namespace caustic::server {

Json timeJson(double unixSeconds) {
    if (!(unixSeconds > 0)) return nullptr;
    std::time_t t = std::time_t(unixSeconds);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
    int ms = int((unixSeconds - std::floor(unixSeconds)) * 1000);
    char out[48];
    std::snprintf(out, sizeof out, "%s.%03dZ", buf, ms);
    return std::string(out);
}

namespace {

Json number(double v) {
    return std::isfinite(v) ? Json(v) : Json(nullptr);
}

}  // namespace

Json jobJson(const Job& job, const std::optional<LiveProgress>& live) {
    const std::string self = "/api/jobs/" + job.id;
    double progress = job.progress, error = job.relativeError, eta = job.etaSeconds;
    Json etaReason = nullptr;
    int total = job.passesTotal;
    if (live && job.state == JobState::Running) {
        // passes_done stays the store's: the passes that are durable, which never go back (a
        // pass the render has finished may still be lost to a crash before it is recorded).
        progress = live->fraction;
        total = live->passesTotal;
        error = live->relativeError;
        eta = live->etaSeconds;
        if (eta >= 0) etaReason = toString(live->etaReason);
    }
    Json links{
        {"self", self}, {"events", self + "/events"}, {"preview_png", self + "/preview.png"}};
    if (job.state == JobState::Succeeded) {
        links["image_png"] = self + "/image.png";
        links["image_exr"] = self + "/image.exr";
    }
    if (!isTerminal(job.state)) links["cancel"] = self + "/cancel";
    // A glTF job's model: what admission found in it and made of it.
    const Json model =
        job.scene.is_object() && job.scene.contains("gltf") && job.scene["gltf"].is_object()
            ? job.scene["gltf"].value("summary", Json())
            : Json();
    return Json{{"id", job.id},
                {"state", toString(job.state)},
                {"scene_name", job.sceneName.empty() ? Json(nullptr) : Json(job.sceneName)},
                {"model", model},
                {"created_at", timeJson(job.createdAt)},
                {"started_at", timeJson(job.startedAt)},
                {"finished_at", timeJson(job.finishedAt)},
                {"attempt", job.attempt},
                {"cancel_requested", job.cancelRequested},
                {"progress", number(progress)},
                {"passes_done", job.passesDone},
                {"passes_total", total},
                {"relative_error", number(error)},
                {"eta_seconds", eta >= 0 ? number(eta) : Json(nullptr)},
                {"eta_reason", etaReason},
                // The photon maps' bias is in the error (their films' bias layer): no job's
                // error leaves it out. Kept for clients that read it.
                {"error_excludes_bias", false},
                {"settings", job.settings},
                {"preset_choice", job.presetChoice},
                {"stats", job.stats},
                {"convergence", job.convergence},
                {"error", job.error.empty() ? Json(nullptr) : Json(job.error)},
                {"links", links}};
}

}  // namespace caustic::server
