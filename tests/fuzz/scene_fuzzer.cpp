// libFuzzer target: scene JSON as `caustic render` reads a scene file (parseJson, then loadScene
// with meshes from tests/fuzz/assets), and the kd-tree built over what loaded, checked against
// brute force. Findings: crashes, sanitizer reports, hangs (-timeout), memory blow-ups
// (-rss_limit_mb), and a kd-tree that disagrees with brute force.
#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "render/settings.h"
#include "scene/scene.h"

using namespace caustic;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::useOneThread();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    SceneOptions options;
    options.assetsDir = CAUSTIC_FUZZ_ASSETS_DIR;
    std::unique_ptr<Scene> scene;
    try {
        scene = loadScene(parseJson(fuzz::text(data, size)), options);
    } catch (const InputError&) {
        return 0;
    }
    try {
        parseSettings(scene->settings);
    } catch (const InputError&) {
    }

    // The camera's rays through a 4 x 4 grid, and rays from it at the primitives.
    const Camera& camera = scene->camera;
    std::vector<Ray> rays = fuzz::raysFrom(camera.position(), scene->geometry, 64);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            rays.push_back(camera.generateRay((float(x) + 0.5f) * float(camera.width()) / 4.0f,
                                              (float(y) + 0.5f) * float(camera.height()) / 4.0f));
    fuzz::checkKdTree(scene->geometry, rays);
    return 0;
}
