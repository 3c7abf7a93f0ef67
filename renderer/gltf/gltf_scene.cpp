#include "gltf/gltf_scene.h"

#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "gltf/gltf_accessors.h"
#include "gltf/gltf_draco.h"
#include "gltf/gltf_materials.h"
#include "gltf/gltf_meshes.h"
#include "gltf/gltf_nodes.h"
#include "gltf/gltf_values.h"

namespace caustic {
namespace {

constexpr double kPiDouble = 3.14159265358979323846;  // core/math.h's kPi is a float
constexpr double kInf = std::numeric_limits<double>::infinity();
// The largest value a float holds: what a scene may carry.
constexpr double kFloatMax = 3.0e38;

// The automatic camera's defaults: the front of an asset faces +z (glTF 2.0, "Coordinate System
// and Units"), seen from a little to its right and above.
constexpr double kAutoAzimuth = 30.0, kAutoElevation = 20.0, kAutoFov = 40.0;
// With no light in the file: a constant white environment, the neutral studio light of glTF
// viewers (every direction lit alike; a white diffuse surface reflects radiance 1).
const Json kDefaultEnvironment = {{"color", {1.0, 1.0, 1.0}}};

// "a, b" + ", c".
void appendListed(std::string& list, const std::string& item) {
    if (!list.empty()) list += ", ";
    list += item;
}

Json vec(const glm::dvec3& v) {
    return {v.x, v.y, v.z};
}

// The image size for a camera of aspect ratio `aspect` (width / height; 0: unknown, 4:3) and a
// long side of `longSide`.
std::pair<int, int> sizeFor(double aspect, int longSide) {
    if (!(aspect > 0.0)) aspect = 4.0 / 3.0;
    if (aspect >= 1.0) return {longSide, std::max(1, int(std::lround(longSide / aspect)))};
    return {std::max(1, int(std::lround(longSide * aspect))), longSide};
}

class Importer {
public:
    Importer(const GltfFile& file, const GltfImportOptions& options, const MeshErrors& errors)
        : file_(file), doc_(file.doc), options_(options), errors_(errors), values_(errors) {}

    GltfScene run() {
        checkExtensions();
        const std::vector<NodeInstance> nodes = walkNodes(file_.model, errors_);
        GltfMaterials materials(file_, *out_.embedded, options_, errors_, out_.warnings);
        readMeshes(nodes, materials);
        readCameras(nodes);
        Json lights = readLights(nodes);
        out_.scene = {{"materials", materials.materials}, {"shapes", shapes_}};
        if (!lights.empty()) out_.scene["lights"] = lights;
        const bool emits = std::any_of(materials.materials.begin(), materials.materials.end(),
                                       [](const Json& m) { return m.contains("emission"); });
        if (lights.empty() && !emits) out_.scene["environment"] = kDefaultEnvironment;
        summarize(nodes, materials, lights.size());
        return std::move(out_);
    }

private:
    void warn(const std::string& what) { out_.warnings.push_back(what); }

    // A required extension the importer does not read is an error; a used one a warning.
    void checkExtensions() {
        const std::vector<std::string>& known = supportedGltfExtensions();
        auto isKnown = [&](const std::string& e) {
            return std::find(known.begin(), known.end(), e) != known.end();
        };
        for (const Json& e : values_.array(doc_, "extensionsRequired", "the file"))
            if (!e.is_string() || !isKnown(e.get<std::string>()))
                errors_.fail("the file requires the extension " + e.dump().substr(0, 80) +
                             ", which Caustic does not support (it reads " + list(known) + ")");
        for (const Json& e : values_.array(doc_, "extensionsUsed", "the file"))
            if (e.is_string() && !isKnown(e.get<std::string>()))
                warn("the extension " + e.get<std::string>() + " is not supported; ignored");
    }

    static std::string list(const std::vector<std::string>& names) {
        std::string out;
        for (const std::string& n : names) appendListed(out, n);
        return out;
    }

