#include "serve_command.h"

#include <signal.h>

#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "service.h"

namespace caustic {
namespace {

using server::ServerConfig;

constexpr const char* kUsage =
    "usage: caustic serve [--host ADDR] [--port N] [--data DIR] [--token TOKEN] [options]\n"
    "  --host ADDR              address to listen on (default 127.0.0.1; any other needs --token)\n"
    "  --port N                 port (default 8080; 0 picks a free one)\n"
    "  --data DIR               job store and images (default: $CAUSTIC_DATA or ./data)\n"
    "  --token TOKEN            bearer token every POST and DELETE must carry (default:\n"
    "                           $CAUSTIC_TOKEN)\n"
    "  --assets DIR             folder mesh files resolve in (default: the repository's\n"
    "                           assets/meshes)\n"
    "  --scenes DIR             example scenes, submittable by name (default: scenes/)\n"
    "  --web DIR                static files of the web page (default: web/)\n"
    "  --workers N              jobs rendered at once (default 1)\n"
    "  --threads N              threads per render, 0 for every core (default 0)\n"
    "  --lease-seconds S        a worker's lease on its job (default 10)\n"
    "  --max-stalled-leases N   leases in a row that may expire before a pass finishes before\n"
    "                           the job fails (default 3); a server killed or stopped from\n"
    "                           outside does not count, one that dies of a fault does\n"
    "  --max-attempts N         starts of one job, whatever stopped them, before it fails\n"
    "                           (default 100; guards against out-of-memory kills)\n"
    "limits (a job over one gets 422 naming the field; defaults protect a small machine):\n"
    "  --max-request-bytes N (8388608)  --max-resolution N (4096)  --max-pixels N (4194304)\n"
    "  --max-spp N (65536)  --max-photons N (10000000)  --max-time-limit S (3600)\n"
    "  --max-memory-mib N (4096)  --max-queued N (100)  --max-event-streams N (64)\n";

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

double number(const std::string& flag, const std::string& text, double lo, double hi) {
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !(v >= lo && v <= hi))
        throw UsageError(flag + " must be a number in [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "], got \"" + text + "\"");
    return v;
}

bool isLoopback(const std::string& host) {
    return host == "127.0.0.1" || host == "localhost" || host == "::1";
}

ServerConfig parseArgs(const std::vector<std::string>& args) {
    ServerConfig c;
    const char* data = std::getenv("CAUSTIC_DATA");
    c.dataDir = data && *data ? data : "data";
    const char* token = std::getenv("CAUSTIC_TOKEN");
    c.token = token ? token : "";
    c.assetsDir = CAUSTIC_DEFAULT_ASSETS_DIR;
    c.scenesDir = CAUSTIC_DEFAULT_SCENES_DIR;
    c.webDir = CAUSTIC_DEFAULT_WEB_DIR;
    server::ServiceLimits& l = c.limits;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
            return args[++i];
        };
        auto integer = [&](double lo, double hi) { return int64_t(number(a, value(), lo, hi)); };
        if (a == "--host")
            c.host = value();
        else if (a == "--port")
            c.port = int(integer(0, 65535));
        else if (a == "--data")
            c.dataDir = value();
        else if (a == "--token")
            c.token = value();
        else if (a == "--assets")
            c.assetsDir = value();
        else if (a == "--scenes")
            c.scenesDir = value();
        else if (a == "--web")
            c.webDir = value();
        else if (a == "--workers")
            c.workers = int(integer(1, 64));
        else if (a == "--threads")
            c.renderThreads = int(integer(0, 1024));
        else if (a == "--lease-seconds")
            c.leaseSeconds = number(a, value(), 0.5, 3600);
        else if (a == "--max-stalled-leases")
            c.maxStalledLeases = int(integer(1, 1000));
        else if (a == "--max-attempts")
            c.maxAttempts = int(integer(1, 1000000));
        else if (a == "--max-request-bytes")
            l.maxRequestBytes = size_t(integer(1024, 1e9));
        else if (a == "--max-resolution")
            l.maxResolution = int(integer(1, 16384));
        else if (a == "--max-pixels")
            l.maxPixels = integer(1, 268435456);
        else if (a == "--max-spp")
            l.maxSpp = int(integer(1, 1e6));
        else if (a == "--max-photons")
            l.maxPhotons = integer(1, 1e9);
        else if (a == "--max-time-limit")
            l.maxTimeLimit = number(a, value(), 1, 1e6);
        else if (a == "--max-memory-mib")
            l.maxMemoryMiB = number(a, value(), 1, 1e9);
        else if (a == "--max-queued")
            l.maxQueuedJobs = int(integer(1, 1e6));
        else if (a == "--max-event-streams")
            l.maxEventStreams = int(integer(1, 4096));
        else
            throw UsageError("unknown option " + a);
    }
    if (!isLoopback(c.host) && c.token.empty())
        throw UsageError("listening on " + c.host +
                         " exposes the service beyond this machine: give --token (or "
                         "CAUSTIC_TOKEN) so that only holders of the token can submit jobs");
    return c;
}

}  // namespace

int runServeCommand(const std::vector<std::string>& args) {
    for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
            std::cout << kUsage;
            return 0;
        }
    ServerConfig config;
    try {
        config = parseArgs(args);
    } catch (const UsageError& e) {
        std::cerr << "caustic serve: " << e.what() << "\n" << kUsage;
        return 2;
    }
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
