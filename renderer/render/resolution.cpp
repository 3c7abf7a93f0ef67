#include "render/resolution.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/error.h"
#include "scene/json_reader.h"

namespace caustic {

void applyResolution(Scene& scene, RenderSettings& settings, const SceneOptions& limits,
                     const std::string& path) {
    const int64_t cameraWidth = scene.camera.width(), cameraHeight = scene.camera.height();
    int64_t width = settings.width, height = settings.height;
    if (width == 0 && height == 0) {
        width = cameraWidth;
        height = cameraHeight;
    } else if (height == 0) {
        height = std::max<int64_t>(
            1, std::llround(double(width) * double(cameraHeight) / double(cameraWidth)));
    } else if (width == 0) {
        width = std::max<int64_t>(
            1, std::llround(double(height) * double(cameraWidth) / double(cameraHeight)));
    }
    std::string widthPath = jsonPointer(path, "width"), heightPath = jsonPointer(path, "height");
    // A side that follows the aspect ratio: its error is the given side's.
    const bool derived = (settings.width == 0) != (settings.height == 0);
    if (derived) widthPath = heightPath = settings.width != 0 ? widthPath : heightPath;
    try {
        checkResolution(width, height, limits, widthPath, heightPath);
    } catch (const InputError& e) {
        if (!derived) throw;
        throw InputError(e.path(), "makes a " + std::to_string(width) + "x" +
                                       std::to_string(height) +
                                       " image at the camera's aspect ratio: " + e.message());
    }
    if (width != cameraWidth || height != cameraHeight)
        scene.camera = scene.camera.resized(int(width), int(height));
    settings.width = int(width);
    settings.height = int(height);
}

}  // namespace caustic
