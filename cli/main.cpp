// The caustic command line: one CLI11 app whose subcommands render, serve, run scale-out workers,
// check a service's health and list settings; each command module adds its subcommand and runs it
// once the whole line has parsed.
#include <iostream>

#include "command_line.h"
#include "health_command.h"
#include "render_command.h"
#include "serve_command.h"
#include "settings_command.h"
#include "worker_command.h"

int main(int argc, char** argv) {
    CLI::App app("Caustic: a physically based renderer and render service.", "caustic");
    app.set_version_flag("--version", "caustic " CAUSTIC_VERSION);
    app.get_formatter()->column_width(36);

    caustic::RenderOptions renderOptions;
    CLI::App* render = caustic::addRenderCommand(app, renderOptions);
    caustic::server::ServerConfig serveConfig;
    CLI::App* serve = caustic::addServeCommand(app, serveConfig);
    caustic::server::ServerConfig workerConfig;
    CLI::App* worker = caustic::addWorkerCommand(app, workerConfig);
    caustic::HealthOptions healthOptions;
    CLI::App* health = caustic::addHealthCommand(app, healthOptions);
    caustic::SettingsOptions settingsOptions;
    CLI::App* settings = caustic::addSettingsCommand(app, settingsOptions);

    if (int exitCode = caustic::cli::parseCommandLine(app, argc, argv); exitCode >= 0)
        return exitCode;
    if (*render) return caustic::runRender(renderOptions);
    if (*serve) return caustic::runServe(serveConfig);
    if (*worker) return caustic::runWorker(workerConfig);
    if (*health) return caustic::runHealth(healthOptions);
    if (*settings) return caustic::runSettings(settingsOptions);
    std::cerr << app.help();  // no command: a usage error
    return 2;
}