    void readMeshes(const std::vector<NodeInstance>& nodes, GltfMaterials& materials) {
        draws_ = gltfDraws(file_.model, nodes, errors_);
        for (const std::string& s : draws_.skipped) warn(s);
        if (draws_.draws.empty())
            errors_.fail("has no triangles (no node of the scene has a triangle mesh)");
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (const GltfDraw& draw : draws_.draws) {
            const std::string material = materials.use(draw.material);
            EmbeddedData::Mesh mesh;
            mesh.name = gltfObjectName("node", draw.instance.node,
                                       file_.model.nodes[draw.instance.node].name) +
                        " mesh " + std::to_string(draw.mesh) + " primitive " +
                        std::to_string(draw.primitive);
            mesh.counts = {draw.vertices, draw.triangles, draw.normals, draw.texcoords};
            if (options_.countOnly) {
                accessorBounds(draw, lo, hi);
            } else {
                mesh.mesh = readDraw(file_.model, draw, MeshTransform{}, true, errors_);
                for (const Vec3& p : mesh.mesh.positions) {
                    lo = glm::min(lo, p);
                    hi = glm::max(hi, p);
                }
            }
            shapes_.push_back({{"type", "mesh"},
                               {"embedded", out_.embedded->meshes.size()},
                               {"material", material}});
            out_.embedded->meshes.push_back(std::move(mesh));
        }
        // No finite point at all (every position off a float's range): a box at the origin.
        out_.boundsMin = lo.x <= hi.x ? lo : glm::vec3(0.0f);
        out_.boundsMax = lo.x <= hi.x ? hi : glm::vec3(0.0f);
    }

    // The world box of a draw's POSITION min and max (glTF requires them; normalized integers
    // scaled as their values are), its 8 corners transformed; without them, its positions read.
    void accessorBounds(const GltfDraw& draw, glm::vec3& lo, glm::vec3& hi) const {
        const tinygltf::Primitive& prim = file_.model.meshes[draw.mesh].primitives[draw.primitive];
        const int position = prim.attributes.at("POSITION");
        const tinygltf::Accessor& a = file_.model.accessors[size_t(position)];
        auto add = [&](const glm::dvec3& p) {
            const glm::vec3 w(draw.instance.world * glm::dvec4(p, 1.0));
            if (!isFinite(w)) return;
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        };
        if (a.minValues.size() != 3 || a.maxValues.size() != 3) {
            if (!dracoExtension(prim))
                for (const Vec3& p :
                     readVec3s(file_.model, position, AccessorUse::Positions, errors_))
                    add(glm::dvec3(p));
            return;
        }
        double scale = 1.0;  // glTF 2.0, "Animations": the normalized integers' divisors
        if (a.normalized)
            scale = a.componentType == TINYGLTF_COMPONENT_TYPE_BYTE             ? 1.0 / 127
                    : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE  ? 1.0 / 255
                    : a.componentType == TINYGLTF_COMPONENT_TYPE_SHORT          ? 1.0 / 32767
                    : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 1.0 / 65535
                                                                                : 1.0;
        for (int corner = 0; corner < 8; ++corner) {
            glm::dvec3 p;
            for (int i = 0; i < 3; ++i)
                p[i] =
                    scale * ((corner >> i & 1) ? a.maxValues[size_t(i)] : a.minValues[size_t(i)]);
            add(p);
        }
    }

    // Position, forward (-z) and up (+y) of a node's world transform.
    struct Pose {
        glm::dvec3 position, forward, up;
    };
    // Every coordinate finite and within a float's range (positions are stored as floats).
    static bool finitePose(const Pose& p) {
        for (const glm::dvec3& v : {p.position, p.forward, p.up})
            for (int i = 0; i < 3; ++i)
                if (!(std::abs(v[i]) <= kFloatMax)) return false;
        return true;
    }
    static Pose poseOf(const glm::dmat4& world) {
        const glm::dmat3 m(world);
        return {glm::dvec3(world[3]), glm::normalize(m * glm::dvec3(0, 0, -1)),
                glm::normalize(m * glm::dvec3(0, 1, 0))};
    }

