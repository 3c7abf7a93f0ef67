#include "serve_command.h"

#include <signal.h>

#include <iostream>
#include <thread>

#include "command_line.h"
#include "service.h"

namespace caustic {
namespace {

using server::ServerConfig;

bool isLoopback(const std::string& host) {
    return host == "127.0.0.1" || host == "localhost" || host == "::1";
}

// A folder option whose --help shows its default (a std::filesystem::path would show it quoted).
CLI::Option* addFolder(CLI::App& serve, const std::string& name, std::filesystem::path& folder,
                       const std::string& help) {
    return serve
        .add_option_function<std::string>(
            name, [&folder](const std::string& dir) { folder = dir; }, help)
        ->type_name("DIR")
        ->default_str(folder.string());
}

void addLimits(CLI::App& limits, server::ServiceLimits& l) {
    cli::addNumber(limits, "--max-request-bytes", l.maxRequestBytes, 1024, 1e9,
                   "Largest request body (413 above)");
    cli::addNumber(limits, "--max-resolution", l.maxResolution, 1, 16384, "Pixels per side");
    cli::addNumber(limits, "--max-pixels", l.maxPixels, 1, 268435456, "Width times height");
    cli::addNumber(limits, "--max-spp", l.maxSpp, 1, 1e6, "Samples per pixel");
    cli::addNumber(limits, "--max-photons", l.maxPhotons, 1, 1e9,
                   "photons and caustic_photons, per pass");
    cli::addNumber(limits, "--max-time-limit", l.maxTimeLimit, 1, 1e6,
                   "Seconds; a job that sets no time_limit gets this one");
    cli::addNumber(limits, "--max-memory-mib", l.maxMemoryMiB, 1, 1e9,
                   "Estimated peak memory of a render, MiB; caps a job's memory_limit");
    cli::addNumber(limits, "--max-queued", l.maxQueuedJobs, 1, 1e6,
                   "Jobs waiting to run (429 above)");
    cli::addNumber(limits, "--max-event-streams", l.maxEventStreams, 1, 4096,
                   "Concurrent Server-Sent Events connections");
    // At most SQLite's default SQLITE_MAX_LENGTH, the largest BLOB the store can hold.
    cli::addNumber(limits, "--max-asset-bytes", l.maxAssetBytes, 1024, 1e9,
                   "Largest uploaded mesh file (413 above)");
    cli::addNumber(limits, "--max-asset-triangles", l.maxAssetTriangles, 1, 1e9,
                   "Triangles of one uploaded mesh (422 above)");
    cli::addNumber(limits, "--max-asset-storage-mib", l.maxAssetStorageMiB, 1, 1e9,
                   "Every stored asset together, MiB (507 above)");
    cli::addNumber(limits, "--max-uploads,--max-uploads-in-flight", l.maxUploads, 1, 1024,
                   "Uploads being read and checked at once (429 above)");
}

void addWorkOptions(CLI::App& serve, ServerConfig& c) {
    cli::addNumber(serve, "--workers", c.workers, 1, 64, "Jobs rendered at once");
    cli::addNumber(serve, "--threads", c.renderThreads, 0, 1024,
                   "Threads per render, 0 for every core");
    cli::addNumber(serve, "--lease-seconds", c.leaseSeconds, 0.5, 3600,
                   "A worker's lease on its job, seconds");
    cli::addNumber(serve, "--max-stalled-leases", c.maxStalledLeases, 1, 1000,
                   "Leases in a row that may expire before a pass finishes before the job fails; "
                   "a server killed or stopped from outside does not count, one that dies of a "
                   "fault does");
    cli::addNumber(serve, "--max-attempts", c.maxAttempts, 1, 1e6,
                   "Starts of one job, whatever stopped them, before it fails (guards against "
                   "out-of-memory kills)");
}

}  // namespace

CLI::App* addServeCommand(CLI::App& app, ServerConfig& c) {
    CLI::App* serve = app.add_subcommand(
        "serve", "Runs the render service (HTTP API and web page) until SIGINT or SIGTERM.");
    serve->add_option("--host", c.host, "Address to listen on; any but loopback needs --token")
        ->type_name("ADDR")
        ->capture_default_str();
    cli::addNumber(*serve, "--port", c.port, 0, 65535, "Port; 0 picks a free one");
    addFolder(*serve, "--data", c.dataDir, "Job store and images")->envname("CAUSTIC_DATA");
    serve
        ->add_option("--token", c.token,
                     "Bearer token every POST and DELETE must carry (default: none)")
        ->envname("CAUSTIC_TOKEN");
    c.assetsDir = CAUSTIC_DEFAULT_ASSETS_DIR;
    c.scenesDir = CAUSTIC_DEFAULT_SCENES_DIR;
    c.webDir = CAUSTIC_DEFAULT_WEB_DIR;
    c.docsDir = CAUSTIC_DEFAULT_DOCS_DIR;
    addFolder(*serve, "--assets", c.assetsDir, "The folder mesh file names resolve in");
    addFolder(*serve, "--scenes", c.scenesDir, "Example scenes, submittable by name");
    addFolder(*serve, "--web", c.webDir, "Static files of the web page");
    addFolder(*serve, "--docs", c.docsDir, "Documentation served at /docs/ (the scene format)");
    addWorkOptions(*serve, c);
    addLimits(*serve->add_option_group("Limits (a job over one gets 422 naming the field)"),
              c.limits);
    serve->callback([&c] {
        if (!isLoopback(c.host) && c.token.empty())
            throw CLI::ValidationError(
                "--host", "listening on " + c.host +
                              " exposes the service beyond this machine: give --token (or "
                              "CAUSTIC_TOKEN) so that only holders of the token can submit jobs");
    });
    return serve;
}

int runServe(const ServerConfig& config) {
    // SIGINT and SIGTERM are taken by one thread with sigwait, not by a handler: stopping the
    // service is not async-signal-safe. Block them before any thread starts.
    sigset_t stopSignals;
    sigemptyset(&stopSignals);
    sigaddset(&stopSignals, SIGINT);
    sigaddset(&stopSignals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);
    signal(SIGPIPE, SIG_IGN);
    try {
        server::RenderService service(config);
        int port = service.bind();
        std::string host =
            config.host.find(':') != std::string::npos ? "[" + config.host + "]" : config.host;
        std::cout << "caustic: serving on http://" << host << ":" << port << "/ (data "
                  << config.dataDir.string() << "; Ctrl-C stops)" << std::endl;
        std::thread watcher([&] {
            int sig = 0;
            sigwait(&stopSignals, &sig);
            std::cerr << "caustic serve: stopping\n";
            service.stop();
        });
        service.serve();
        // serve() returned without a signal (it could not listen): release the watcher.
        pthread_kill(watcher.native_handle(), SIGTERM);
        watcher.join();
    } catch (const std::exception& e) {
        std::cerr << "caustic serve: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

}  // namespace caustic
