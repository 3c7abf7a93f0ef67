// Scene JSON -> Scene, validated strictly (DESIGN.md, "Scene format").
#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "lights/area_light.h"
#include "materials/conductor.h"
#include "materials/dielectric.h"
#include "materials/diffuse.h"
#include "materials/metallic_roughness.h"
#include "materials/mirror.h"
#include "materials/mixed_material.h"
#include "materials/rough_dielectric.h"
#include "materials/textured_metallic_roughness.h"
#include "scene/json_reader.h"
#include "scene/light_loader.h"
#include "scene/mesh_file.h"
#include "scene/mesh_loader.h"
#include "scene/mesh_tangents.h"
#include "scene/scene.h"
#include "scene/texture_loader.h"

namespace caustic {
namespace {

const std::vector<std::string> kMaterialTypes{"diffuse", "mirror", "dielectric", "conductor",
                                              "metallic_roughness"};
const std::vector<std::string> kShapeTypes{"sphere", "quad", "triangle", "mesh"};

// A reflectance in [0, 1] per channel: anything above 1 would create energy.
Color readReflectance(JsonObject& o, const std::string& key, const Color& fallback) {
    Color c = o.color(key, fallback);
    for (int i = 0; i < 3; ++i)
        if (c[i] > 1.0f)
            throw InputError(jsonPointer(o.pathOf(key), size_t(i)),
                             "must be <= 1 (energy conservation)");
    return c;
}

Camera readCamera(const Json& j, const SceneOptions& options, Frame& frame) {
    JsonObject o(j, "/camera");
    frame.origin = readDVec3(o.require("position"), o.pathOf("position"));
    Vec3 position(0.0f);
    Vec3 lookAt = frame.point(o, "look_at");
    Vec3 up = o.vec3("up", Vec3(0.0f, 1.0f, 0.0f));
    float fov = o.number("fov", 40.0f);
    int64_t width = o.find("width") ? readInteger(j["width"], o.pathOf("width")) : 512;
    int64_t height = o.find("height") ? readInteger(j["height"], o.pathOf("height")) : 512;
    o.finish();
    if (!(fov > 0.0f && fov < 180.0f))
        throw InputError(o.pathOf("fov"), "must be in (0, 180) degrees");
    checkResolution(width, height, options, o.pathOf("width"), o.pathOf("height"));
    Vec3 forward = lookAt - position;
    if (glm::dot(forward, forward) == 0.0f)
        throw InputError(o.pathOf("look_at"), "must differ from position");
    Vec3 side = glm::cross(glm::normalize(forward), up);
    if (!(glm::length(side) > 1e-6f * glm::length(up)))
        throw InputError(o.pathOf("up"), "must not be zero or parallel to the viewing direction");
    return Camera(position, lookAt, up, fov, static_cast<int>(width), static_cast<int>(height));
}

// A microfacet surface's perceptual roughness, in [0, 1]; 0 when absent (smooth).
float readRoughness(JsonObject& o) {
    const float roughness = o.number("roughness", 0.0f);
    if (!(roughness >= 0.0f && roughness <= 1.0f))
        throw InputError(o.pathOf("roughness"), "must be in [0, 1]");
    return roughness;
}

// A metal: its roughness, and its Fresnel term from either f0 or a complex index eta + i k.
std::unique_ptr<Material> readConductor(JsonObject& o, const Color& emission) {
    const float roughness = readRoughness(o);
    const bool byIor = o.find("eta") || o.find("k");
    if (byIor && o.find("f0"))
        throw InputError(o.pathOf("f0"), "give either f0 or eta and k, not both");
    ConductorFresnel fresnel = ConductorFresnel::fromF0(readReflectance(o, "f0", Color(1.0f)));
    if (byIor) {
        const Color eta = o.color("eta"), k = o.color("k", Color(0.0f));
        for (int c = 0; c < 3; ++c)
            if (!(eta[c] > 0.0f))
                throw InputError(jsonPointer(o.pathOf("eta"), size_t(c)), "must be > 0");
        fresnel = ConductorFresnel::fromComplexIor(eta, k);
    }
    const bool multipleScattering = o.boolean("multiple_scattering", true);
    return std::make_unique<Conductor>(roughness, fresnel, multipleScattering, emission);
}

// glTF's alpha: "alpha_mode" opaque (default), mask or blend; "alpha" and "alpha_cutoff" in [0, 1].
void readAlpha(JsonObject& o, TexturedMetallicRoughness::Inputs& in) {
    const std::string mode = o.choice("alpha_mode", {"opaque", "mask", "blend"}, "opaque");
    in.alphaMode = mode == "mask"    ? AlphaMode::Mask
                   : mode == "blend" ? AlphaMode::Blend
                                     : AlphaMode::Opaque;
    in.alpha = o.number("alpha", 1.0f);
    if (!(in.alpha >= 0.0f && in.alpha <= 1.0f))
        throw InputError(o.pathOf("alpha"), "must be in [0, 1]");
    if (o.find("alpha_cutoff")) {
        if (in.alphaMode != AlphaMode::Mask)
            throw InputError(o.pathOf("alpha_cutoff"), "applies to \"alpha_mode\": \"mask\" only");
        in.alphaCutoff = o.number("alpha_cutoff");
        if (!(in.alphaCutoff >= 0.0f && in.alphaCutoff <= 1.0f))
            throw InputError(o.pathOf("alpha_cutoff"), "must be in [0, 1]");
    }
}

// glTF's metallic-roughness material, with its optional textures (textured_metallic_roughness.h).
std::unique_ptr<Material> readMetallicRoughness(JsonObject& o, const Color& emission,
                                                const SceneOptions& options, Scene& scene) {
    // glTF 2.0's defaults: white, fully metallic, fully rough.
    TexturedMetallicRoughness::Inputs in;
    in.baseColor = readReflectance(o, "base_color", Color(1.0f));
    in.metallic = o.number("metallic", 1.0f);
    if (!(in.metallic >= 0.0f && in.metallic <= 1.0f))
        throw InputError(o.pathOf("metallic"), "must be in [0, 1]");
    in.roughness = o.find("roughness") ? readRoughness(o) : 1.0f;
    in.multipleScattering = o.boolean("multiple_scattering", true);
    in.emission = emission;
    in.baseColorTexture =
        readTexture(o, "base_color_texture", TextureEncoding::Srgb, options, scene);
    in.metallicRoughnessTexture =
        readTexture(o, "metallic_roughness_texture", TextureEncoding::Linear, options, scene);
    in.normalTexture =
        readTexture(o, "normal_texture", TextureEncoding::Linear, options, scene, &in.normalScale);
    in.emissiveTexture = readTexture(o, "emissive_texture", TextureEncoding::Srgb, options, scene);
    readAlpha(o, in);
    in.ior = o.number("ior", 1.5f);
    if (!(in.ior >= 1.0f && in.ior <= 10.0f))
        throw InputError(o.pathOf("ior"), "must be in [1, 10]");
    const float transmission = o.number("transmission", 0.0f);
    if (!(transmission >= 0.0f && transmission <= 1.0f))
        throw InputError(o.pathOf("transmission"), "must be in [0, 1]");
    const bool textured = in.baseColorTexture.named || in.metallicRoughnessTexture.named ||
                          in.normalTexture.named || in.emissiveTexture.named ||
                          in.alphaMode != AlphaMode::Opaque;
    if (textured && transmission > 0.0f)
        throw InputError(o.pathOf("transmission"),
                         "cannot be combined with textures or alpha yet; use an untextured "
                         "material for a transmissive surface");
    if (textured) return std::make_unique<TexturedMetallicRoughness>(in, scene.textures);
    auto surface = std::make_unique<MetallicRoughness>(in.baseColor, in.metallic, in.roughness,
                                                       in.multipleScattering, emission, in.ior);
    const float weight = (1.0f - in.metallic) * transmission;
    if (!(weight > 0.0f)) return surface;
    // Smooth glass (glTF's usual glass: transmission 1, roughness 0) is a smooth interface, not a
    // microfacet one of the smallest roughness: one of alpha 0.0009 would take point lights by
    // light sampling through a lobe a million times its mean, a few enormous samples in millions.
    if (weight >= 1.0f && in.roughness < MetallicRoughness::kMinRoughness)
        return std::make_unique<Dielectric>(in.ior, FresnelModel::Schlick, in.baseColor, emission);
    // KHR_materials_transmission: the dielectric's diffuse gives way to a rough refraction
    // tinted by the base colour, its Fresnel term Schlick's as the specification's.
    auto glass =
        std::make_unique<RoughDielectric>(std::max(in.roughness, MetallicRoughness::kMinRoughness),
                                          in.ior, FresnelModel::Schlick, in.baseColor, Color(0.0f));
    return std::make_unique<MixedMaterial>(std::move(surface), std::move(glass), weight);
}

std::unique_ptr<Material> readMaterial(const Json& j, const std::string& path,
                                       const SceneOptions& options, Scene& scene) {
    JsonObject o(j, path);
    std::string type = o.choice("type", kMaterialTypes);
    Color emission = o.color("emission", Color(0.0f));
    std::unique_ptr<Material> m;
    if (type == "diffuse") {
        m = std::make_unique<Diffuse>(readReflectance(o, "albedo", Color(0.8f)), emission);
    } else if (type == "mirror") {
        m = std::make_unique<Mirror>(readReflectance(o, "reflectance", Color(1.0f)), emission);
    } else if (type == "conductor") {
        m = readConductor(o, emission);
    } else if (type == "metallic_roughness") {
        m = readMetallicRoughness(o, emission, options, scene);
    } else {
        float ior = o.number("ior", 1.5f);
        if (!(ior > 0.0f)) throw InputError(o.pathOf("ior"), "must be > 0");
        std::string fresnel = o.choice("fresnel", {"exact", "schlick"}, "exact");
        Color tint = readReflectance(o, "tint", Color(1.0f));
        const float roughness = readRoughness(o);
        const FresnelModel model = fresnel == "exact" ? FresnelModel::Exact : FresnelModel::Schlick;
        if (roughness < Conductor::kSmoothRoughness)
            m = std::make_unique<Dielectric>(ior, model, tint, emission);
        else
            m = std::make_unique<RoughDielectric>(roughness, ior, model, tint, emission);
    }
    o.finish();
    return m;
}

uint32_t readMaterialRef(JsonObject& o, const Scene& scene) {
    std::string name = o.string("material");
    for (size_t i = 0; i < scene.materialNames.size(); ++i)
        if (scene.materialNames[i] == name) return static_cast<uint32_t>(i);
    std::string valid;
    for (const std::string& n : scene.materialNames) valid += (valid.empty() ? "" : ", ") + n;
    throw InputError(o.pathOf("material"), "unknown material \"" + name + "\"; valid: " +
                                               (valid.empty() ? "(none defined)" : valid));
}

MeshTransform readTransform(const Json& j, const std::string& path, const Frame& frame) {
    JsonObject o(j, path);
    MeshTransform t;
    if (const Json* s = o.find("scale")) {
        t.scale = s->is_number() ? Vec3(readNumber(*s, o.pathOf("scale")))
                                 : readVec3(*s, o.pathOf("scale"));
        for (int i = 0; i < 3; ++i)
            if (!(t.scale[i] != 0.0f)) throw InputError(o.pathOf("scale"), "must not be zero");
    }
    t.rotateDegrees = o.vec3("rotate", Vec3(0.0f));
    const Json* translate = o.find("translate");
    t.translate = translate ? frame.point(*translate, o.pathOf("translate")) : Vec3(-frame.origin);
    o.finish();
    return t;
}

// An uploaded mesh's id: the SHA-256 of its bytes in lowercase hexadecimal.
bool isAssetId(const std::string& id) {
    return id.size() == 64 && std::all_of(id.begin(), id.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
           });
}

// A loaded mesh into the scene, with the attributes its material reads: texture coordinates for
// a textured one (loaded only then), and tangents (MikkTSpace's) for a normal map.
void addMesh(TriangleMesh mesh, uint32_t material, Scene& scene) {
    const Material& m = *scene.materials[material];
    std::vector<glm::vec4> tangents;
    if (m.needsTangents()) {
        const auto start = Interrupt::Clock::now();
        tangents = generateTangents(mesh);
        scene.built.add("tangent frames", secondsSince(start), tangents.size() * sizeof(glm::vec4));
    }
    scene.geometry.addTriangles(mesh.positions, mesh.triangles, material, mesh.normals,
                                mesh.texcoords, tangents);
}

// A mesh from exactly one of "file" (an OBJ in the assets folder), "asset" (an uploaded mesh) or
// "embedded" (an imported model's).
void readMesh(JsonObject& o, uint32_t material, Scene& scene, const SceneOptions& options,
              const Frame& frame) {
    const Json* fileField = o.find("file");
    const Json* assetField = o.find("asset");
    const Json* embeddedField = o.find("embedded");
    if (int(!!fileField) + int(!!assetField) + int(!!embeddedField) > 1)
        throw InputError(o.path(),
                         "a mesh has one of \"file\", \"asset\" and \"embedded\", not two");
    if (!fileField && !assetField && !embeddedField)
        throw InputError(o.path(),
                         "a mesh needs \"file\" (an OBJ in the assets folder) or "
                         "\"asset\" (an uploaded mesh's id)");
    // Without a transform the mesh stays where its file puts it, relative to the camera.
    MeshTransform transform;
    transform.translate = Vec3(-frame.origin);
    if (const Json* t = o.find("transform"))
        transform = readTransform(*t, o.pathOf("transform"), frame);
    if (embeddedField) {
        const EmbeddedData::Mesh& embedded =
            embeddedItem(o, options.embedded, &EmbeddedData::meshes, "mesh");
        if (options.countMeshesOnly) {
            scene.countedMeshes.push_back({embedded.counts, material});
            return;
        }
        TriangleMesh placed = embedded.mesh;
        for (Vec3& p : placed.positions) p = transform.apply(p);
        for (Vec3& n : placed.normals) n = transform.applyToNormal(n);
        if (!scene.materials[material]->isTextured()) placed.texcoords.clear();
        addMesh(std::move(placed), material, scene);
        return;
    }
    const std::string key = fileField ? "file" : "asset";
    const bool textured = scene.materials[material]->isTextured();
    const std::string at = o.pathOf(key);
    const std::string name = o.string(key);

    if (fileField) {
        std::filesystem::path full = resolveAsset(options.assetsDir, name, at);
        if (options.countMeshesOnly) {
            MeshCounts counts =
                options.meshCounts ? options.meshCounts->counts(full, at) : countObj(full, at);
            scene.countedMeshes.push_back({counts, material});
        } else {
            addMesh(loadObj(full, transform, at, textured), material, scene);
        }
        return;
    }
    if (!isAssetId(name))
        throw InputError(at,
                         "must be an asset id: 64 lowercase hexadecimal digits (the SHA-256 "
                         "of the file)");
    if (!options.resolveMeshAsset)
        throw InputError(at, "this renderer has no asset store; use \"file\"");
    // Admission counts from what the upload stored; only a render reads the bytes.
    MeshAsset asset = options.resolveMeshAsset(name, at, !options.countMeshesOnly);
    if (options.countMeshesOnly) {
        scene.countedMeshes.push_back({asset.counts, material});
        return;
    }
    if (!asset.bytes) throw InputError(at, "the asset store gave no bytes for asset " + name);
    addMesh(parseMeshBytes(*asset.bytes, asset.format, transform, "asset " + name, at,
                           uint64_t(1) << 25, textured),
            material, scene);
}

void readShape(const Json& j, const std::string& path, Scene& scene, const SceneOptions& options,
               const Frame& frame) {
    JsonObject o(j, path);
    std::string type = o.choice("type", kShapeTypes);
    uint32_t material = readMaterialRef(o, scene);
    if (type == "sphere") {
        Vec3 center = frame.point(o, "center");
        float radius = o.positive("radius");
        bool flipped = o.boolean("flip_normals", false);
        scene.geometry.addSphere(Sphere{center, radius, flipped}, material);
    } else if (type == "quad") {
        Vec3 origin = frame.point(o, "origin"), u = o.vec3("u"), v = o.vec3("v");
        if (!(glm::length(glm::cross(u, v)) > 0.0f))
            throw InputError(o.pathOf("v"),
                             "must not be zero or parallel to u (the quad has no area)");
        scene.geometry.addQuad(origin, u, v, material);
    } else if (type == "triangle") {
        const Json& vs = o.require("vertices");
        std::string at = o.pathOf("vertices");
        if (!vs.is_array() || vs.size() != 3)
            throw InputError(at, "expected an array of 3 points, got " +
                                     (vs.is_array() ? "an array of " + std::to_string(vs.size())
                                                    : jsonTypeName(vs)));
        std::vector<Vec3> p;
        for (size_t i = 0; i < 3; ++i) p.push_back(frame.point(vs[i], jsonPointer(at, i)));
        if (!(glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) > 0.0f))
            throw InputError(at, "the triangle has no area");
        scene.geometry.addTriangles(p, {glm::uvec3(0, 1, 2)}, material);
    } else {
        readMesh(o, material, scene, options, frame);
    }
    o.finish();
}

