#include "gltf/gltf_model.h"

#include "gltf/gltf_meshopt.h"
#include "gltf/gltf_values.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "scene/mesh_loader.h"

namespace caustic {
namespace {

// tinygltf's file callbacks. A .glb's refuse everything (checkGltfJson has refused every URI
// already, so these are a second lock on the same door); a .gltf's go through its reader, each
// file read once (tinygltf asks whether a file exists, then reads it).
struct CachedFiles {
    const GltfFileReader* reader = nullptr;
    std::map<std::string, std::optional<std::string>> files;
    const std::optional<std::string>& get(const std::string& name) {
        auto it = files.find(name);
        if (it == files.end()) it = files.emplace(name, (*reader)(name)).first;
        return it->second;
    }
};
bool fileExists(const std::string& name, void* user) {
    auto* files = static_cast<CachedFiles*>(user);
    return files && files->reader && files->get(name).has_value();
}
std::string noExpansion(const std::string& file, void*) {
    return file;
}
bool readFile(std::vector<unsigned char>* out, std::string* err, const std::string& name,
              void* user) {
    auto* files = static_cast<CachedFiles*>(user);
    if (!files || !files->reader || !files->get(name)) {
        if (err) *err += "no file \"" + name.substr(0, 120) + "\" in the model\n";
        return false;
    }
    const std::string& bytes = *files->get(name);
    out->assign(bytes.begin(), bytes.end());
    files->files.erase(name);  // read once: tinygltf keeps its copy
    return true;
}
bool noFileWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "refused to write a file\n";
    return false;
}

// tinygltf hands an image's bytes over without checking a bufferView's range against its buffer,
// so images in a bufferView are read by imageBytes instead; one from a uri (a file the reader
// gave, or data: decoded) is kept as it is, encoded. Nothing is decoded here: OpenImageIO decodes
// the images a material uses, in the texture store.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
    return true;
}

// tinygltf (built without Draco, as Debian's is) refuses a primitive whose indices accessor has
// no bufferView, which KHR_draco_mesh_compression's accessors lack: such an accessor is given the
// extension's bufferView, which is in range and never read as an accessor (gltf_draco.h decodes
// it). Returns whether the document changed.
bool viewsForDracoIndices(Json& doc) {
    bool changed = false;
    auto meshes = doc.find("meshes");
    auto accessors = doc.find("accessors");
    if (meshes == doc.end() || !meshes->is_array() || accessors == doc.end() ||
        !accessors->is_array())
        return false;
    for (Json& mesh : *meshes) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
            continue;
        for (Json& prim : mesh["primitives"]) {
            if (!prim.is_object()) continue;
            const Json* draco = nullptr;
            if (auto e = prim.find("extensions"); e != prim.end() && e->is_object())
                if (auto d = e->find("KHR_draco_mesh_compression"); d != e->end()) draco = &*d;
            auto indices = prim.find("indices");
            if (!draco || !draco->is_object() || !draco->contains("bufferView") ||
                indices == prim.end() || !indices->is_number_unsigned() ||
                indices->get<size_t>() >= accessors->size())
                continue;
            Json& accessor = (*accessors)[indices->get<size_t>()];
            if (accessor.is_object() && !accessor.contains("bufferView")) {
                accessor["bufferView"] = (*draco)["bufferView"];
                changed = true;
            }
        }
    }
    return changed;
}

tinygltf::Model load(std::string_view bytes, bool binary, const GltfFileReader* files,
                     const MeshErrors& errors) {
    tinygltf::TinyGLTF loader;
    CachedFiles cached{files, {}};
    loader.SetFsCallbacks({&fileExists, &noExpansion, &readFile, &noFileWrite, &cached});
    loader.SetImageLoader(&keepEncodedImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool loaded = false;
    try {
        // checkGlbContainer checked a .glb's length against the header's 32-bit field, and
        // checkGltfJson a .gltf's against kMaxGlbJsonBytes.
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        const auto size = static_cast<unsigned int>(bytes.size());
        loaded = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, size)
                        : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, "");
    } catch (const std::out_of_range&) {
        // tinygltf reads some arrays with at(): a buffer declaring 0 bytes, with views into it,
        // threw here (a fuzzing finding). A malformed upload is an error, not a crash.
        err = "an index or a byte range in the document points outside what the file holds";
    } catch (const std::exception& e) {
        err = e.what();
    }
    if (!loaded) {
        err = err.substr(0, err.find('\n'));
        errors.fail("glTF: " + (err.empty() ? std::string("tinygltf cannot read it") : err));
    }
    return model;
}

// What tinygltf cannot read as the file has it, made readable: Draco's indices accessors given a
// view, meshopt-compressed views decoded into `decoded`. Returns whether `doc` changed.
bool prepareForTinygltf(Json& doc, const std::function<std::string_view(size_t)>& buffer,
                        std::string& decoded, const MeshErrors& errors) {
    try {
        const bool draco = viewsForDracoIndices(doc);
        const bool meshopt = decodeMeshopt(doc, buffer, decoded, errors);
        return draco || meshopt;
    } catch (const nlohmann::json::exception& e) {
        errors.fail(std::string("the glTF JSON: ") + e.what());
    }
}

