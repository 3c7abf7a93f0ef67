#include "scene/light_loader.h"

#include <algorithm>

#include "core/interrupt.h"
#include "film/image_io.h"
#include "lights/directional_light.h"
#include "lights/environment_light.h"
#include "lights/point_light.h"
#include "lights/spot_light.h"
#include "scene/mesh_loader.h"

namespace caustic {
namespace {

const std::vector<std::string> kLightTypes{"point", "spot", "directional"};

// A photometric quantity in lumens-based units to radiometric watts: 683 lm/W at 555 nm, the
// conversion glTF's KHR_lights_punctual names.
constexpr float kLumensPerWatt = 683.0f;

// A point or spot light's intensity: "intensity" in W/sr per channel, or "candela" (lm/sr) times
// a "color" (glTF's KHR_lights_punctual).
Color readIntensity(JsonObject& o, const char* photometric) {
    if (o.find(photometric)) {
        if (o.find("intensity"))
            throw InputError(
                o.pathOf("intensity"),
                std::string("give either intensity or color and ") + photometric + ", not both");
        const float value = o.number(photometric);
        if (!(value >= 0.0f)) throw InputError(o.pathOf(photometric), "must be >= 0");
        return o.color("color", Color(1.0f)) * (value / kLumensPerWatt);
    }
    return o.color("intensity");
}

// A direction vector of non-zero length.
Vec3 readDirection(JsonObject& o, const std::string& key) {
    const Vec3 d = o.vec3(key);
    if (!(glm::dot(d, d) > 0.0f)) throw InputError(o.pathOf(key), "must not be zero");
    return d;
}

float readAngle(JsonObject& o, const std::string& key, float fallback) {
    const float degrees = o.number(key, fallback);
    if (!(degrees >= 0.0f && degrees <= 90.0f))
        throw InputError(o.pathOf(key), "must be in [0, 90] degrees");
    return degrees;
}

}  // namespace

void readLight(const Json& j, const std::string& path, const Frame& frame, const Bounds3& bounds,
               Scene& scene) {
    JsonObject o(j, path);
    const std::string type = o.choice("type", kLightTypes);
    if (type == "point") {
        const Vec3 position = frame.point(o, "position");
        scene.lights.push_back(std::make_unique<PointLight>(position, readIntensity(o, "candela")));
    } else if (type == "spot") {
        const Vec3 position = frame.point(o, "position");
        const Vec3 direction = readDirection(o, "direction");
        const Color intensity = readIntensity(o, "candela");
        const float inner = readAngle(o, "inner_angle", 0.0f);
        const float outer = readAngle(o, "outer_angle", 45.0f);
        if (!(outer > 0.0f)) throw InputError(o.pathOf("outer_angle"), "must be > 0");
        if (inner > outer) throw InputError(o.pathOf("inner_angle"), "must be <= outer_angle");
        scene.lights.push_back(
            std::make_unique<SpotLight>(position, direction, intensity, inner, outer));
    } else {
        const Vec3 direction = readDirection(o, "direction");
        Color irradiance;
        if (o.find("lux")) {
            if (o.find("irradiance"))
                throw InputError(o.pathOf("irradiance"),
                                 "give either irradiance or color and lux, not both");
            const float lux = o.number("lux");
            if (!(lux >= 0.0f)) throw InputError(o.pathOf("lux"), "must be >= 0");
            irradiance = o.color("color", Color(1.0f)) * (lux / kLumensPerWatt);
        } else {
            irradiance = o.color("irradiance");
        }
        scene.lights.push_back(std::make_unique<DirectionalLight>(direction, irradiance, bounds));
    }
    o.finish();
}

void readEnvironment(const Json& j, const std::string& path, const SceneOptions& options,
                     const Bounds3& bounds, Scene& scene) {
    JsonObject o(j, path);
    const float strength = o.number("strength", 1.0f);
    if (!(strength >= 0.0f)) throw InputError(o.pathOf("strength"), "must be >= 0");
    const float rotation = o.number("rotation", 0.0f);
    const bool hasColor = o.find("color") != nullptr, hasFile = o.find("file") != nullptr;
    if (hasColor == hasFile)
        throw InputError(path,
                         "an environment needs \"color\" or \"file\" (an EXR or HDR image "
                         "in the assets folder), not both");
    std::unique_ptr<EnvironmentLight> light;
    if (hasColor) {
        if (o.find("rotation")) throw InputError(o.pathOf("rotation"), "applies to a file only");
        light = std::make_unique<EnvironmentLight>(o.color("color") * strength, bounds);
    } else {
        const std::string name = o.string("file");
        const std::string at = o.pathOf("file");
        std::string extension = std::filesystem::path(name).extension().string();
        std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
        if (extension != ".exr" && extension != ".hdr")
            throw InputError(at, "must be an EXR or HDR (Radiance) image, got \"" + name + "\"");
        const std::filesystem::path file = resolveAsset(options.assetsDir, name, at);
        try {
            if (options.countMeshesOnly) {
                // Admission: the size alone, for the memory estimate; a stand-in light, so that
                // the scene counts as lit.
                const ImageSize size = readImageSize(file, options.maxPixels);
                scene.environmentBytes = EnvironmentLight::bytesFor(size.width, size.height);
                light = std::make_unique<EnvironmentLight>(Color(1.0f), bounds);
            } else {
                RgbImage image = readImage(file, options.maxPixels);
                const auto bad =
                    std::find_if(image.pixels.begin(), image.pixels.end(),
                                 [](float v) { return !(v >= 0.0f && v < kInfinity); });
                if (bad != image.pixels.end()) {
                    const size_t texel = size_t(bad - image.pixels.begin()) / 3;
                    throw InputError(at, "texel (" + std::to_string(texel % image.width) + ", " +
                                             std::to_string(texel / image.width) +
                                             ") is negative or not finite");
                }
                const auto start = Interrupt::Clock::now();
                light = std::make_unique<EnvironmentLight>(std::move(image), rotation, strength,
                                                           bounds);
                scene.environmentBytes = light->memoryBytes();
                scene.built.add("environment distribution", secondsSince(start),
                                scene.environmentBytes);
            }
        } catch (const InputError&) {
            throw;
        } catch (const std::runtime_error& e) {
            throw InputError(at, e.what());
        }
    }
    o.finish();
    scene.environment = light.get();
    scene.environmentIndex = scene.lights.size();
    scene.lights.push_back(std::move(light));
}

}  // namespace caustic