    void readCameras(const std::vector<NodeInstance>& nodes) {
        const Json& cameras = values_.array(doc_, "cameras", "the file");
        for (const NodeInstance& n : nodes) {
            const int c = file_.model.nodes[n.node].camera;
            if (c < 0) continue;
            const std::string nodeAt =
                gltfObjectName("node", n.node, file_.model.nodes[n.node].name);
            if (size_t(c) >= cameras.size())
                errors_.fail(nodeAt + ": camera " + std::to_string(c) + " does not exist (" +
                             std::to_string(cameras.size()) + " cameras)");
            const Json& camera = cameras[size_t(c)];
            const std::string name = textOf(camera, "name");
            const std::string at = gltfObjectName("camera", size_t(c), name);
            const std::string type = values_.string(camera, "type", "", at);
            if (type != "perspective") {
                warn(at + ": a " + (type.empty() ? std::string("camera without a type") : type) +
                     " camera is not read (only perspective ones are)");
                continue;
            }
            const Json& p = values_.object(camera, "perspective", at);
            const double yfov =
                values_.number(p, "yfov", kInf, 1e-6, kPiDouble - 1e-6, at + ": perspective");
            if (std::isinf(yfov)) errors_.fail(at + ": perspective has no yfov");
            const double aspect =
                values_.number(p, "aspectRatio", 0.0, 1e-6, 1e6, at + ": perspective");
            const Pose pose = poseOf(n.world);
            if (!finitePose(pose))
                errors_.fail(nodeAt + ": its transform gives camera " + std::to_string(c) +
                             " no direction");
            const auto [width, height] = sizeFor(aspect, options_.width);
            Json scene{{"position", vec(pose.position)},
                       {"look_at", vec(pose.position + pose.forward)},
                       {"up", vec(pose.up)},
                       {"fov", yfov * 180.0 / kPiDouble},
                       {"width", width},
                       {"height", height}};
            out_.cameras.push_back(
                {{"name", name}, {"camera", c}, {"node", n.node}, {"scene", std::move(scene)}});
        }
    }

    // KHR_lights_punctual: lights of the file's list, placed by the nodes that name them; glTF's
    // units are Caustic's candela and lux, converted at 683 lm/W.
    Json readLights(const std::vector<NodeInstance>& nodes) {
        const Json& list =
            values_.array(values_.object(values_.object(doc_, "extensions", "the file"),
                                         "KHR_lights_punctual", "the file"),
                          "lights", "KHR_lights_punctual");
        Json out = Json::array();
        for (const NodeInstance& n : nodes) {
            const Json& node = doc_.at("nodes").at(n.node);
            const std::string nodeAt =
                gltfObjectName("node", n.node, file_.model.nodes[n.node].name);
            const Json& ext = values_.object(values_.object(node, "extensions", nodeAt),
                                             "KHR_lights_punctual", nodeAt);
            const int l =
                values_.index(ext, "light", list.size(), nodeAt + ": KHR_lights_punctual");
            if (l < 0) continue;
            const Json& light = list[size_t(l)];
            const std::string at = gltfObjectName("light", size_t(l), textOf(light, "name"));
            const std::string type = values_.string(light, "type", "", at);
            const std::vector<double> color =
                values_.numbers(light, "color", 3, {1, 1, 1}, 0.0, kFloatMax, at);
            const double intensity = values_.number(light, "intensity", 1.0, 0.0, kFloatMax, at);
            const Pose pose = poseOf(n.world);
            Json caustic{{"color", color}};
            if (type == "directional") {
                caustic["type"] = "directional";
                caustic["direction"] = vec(pose.forward);
                caustic["lux"] = intensity;
            } else if (type == "point" || type == "spot") {
                caustic["type"] = type;
                caustic["position"] = vec(pose.position);
                caustic["candela"] = intensity;
                if (type == "spot") {
                    const Json& spot = values_.object(light, "spot", at);
                    const double outer = values_.number(spot, "outerConeAngle", kPiDouble / 4, 1e-6,
                                                        kPiDouble / 2, at + ": spot");
                    const double inner =
                        values_.number(spot, "innerConeAngle", 0.0, 0.0, outer, at + ": spot");
                    caustic["direction"] = vec(pose.forward);
                    caustic["inner_angle"] = inner * 180.0 / kPiDouble;
                    caustic["outer_angle"] = outer * 180.0 / kPiDouble;
                }
            } else {
                errors_.fail(at + ": type \"" + type.substr(0, 40) +
                             "\" is none of directional, point, spot");
            }
            if (light.contains("range"))
                warn(at +
                     ": range is not applied (the light falls off by the inverse square "
                     "law alone)");
            if (!finitePose(pose))
                errors_.fail(nodeAt + ": its transform gives light " + std::to_string(l) +
                             " no direction");
            lightNames_.push_back(textOf(light, "name"));
            lightTypes_.push_back(type);
            out.push_back(std::move(caustic));
        }
        return out;
    }