const Json& requireArray(JsonObject& o, const std::string& key) {
    const Json& a = o.require(key);
    if (!a.is_array()) throw InputError(o.pathOf(key), "expected an array, got " + jsonTypeName(a));
    return a;
}

}  // namespace

void checkResolution(int64_t width, int64_t height, const SceneOptions& options,
                     const std::string& widthPath, const std::string& heightPath) {
    for (auto [path, v] : {std::pair{&widthPath, width}, std::pair{&heightPath, height}})
        if (v < 1 || v > options.maxResolution)
            throw InputError(*path, "must be in [1, " + std::to_string(options.maxResolution) +
                                        "], got " + std::to_string(v));
    if (width * height > options.maxPixels)
        throw InputError(widthPath, "width x height must be at most " +
                                        std::to_string(options.maxPixels) + " pixels");
}

std::unique_ptr<Scene> loadScene(const Json& doc, const SceneOptions& options) {
    // Before anything copies a part of it (the settings; issue 12, bug 3).
    checkJsonDepth(doc, "");
    auto scene = std::make_unique<Scene>();
    JsonObject root(doc, "");
    Frame frame;
    scene->camera = readCamera(root.require("camera"), options, frame);

    // Materials first: shapes refer to them by name.
    const Json& materials = root.require("materials");
    JsonObject materialsObject(materials, "/materials");
    for (auto it = materials.begin(); it != materials.end(); ++it) {
        materialsObject.find(it.key());
        scene->materials.push_back(
            readMaterial(it.value(), jsonPointer("/materials", it.key()), options, *scene));
        scene->materialNames.push_back(it.key());
        scene->hasAlpha = scene->hasAlpha || scene->materials.back()->hasAlpha();
    }

    const Json& shapes = requireArray(root, "shapes");
    for (size_t i = 0; i < shapes.size(); ++i)
        readShape(shapes[i], jsonPointer("/shapes", i), *scene, options, frame);

    // Lights at infinity (directional, environment) send photons in through the scene's
    // bounding sphere.
    const Bounds3 bounds = scene->geometry.bounds();
    if (root.find("lights")) {
        const Json& lights = requireArray(root, "lights");
        for (size_t i = 0; i < lights.size(); ++i)
            readLight(lights[i], jsonPointer("/lights", i), frame, bounds, *scene);
    }
    if (const Json* environment = root.find("environment")) {
        if (root.find("background"))
            throw InputError("/background", "give either background or environment, not both");
        readEnvironment(*environment, "/environment", options, bounds, *scene);
    }
    scene->background = root.color("background", Color(0.0f));
    if (const Json* settings = root.find("settings")) {
        if (!settings->is_object())
            throw InputError("/settings", "expected an object, got " + jsonTypeName(*settings));
        scene->settings = *settings;
    }
    root.finish();
    scene->geometry.shrinkToFit();

    // Every emissive primitive is an area light.
    scene->firstAreaLight = scene->lights.size();
    for (uint32_t prim = 0; prim < scene->geometry.size(); ++prim) {
        const Material& m = scene->material(prim);
        if (!m.isEmissive()) continue;
        scene->lights.push_back(std::make_unique<AreaLight>(
            scene->geometry, prim, m.averageEmission(), m.isTextured() ? &m : nullptr));
        scene->emitterPrims.push_back(prim);
    }
    const auto start = Interrupt::Clock::now();
    if (!scene->lights.empty()) scene->lightSampler = LightSampler(scene->lights);
    scene->directLights = LocalLightSampler(
        scene->lights, scene->environment ? scene->environmentIndex : scene->lights.size(),
        scene->lightSampler);
    if (!scene->lights.empty())
        scene->built.add("light tables", secondsSince(start),
                         scene->lightTableBytes() - scene->environmentBytes);
    return scene;
}

std::optional<size_t> Scene::areaLightOf(uint32_t prim) const {
    auto it = std::lower_bound(emitterPrims.begin(), emitterPrims.end(), prim);
    if (it == emitterPrims.end() || *it != prim) return std::nullopt;
    return firstAreaLight + size_t(it - emitterPrims.begin());
}

Json parseJson(const std::string& text) {
    try {
        return Json::parse(text);
    } catch (const Json::exception& e) {
        // nlohmann's text is "[json.exception.parse_error.101] parse error at line L, column C:
        // ...", or "[json.exception.out_of_range.406] number overflow parsing '1e400'".
        std::string what = e.what();
        size_t at = what.find("] ");
        throw InputError("",
                         "invalid JSON: " + (at == std::string::npos ? what : what.substr(at + 2)));
    }
}

Json readJsonFile(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError("", "cannot open " + file.string());
    std::ostringstream text;
    text << in.rdbuf();
    return parseJson(text.str());
}

}  // namespace caustic
