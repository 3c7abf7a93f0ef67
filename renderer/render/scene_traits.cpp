#include "render/scene_traits.h"

#include <optional>
#include <vector>

#include "lights/directional_light.h"
#include "scene/scene.h"

namespace caustic {

SceneTraits sceneTraits(const Scene& scene) {
    SceneTraits t;
    std::vector<char> used(scene.materials.size(), 0);
    for (uint32_t prim = 0; prim < scene.geometry.size(); ++prim)
        used[scene.geometry.material(prim)] = 1;
    for (const Scene::CountedMesh& mesh : scene.countedMeshes) used[mesh.material] = 1;
    for (size_t i = 0; i < used.size(); ++i) {
        if (!used[i]) continue;
        const Material& m = *scene.materials[i];
        const std::optional<Color> lambertian = m.lambertian();
        if (m.isEmissive() && lambertian && isBlack(*lambertian))
            continue;  // a lamp that reflects nothing
        if (m.isSpecular())
            t.specular = true;
        else if (m.lobeRoughness() >= 1.0f)
            t.diffuse = true;
        else
            t.glossy = true;
    }
    float distant = 0.0f;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& light = *scene.lights[i];
        const float power = luminance(light.power());
        t.totalPower += power;
        if ((scene.environment && i == scene.environmentIndex) ||
            dynamic_cast<const DirectionalLight*>(&light))
            distant += power;
    }
    t.distantShare = t.totalPower > 0.0f ? distant / t.totalPower : 0.0f;
    return t;
}

}  // namespace caustic