// The model's files, and the meshopt-decoded buffer under its reserved name.
GltfFileReader withDecoded(const GltfFileReader* files, const std::string& decoded) {
    return [files, &decoded](const std::string& uri) -> std::optional<std::string> {
        if (uri == kMeshoptDecodedUri) return decoded;
        if (uri == kMeshoptEmptyUri) return std::string();
        return files ? (*files)(uri) : std::nullopt;
    };
}

}  // namespace

GltfFile loadGlbModel(std::string_view bytes, const MeshErrors& errors) {
    Json doc = checkGlbContainer(bytes, errors);
    Json patched = doc;
    std::string decoded;
    const std::string_view bin = glbBinChunk(bytes);
    const auto buffer = [&](size_t b) { return b == 0 ? bin : std::string_view(); };
    if (!prepareForTinygltf(patched, buffer, decoded, errors))
        return {load(bytes, true, nullptr, errors), std::move(doc)};
    const GltfFileReader reader = withDecoded(nullptr, decoded);
    return {load(withJsonChunk(bytes, patched.dump()), true, &reader, errors), std::move(doc)};
}

GltfFile loadGltfModel(std::string_view json, const GltfFileReader& files,
                       const MeshErrors& errors) {
    if (json.empty()) errors.fail("the file is empty");
    Json doc = checkGltfJson(json, true, errors);
    for (const char* kind : {"buffers", "images"})
        if (auto list = doc.find(kind); list != doc.end() && list->is_array())
            for (const Json& o : *list)
                if (percentDecoded(textOf(o, "uri")).rfind("caustic:", 0) == 0)
                    errors.fail(std::string(kind) + ": a uri starting \"caustic:\" is reserved");
    Json patched = doc;
    std::string decoded;
    std::vector<std::optional<std::string>> sources;
    const auto buffer = [&](size_t b) -> std::string_view {
        sources.resize(std::max(sources.size(), b + 1));
        if (!sources[b]) {
            const Json& o = patched.at("buffers").at(b);
            const std::string uri = percentDecoded(textOf(o, "uri"));  // as tinygltf asks
            sources[b] = uri.empty() ? std::string() : files(uri).value_or(std::string());
        }
        return *sources[b];
    };
    if (!prepareForTinygltf(patched, buffer, decoded, errors))
        return {load(json, false, &files, errors), std::move(doc)};
    sources.clear();
    const GltfFileReader reader = withDecoded(&files, decoded);
    return {load(patched.dump(), false, &reader, errors), std::move(doc)};
}

bool isGltfFileName(const std::string& name) {
    std::string ext = std::filesystem::path(name).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".glb" || ext == ".gltf";
}

GltfFile loadGltfPath(const std::filesystem::path& file, const MeshErrors& errors) {
    auto read = [](const std::filesystem::path& f) -> std::optional<std::string> {
        std::ifstream in(f, std::ios::binary);
        if (!in) return std::nullopt;
        std::ostringstream bytes;
        bytes << in.rdbuf();
        return std::move(bytes).str();
    };
    std::optional<std::string> bytes = read(file);
    if (!bytes) errors.fail("cannot open it");
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".glb") return loadGlbModel(*bytes, errors);
    const std::filesystem::path folder = file.parent_path().empty() ? "." : file.parent_path();
    GltfFileReader beside = [&](const std::string& uri) -> std::optional<std::string> {
        return read(resolveAsset(folder, uri, errors.path));  // InputError: it leaves the folder
    };
    return loadGltfModel(*bytes, beside, errors);
}

std::string_view imageBytes(const tinygltf::Model& m, int index, const MeshErrors& errors) {
    const std::string at = "image " + std::to_string(index) + ": ";
    if (index < 0 || size_t(index) >= m.images.size())
        errors.fail(at + "does not exist (" + std::to_string(m.images.size()) + " images)");
    const tinygltf::Image& image = m.images[size_t(index)];
    if (image.bufferView < 0) {
        if (image.image.empty()) errors.fail(at + "has no bytes");
        return {reinterpret_cast<const char*>(image.image.data()), image.image.size()};
    }
    const tinygltf::BufferView& v = m.bufferViews[size_t(image.bufferView)];  // tinygltf checked
    const std::vector<unsigned char>& buffer = m.buffers[size_t(v.buffer)].data;
    if (v.byteLength == 0 || v.byteLength > buffer.size() ||
        v.byteOffset > buffer.size() - v.byteLength)
        errors.fail(at + "bufferView " + std::to_string(image.bufferView) + ": " +
                    std::to_string(v.byteLength) + " bytes at offset " +
                    std::to_string(v.byteOffset) + " do not fit buffer " +
                    std::to_string(v.buffer) + " (" + std::to_string(buffer.size()) + " bytes)");
    return {reinterpret_cast<const char*>(buffer.data() + v.byteOffset), v.byteLength};
}

}  // namespace caustic
