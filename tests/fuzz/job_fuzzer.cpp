// libFuzzer target: a POST /api/jobs body as the server admits it (no NUL byte, at most
// maxJsonDepth levels, then prepareJob), with example scenes from scenes/ and meshes from
// tests/fuzz/assets. An admitted job must load again as a worker loads it.
#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "jobs/submission.h"
#include "render/settings.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

using namespace caustic;

namespace {

const server::ServerConfig& config() {
    static const server::ServerConfig c = [] {
        server::ServerConfig config;
        config.scenesDir = CAUSTIC_SOURCE_DIR "/scenes";
        config.assetsDir = CAUSTIC_FUZZ_ASSETS_DIR;
        config.renderThreads = 1;
        return config;
    }();
    return c;
}

// As server/http/routes.cpp parses a body; nullopt for what it answers 400 to. Its parse callback
// refuses any event deeper than maxJsonDepth (the root's start is at depth 0): at most
// maxJsonDepth + 1 levels, the last of them empty.
std::optional<Json> parseBody(const std::string& body) {
    if (body.find('\0') != std::string::npos) return std::nullopt;
    return tryParseJson(body, config().limits.maxJsonDepth + 1);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::useOneThread();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::optional<Json> body = parseBody(fuzz::text(data, size));
    if (!body) return 0;
    server::Job job;
    try {
        job = server::prepareJob(*body, config());
    } catch (const InputError&) {
        return 0;
    }
    // As server/jobs/worker_pool.cpp starts it.
    try {
        SceneOptions options;
        options.assetsDir = config().assetsDir;
        loadScene(job.scene, options);
        parseSettings(job.settings);
    } catch (const InputError& e) {
        fuzz::fail(std::string("an admitted job does not load in a worker: ") + e.what());
    }
    return 0;
}