    void summarize(const std::vector<NodeInstance>& nodes, const GltfMaterials& materials,
                   size_t lights) {
        Json names = Json::array();
        for (const Json& m : values_.array(doc_, "materials", "the file"))
            names.push_back(textOf(m, "name"));
        Json lightList = Json::array();
        for (size_t i = 0; i < lights; ++i)
            lightList.push_back({{"name", lightNames_[i]}, {"type", lightTypes_[i]}});
        Json cameras = Json::array();
        for (const Json& c : out_.cameras)
            cameras.push_back({{"name", c["name"]}, {"camera", c["camera"]}, {"node", c["node"]}});
        auto strings = [&](const char* key) {
            Json a = Json::array();
            for (const Json& e : values_.array(doc_, key, "the file"))
                if (e.is_string()) a.push_back(e);
            return a;
        };
        out_.summary = {
            {"generator", textOf(values_.object(doc_, "asset", "the file"), "generator")},
            {"nodes", nodes.size()},
            {"meshes", file_.model.meshes.size()},
            {"draws", draws_.draws.size()},
            {"vertices", draws_.vertices},
            {"triangles", draws_.triangles},
            {"materials", names},
            {"textures", materials.textures},
            {"cameras", cameras},
            {"lights", lightList},
            {"bounds",
             {{"min", {out_.boundsMin.x, out_.boundsMin.y, out_.boundsMin.z}},
              {"max", {out_.boundsMax.x, out_.boundsMax.y, out_.boundsMax.z}}}},
            {"extensions",
             {{"used", strings("extensionsUsed")}, {"required", strings("extensionsRequired")}}},
            {"warnings", out_.warnings}};
    }

