#include "serve_command.h"

#include <signal.h>

#include <cctype>
#include <fstream>
#include <iostream>
#include <regex>
#include <thread>

#include <spdlog/spdlog.h>

#include "command_line.h"
#include "http/same_origin.h"
#include "logging.h"
#include "service.h"
#include "service_options.h"

namespace caustic {
namespace {

using server::ServerConfig;

// A folder option whose --help shows its default (a std::filesystem::path would show it quoted).
CLI::Option* addFolder(CLI::App& serve, const std::string& name, std::filesystem::path& folder,
                       const std::string& help) {
    return serve
        .add_option_function<std::string>(
            name, [&folder](const std::string& dir) { folder = dir; }, help)
        ->type_name("DIR")
        ->default_str(folder.string());
}

// The token's first line, without the line break: a secret file (/run/secrets/...) keeps the
// token out of the process's environment and command line.
std::string readTokenFile(const std::string& file) {
    std::ifstream in(file);
    std::string token;
    if (!in || !std::getline(in, token))
        throw CLI::ValidationError("--token-file", "cannot read a token from " + file);
    while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back())))
        token.pop_back();
    if (token.empty()) throw CLI::ValidationError("--token-file", file + " holds no token");
    return token;
}

// --token, --token-file, --tls-cert and --tls-key.
void addSecurityOptions(CLI::App& serve, ServerConfig& c) {
    CLI::Option* token =
        serve
            .add_option("--token", c.token,
                        "Bearer token every POST and DELETE must carry (default: none)")
            ->envname("CAUSTIC_TOKEN");
    serve
        .add_option_function<std::string>(
            "--token-file", [&c](const std::string& file) { c.token = readTokenFile(file); },
            "A file whose first line is the token (a container's secret)")
        ->type_name("FILE")
        ->envname("CAUSTIC_TOKEN_FILE")
        ->excludes(token);
    CLI::Option* cert =
        serve
            .add_option_function<std::string>(
                "--tls-cert", [&c](const std::string& file) { c.tlsCert = file; },
                "PEM certificate (chain): serve HTTPS only, so that the token cannot be read "
                "on the way")
            ->type_name("FILE")
            ->envname("CAUSTIC_TLS_CERT");
    CLI::Option* key = serve
                           .add_option_function<std::string>(
                               "--tls-key", [&c](const std::string& file) { c.tlsKey = file; },
                               "PEM private key of --tls-cert")
                           ->type_name("FILE")
                           ->envname("CAUSTIC_TLS_KEY");
    cert->needs(key);
    key->needs(cert);
}

