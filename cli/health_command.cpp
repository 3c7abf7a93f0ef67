#include "health_command.h"

#include <httplib.h>

#include <iostream>
#include <regex>

#include "command_line.h"

namespace caustic {

CLI::App* addHealthCommand(CLI::App& app, HealthOptions& options) {
    CLI::App* health = app.add_subcommand(
        "health", "Exits 0 when a service's /healthz answers 200 (a container's health check).");
    health->add_option("--url", options.url, "The service's /healthz")
        ->envname("CAUSTIC_HEALTH_URL")
        ->capture_default_str();
    cli::addNumber(*health, "--timeout", options.timeoutSeconds, 0.1, 600, "Seconds to wait");
    return health;
}

int runHealth(const HealthOptions& options) {
    // scheme://host[:port] and the path.
    static const std::regex url(R"(^(https?://[^/]+)(/.*)?$)");
    std::smatch m;
    if (!std::regex_match(options.url, m, url)) {
        std::cerr << "caustic health: --url: expected http(s)://host:port/path, got \""
                  << options.url << "\"\n";
        return 2;
    }
    httplib::Client client(m[1].str());
    // The check runs beside the server, which may hold a certificate made for another name.
    client.enable_server_certificate_verification(false);
    auto seconds = std::chrono::duration<double>(options.timeoutSeconds);
    client.set_connection_timeout(seconds);
    client.set_read_timeout(seconds);
    const std::string path = m[2].matched ? m[2].str() : "/";
    httplib::Result r = client.Get(path);
    if (!r) {
        std::cerr << "caustic health: " << options.url << ": " << httplib::to_string(r.error())
                  << "\n";
        return 1;
    }
    if (r->status != 200) {
        std::cerr << "caustic health: " << options.url << " answered " << r->status << ": "
                  << r->body << "\n";
        return 1;
    }
    return 0;
}

}  // namespace caustic