    const GltfFile& file_;
    const Json& doc_;
    const GltfImportOptions& options_;
    const MeshErrors& errors_;
    GltfValues values_;
    GltfScene out_;
    GltfDraws draws_;
    Json shapes_ = Json::array();
    std::vector<std::string> lightNames_, lightTypes_;
};

// A request's "lights": an array of Caustic lights added to the file's, or an object whose keys
// name the file's lights (KHR_lights_punctual's "name"; every light of that name) and whose values
// are fields merged into them, null to leave them out.
void changeLights(Json& scene, const Json& summary, const Json& request, const std::string& at) {
    if (!scene.contains("lights")) scene["lights"] = Json::array();
    Json& lights = scene["lights"];
    if (request.is_array()) {
        for (const Json& light : request) lights.push_back(light);
        return;
    }
    if (!request.is_object())
        throw InputError(at,
                         "expected an array of lights to add, or an object of the file's "
                         "lights to change by name");
    const Json& named = summary.at("lights");  // the file's lights, in the scene's order
    std::vector<bool> removed(lights.size(), false);
    for (auto it = request.begin(); it != request.end(); ++it) {
        const std::string path = jsonPointer(at, it.key());
        if (!it.value().is_object() && !it.value().is_null())
            throw InputError(path, "expected an object of fields to change, or null");
        bool found = false;
        for (size_t i = 0; i < named.size() && i < lights.size(); ++i) {
            if (textOf(named[i], "name") != it.key()) continue;
            found = true;
            if (it.value().is_null())
                removed[i] = true;
            else
                lights[i].merge_patch(it.value());
        }
        if (!found) {
            std::string known;
            for (const Json& n : named)
                if (!textOf(n, "name").empty()) appendListed(known, textOf(n, "name"));
            throw InputError(path, "no light of that name in the file; its lights: " +
                                       (known.empty() ? std::string("none named") : known));
        }
    }
    Json kept = Json::array();
    for (size_t i = 0; i < lights.size(); ++i)
        if (i >= removed.size() || !removed[i]) kept.push_back(lights[i]);
    lights = std::move(kept);
    if (lights.empty()) scene.erase("lights");
}

}  // namespace

const std::vector<std::string>& supportedGltfExtensions() {
    static const std::vector<std::string> kSupported{
        "EXT_meshopt_compression", "KHR_draco_mesh_compression",
        "KHR_lights_punctual",     "KHR_materials_emissive_strength",
        "KHR_materials_ior",       "KHR_materials_transmission",
        "KHR_materials_volume",    "KHR_mesh_quantization",
        "KHR_texture_transform"};
    return kSupported;
}

GltfScene importGltf(const GltfFile& file, const GltfImportOptions& options,
                     const MeshErrors& errors) {
    try {
        return Importer(file, options, errors).run();
    } catch (const nlohmann::json::exception& e) {
        // A value of an unexpected type somewhere the importer reads without a check of its own.
        errors.fail(std::string("the glTF JSON: ") + e.what());
    }
}

Json autoCamera(const Vec3& boundsMin, const Vec3& boundsMax, double azimuth, double elevation,
                double fov, int width, int height) {
    const glm::dvec3 lo(boundsMin), hi(boundsMax);
    const glm::dvec3 center = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
    const double az = azimuth * kPiDouble / 180.0, el = elevation * kPiDouble / 180.0;
    const glm::dvec3 toCamera(std::sin(az) * std::cos(el), std::sin(el),
                              std::cos(az) * std::cos(el));
    // The sphere fits the narrower of the two fields of view.
    const double vertical = fov * kPiDouble / 180.0;
    const double horizontal = 2.0 * std::atan(std::tan(vertical / 2) * width / double(height));
    const double distance = radius / std::sin(std::min(vertical, horizontal) / 2);
    return {{"position", vec(center + distance * toCamera)},
            {"look_at", vec(center)},
            {"fov", fov},
            {"width", width},
            {"height", height}};
}

Json gltfSceneWithOverrides(GltfScene& imported, const Json& request, const std::string& path,
                            const GltfImportOptions& options) {
    Json scene = imported.scene;
    JsonObject o(request, path);
    (void)o.find("gltf");  // the file itself: read by the caller

    // The camera: the file's first unless the request names one or asks for the automatic one.
    const Json* camera = o.find("camera");
    const std::string cameraAt = o.pathOf("camera");
    Json chosen;
    Json used;
    auto sized = [&](Json c, JsonObject& at) {
        const Json* w = at.find("width");
        const Json* h = at.find("height");
        if (w || h) {
            const double aspect = c["width"].get<double>() / c["height"].get<double>();
            const int64_t width =
                w ? readInteger(*w, at.pathOf("width"))
                  : int64_t(std::lround(double(readInteger(*h, at.pathOf("height"))) * aspect));
            const int64_t height = h ? readInteger(*h, at.pathOf("height"))
                                     : int64_t(std::lround(double(width) / aspect));
            c["width"] = std::max<int64_t>(width, 1);
            c["height"] = std::max<int64_t>(height, 1);
        }
        return c;
    };
    auto automatic = [&](const Json* settings, const std::string& at) {
        double azimuth = kAutoAzimuth, elevation = kAutoElevation, fov = kAutoFov;
        Json a = settings ? *settings : Json::object();
        JsonObject s(a, at);
        azimuth = s.number("azimuth", float(azimuth));
        elevation = s.number("elevation", float(elevation));
        fov = s.number("fov", float(fov));
        s.finish();
        if (!(elevation >= -90.0 && elevation <= 90.0))
            throw InputError(jsonPointer(at, "elevation"), "must be in [-90, 90] degrees");
        if (!(fov > 0.0 && fov < 180.0))
            throw InputError(jsonPointer(at, "fov"), "must be in (0, 180) degrees");
        const auto [width, height] = sizeFor(4.0 / 3.0, options.width);
        used = {{"auto", {{"azimuth", azimuth}, {"elevation", elevation}, {"fov", fov}}}};
        return autoCamera(imported.boundsMin, imported.boundsMax, azimuth, elevation, fov, width,
                          height);
    };
    if (!camera) {
        if (!imported.cameras.empty()) {
            chosen = imported.cameras[0]["scene"];
            used = {{"gltf", imported.cameras[0]["camera"]}, {"name", imported.cameras[0]["name"]}};
        } else {
            chosen = automatic(nullptr, cameraAt);
        }
    } else {
        JsonObject c(*camera, cameraAt);
        if (const Json* g = c.find("gltf")) {
            const std::string at = c.pathOf("gltf");
            const Json* found = nullptr;
            for (const Json& entry : imported.cameras)
                if ((g->is_number_integer() && entry["camera"] == *g) ||
                    (g->is_string() && entry["name"] == *g))
                    found = &entry;
            if (!found) {
                std::string known;
                for (const Json& entry : imported.cameras)
                    appendListed(known, entry["camera"].dump() + " " + entry["name"].dump());
                throw InputError(at, "no perspective camera " + g->dump().substr(0, 80) +
                                         " in the file; it has " +
                                         (known.empty() ? std::string("none") : known));
            }
            chosen = (*found)["scene"];
            used = {{"gltf", (*found)["camera"]}, {"name", (*found)["name"]}};
        } else if (const Json* a = c.find("auto")) {
            chosen = automatic(a, c.pathOf("auto"));
        } else {
            chosen = *camera;  // a Caustic camera, read by the scene loader
            used = {{"custom", true}};
        }
        if (c.find("gltf") || c.find("auto")) {
            chosen = sized(chosen, c);
            c.finish();
        }
    }
    scene["camera"] = chosen;
    imported.summary["camera"] = used;

    if (const Json* e = o.find("environment")) {
        if (e->is_null())
            scene.erase("environment");
        else
            scene["environment"] = *e;
    }
    if (const Json* b = o.find("background")) {
        scene["background"] = *b;
        if (!o.find("environment")) scene.erase("environment");
    }
    imported.summary["environment"] = scene.contains("environment") ? scene["environment"] : Json();

    if (const Json* m = o.find("materials")) {
        JsonObject changes(*m, o.pathOf("materials"));
        for (auto it = m->begin(); it != m->end(); ++it) {
            (void)changes.find(it.key());
            if (!scene["materials"].contains(it.key())) {
                std::string known;
                for (auto k = scene["materials"].begin(); k != scene["materials"].end(); ++k)
                    appendListed(known, k.key());
                throw InputError(changes.pathOf(it.key()),
                                 "no material of that name in the file; its materials: " + known);
            }
            if (!it.value().is_object())
                throw InputError(changes.pathOf(it.key()),
                                 "expected an object of fields to change");
            scene["materials"][it.key()].merge_patch(it.value());
        }
    }
    if (const Json* l = o.find("lights"))
        changeLights(scene, imported.summary, *l, o.pathOf("lights"));
    if (const Json* s = o.find("settings")) scene["settings"] = *s;
    o.finish();
    return scene;
}

}  // namespace caustic