void addLimits(CLI::App& limits, server::ServiceLimits& l) {
    cli::addNumber(limits, "--max-request-bytes", l.maxRequestBytes, 1024, 1e9,
                   "Largest request body (413 above)");
    cli::addNumber(limits, "--max-resolution", l.maxResolution, 1, 16384, "Pixels per side");
    cli::addNumber(limits, "--max-pixels", l.maxPixels, 1, 268435456, "Width times height");
    cli::addNumber(limits, "--max-spp", l.maxSpp, 1, 1e6, "Samples per pixel");
    cli::addNumber(limits, "--max-photons", l.maxPhotons, 1, 1e9,
                   "photons, caustic_photons and indirect_photons, per pass, wherever the job's "
                   "integrator reads them");
    cli::addNumber(limits, "--max-time-limit", l.maxTimeLimit, 1, 1e6,
                   "Seconds; a job that sets no time_limit gets this one");
    cli::addNumber(limits, "--max-memory-mib", l.maxMemoryMiB, 1, 1e9,
                   "Estimated peak memory of a render, MiB; caps a job's memory_limit");
    cli::addNumber(limits, "--max-queued", l.maxQueuedJobs, 1, 1e6,
                   "Jobs waiting to run (429 above)");
    cli::addNumber(limits, "--max-event-streams", l.maxEventStreams, 1, 4096,
                   "Concurrent Server-Sent Events connections");
    cli::addNumber(limits, "--max-connections", l.maxConnections, 1, 1e6,
                   "Connections open at once, from all clients (503 above)");
    cli::addNumber(limits, "--max-connections-per-client", l.maxConnectionsPerClient, 0, 1e6,
                   "Connections open at once from one address (429 above); 0 for no limit, as "
                   "behind a reverse proxy, whose address every request has");
    cli::addNumber(limits, "--request-head-seconds", l.requestHeadSeconds, 0.1, 3600,
                   "Seconds a request's head (request line and headers) may take to arrive, from "
                   "the connection's opening or its previous response; a slower one is cut");
    cli::addNumber(limits, "--min-body-rate", l.minBodyBytesPerSecond, 1, 1e12,
                   "Bytes a second a request body must average, after --request-head-seconds of "
                   "grace; a slower one is cut");
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

void addStorageOptions(CLI::App& serve, server::StoragePolicy& s) {
    cli::addNumber(serve, "--keep-days", s.keepDays, 0, 1e5,
                   "Finished jobs and their files are removed this many days after they finished "
                   "(fractions allowed); 0 keeps them");
    cli::addNumber(serve, "--max-stored-jobs", s.maxStoredJobs, 0, 1e9,
                   "Finished jobs kept at most, the most recently finished; 0 for no limit");
    cli::addNumber(serve, "--sweep-seconds", s.sweepSeconds, 0.05, 86400,
                   "How often retention runs and the data folder's disk use is measured");
    cli::addNumber(serve, "--min-free-mib", s.minFreeMiB, 0, 1e9,
                   "Free space the data folder's disk must keep after a new job or upload (507 "
                   "under it); 0 checks only that writes succeed");
}

// Who may use the API from a web page, and what the service logs (docs/security.md and
// docs/operations.md).
void addBrowserAndLogOptions(CLI::App& serve, ServerConfig& c) {
    // An origin is a scheme, a host and a port, without a path (RFC 6454, section 4): what a
    // browser sends in Origin; "null" and "*" are no origin.
    static const std::regex origin(R"(https?://[^/?#@\s]+)", std::regex::icase);
    serve
        .add_option("--allow-origin", c.allowedOrigins,
                    "An origin (scheme://host[:port]) whose pages may change jobs and read "
                    "answers (CORS); repeatable. Other origins' POST and DELETE get 403")
        ->type_name("ORIGIN")
        ->check(CLI::Validator(
            [](const std::string& value) {
                return std::regex_match(value, origin)
                           ? std::string()
                           : "must be scheme://host[:port] with no path, as a browser sends it "
                             "in Origin (http://localhost:5173), got \"" +
                                 value + "\"";
            },
            "ORIGIN"));
    cli::addLogLevelOption(serve, c);
    serve
        .add_option("--access-log", c.accessLog,
                    "File for the access log, one line per request, \"-\" for stdout "
                    "(default: stderr, with the messages)")
        ->type_name("FILE|-");
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
    addSecurityOptions(*serve, c);
    c.assetsDir = CAUSTIC_DEFAULT_ASSETS_DIR;
    c.scenesDir = CAUSTIC_DEFAULT_SCENES_DIR;
    c.webDir = CAUSTIC_DEFAULT_WEB_DIR;
    c.docsDir = CAUSTIC_DEFAULT_DOCS_DIR;
    addFolder(*serve, "--assets", c.assetsDir, "The folder mesh file names resolve in")
        ->envname("CAUSTIC_ASSETS");
    addFolder(*serve, "--scenes", c.scenesDir, "Example scenes, submittable by name");
    addFolder(*serve, "--web", c.webDir, "Static files of the web page");
    addFolder(*serve, "--docs", c.docsDir, "Documentation served at /docs/ (the scene format)");
    cli::addStoreOptions(*serve, c, false);
    cli::addWorkOptions(*serve, c, 0);
    addStorageOptions(*serve, c.storage);
    addBrowserAndLogOptions(*serve, c);
    addLimits(*serve->add_option_group("Limits (a job over one gets 422 naming the field)"),
              c.limits);
    serve->callback([&c] {
        if (c.workers == 0 && c.store.empty())
            throw CLI::ValidationError(
                "--workers",
                "0 workers render nothing with the embedded SQLite store: give at "
                "least 1, or --store postgresql://... with `caustic worker` processes");
        if (!server::isLoopbackHost(c.host) && c.token.empty())
            throw CLI::ValidationError(
                "--host", "listening on " + c.host +
                              " exposes the service beyond this machine: give --token (or "
                              "CAUSTIC_TOKEN) so that only holders of the token can submit jobs");
    });
    return serve;
}

int runServe(const ServerConfig& config) {
    cli::StopSignals stopSignals;  // before any thread starts
    try {
        server::setUpLogging(config.logLevel, config.accessLog);
    } catch (const std::exception& e) {
        std::cerr << "caustic serve: --access-log: " << e.what() << "\n";
        return 1;
    }
    try {
        server::RenderService service(config);
        int port = service.bind();
        std::string host =
            config.host.find(':') != std::string::npos ? "[" + config.host + "]" : config.host;
        // Printed on stdout, not logged: scripts and tests read the address from this line.
        const std::string store = config.store.empty()
                                      ? "data " + config.dataDir.string()
                                      : "store " + cli::redactedStore(config.store);
        std::cout << "caustic: serving on " << (config.tls() ? "https://" : "http://") << host
                  << ":" << port << "/ (" << store << "; Ctrl-C stops)" << std::endl;
        std::thread watcher([&] {
            spdlog::info("stopping (signal {})", stopSignals.wait());
            service.stop();
        });
        service.serve();
        // serve() returned without a signal (it could not listen): release the watcher.
        cli::StopSignals::release(watcher.native_handle());
        watcher.join();
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 1;
    }
    return 0;
}

}  // namespace caustic
