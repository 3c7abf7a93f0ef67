// What a scene holds that decides how to render it fastest: the `auto` preset's inputs
// (render/presets.h). Read from a loaded scene, or from one loaded for admission (its meshes
// counted, not loaded): materials in use, and where the light comes from.
#pragma once

#include <string>

namespace caustic {

struct Scene;

struct SceneTraits {
    /// Some surface is a mirror or smooth glass (every lobe a delta): it makes caustics, which
    /// a path tracer finds only by chance from small lights.
    bool specular = false;
    /// Some surface has a diffuse lobe: light bounces between such surfaces (interreflection).
    bool diffuse = false;
    /// Some surface is glossy (microfacet lobes only, rough but below fully diffuse).
    bool glossy = false;
    /// The share of the emitted power (luminance) from light at infinity: the environment and
    /// directional lights. Photons from there spread over the whole scene's disk, most far from
    /// what the camera sees.
    float distantShare = 0.0f;
    /// Luminance of every light's power together; 0 when nothing emits.
    float totalPower = 0.0f;

    /// The local lights' photons land where the camera looks, and there are any.
    bool localLight() const { return totalPower > 0.0f && distantShare < 0.5f; }
};

SceneTraits sceneTraits(const Scene& scene);

}  // namespace caustic
