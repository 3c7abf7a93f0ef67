// The caustic command line: render scenes, list settings.
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "render/settings.h"
#include "render_command.h"
#include "serve_command.h"

namespace {

constexpr const char* kHelp =
    "caustic: a physically based renderer\n"
    "usage:\n"
    "  caustic render SCENE -o OUT.png [--set key=value ...]   render a scene (see caustic render "
    "--help)\n"
    "  caustic serve [--port N] [--data DIR] ...               run the render service (see caustic "
    "serve --help)\n"
    "  caustic settings                                        list render settings as JSON\n"
    "  caustic --version\n";

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        std::cout << kHelp;
        return args.empty() ? 2 : 0;
    }
    if (args[0] == "--version") {
        std::cout << "caustic 0.1.0\n";
        return 0;
    }
    if (args[0] == "settings") {
        std::cout << caustic::settingsSchemaJson().dump(2) << "\n";
        return 0;
    }
    if (args[0] == "serve") {
        std::vector<std::string> rest(args.begin() + 1, args.end());
        return caustic::runServeCommand(rest);
    }
    if (args[0] == "render") {
        std::vector<std::string> rest(args.begin() + 1, args.end());
        return caustic::runRenderCommand(rest);
    }
    std::cerr << "caustic: unknown command \"" << args[0] << "\"\n" << kHelp;
    return 2;
}
