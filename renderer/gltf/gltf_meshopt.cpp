#include "gltf/gltf_meshopt.h"

#include <meshoptimizer.h>

#include "gltf/gltf_values.h"

#include <cstdint>
#include <vector>

namespace caustic {
namespace {

const Json* meshoptOf(const Json& o) {
    if (!o.is_object()) return nullptr;
    auto e = o.find("extensions");
    if (e == o.end() || !e->is_object()) return nullptr;
    auto m = e->find("EXT_meshopt_compression");
    return m == e->end() ? nullptr : &*m;
}

uint64_t unsignedField(const Json& o, const char* key, uint64_t fallback, const std::string& at,
                       const MeshErrors& errors) {
    auto it = o.find(key);
    if (it == o.end()) return fallback;
    if (!it->is_number_unsigned()) errors.fail(at + ": " + key + " is not a non-negative integer");
    return it->get<uint64_t>();
}

}  // namespace

bool isMeshoptFallback(const Json& buffer) {
    const Json* ext = meshoptOf(buffer);
    return ext && ext->is_object() && ext->value("fallback", Json(false)) == Json(true);
}

bool decodeMeshopt(Json& doc, const std::function<std::string_view(size_t)>& source,
                   std::string& decoded, const MeshErrors& errors) {
    auto views = doc.find("bufferViews");
    auto buffers = doc.find("buffers");
    if (views == doc.end() || !views->is_array() || buffers == doc.end() || !buffers->is_array())
        return false;
    struct Rewrite {
        size_t view;
        size_t offset, length;
    };
    std::vector<Rewrite> rewrites;
    for (size_t v = 0; v < views->size(); ++v) {
        const Json* ext = meshoptOf((*views)[v]);
        if (!ext) continue;
        const std::string at = "bufferView " + std::to_string(v) + ": EXT_meshopt_compression";
        if (!ext->is_object()) errors.fail(at + " is not an object");
        const uint64_t buffer = unsignedField(*ext, "buffer", UINT64_MAX, at, errors);
        if (buffer >= buffers->size())
            errors.fail(at + ": buffer " + std::to_string(buffer) + " does not exist");
        const uint64_t offset = unsignedField(*ext, "byteOffset", 0, at, errors);
        const uint64_t length = unsignedField(*ext, "byteLength", UINT64_MAX, at, errors);
        const uint64_t stride = unsignedField(*ext, "byteStride", 0, at, errors);
        const uint64_t count = unsignedField(*ext, "count", UINT64_MAX, at, errors);
        const std::string mode = textOf(*ext, "mode");
        const std::string filter = textOf(*ext, "filter", "NONE");
        const std::string_view bytes = source(size_t(buffer));
        if (length == UINT64_MAX || count == UINT64_MAX)
            errors.fail(at + ": byteLength and count are required");
        if (offset > bytes.size() || length > bytes.size() - offset)
            errors.fail(at + ": " + std::to_string(length) + " bytes at offset " +
                        std::to_string(offset) + " run past the end of buffer " +
                        std::to_string(buffer) + " (" + std::to_string(bytes.size()) + " bytes)");
        const bool attributes = mode == "ATTRIBUTES";
        if (attributes ? (stride == 0 || stride % 4 != 0 || stride > 256)
                       : (stride != 2 && stride != 4))
            errors.fail(at + ": byteStride " + std::to_string(stride) +
                        " is not allowed for mode " +
                        (mode.empty() ? std::string("(none)") : mode));
        if (!attributes && mode != "TRIANGLES" && mode != "INDICES")
            errors.fail(at + ": mode \"" + mode.substr(0, 40) +
                        "\" is none of ATTRIBUTES, TRIANGLES, INDICES");
        if (mode == "TRIANGLES" && count % 3 != 0)
            errors.fail(at + ": count " + std::to_string(count) + " is not whole triangles");
        if (count > kMaxMeshoptBytes / stride || decoded.size() + count * stride > kMaxMeshoptBytes)
            errors.fail(at + ": decodes past " + std::to_string(kMaxMeshoptBytes) +
                        " bytes, the most a file's compressed views may make");
        // Views are 4-byte aligned in the decoded buffer, as accessors of 4-byte components need.
        decoded.resize((decoded.size() + 3) / 4 * 4, '\0');
        const size_t start = decoded.size();
        decoded.resize(start + size_t(count * stride));
        auto* out = reinterpret_cast<unsigned char*>(decoded.data() + start);
        const auto* in = reinterpret_cast<const unsigned char*>(bytes.data() + offset);
        const int status = attributes ? meshopt_decodeVertexBuffer(out, count, stride, in, length)
                           : mode == "TRIANGLES"
                               ? meshopt_decodeIndexBuffer(out, count, stride, in, length)
                               : meshopt_decodeIndexSequence(out, count, stride, in, length);
        if (status != 0)
            errors.fail(at + ": the data does not decode (meshoptimizer says " +
                        std::to_string(status) + ")");
        if (filter == "OCTAHEDRAL" && attributes && (stride == 4 || stride == 8))
            meshopt_decodeFilterOct(out, count, stride);
        else if (filter == "QUATERNION" && attributes && stride == 8)
            meshopt_decodeFilterQuat(out, count, stride);
        else if (filter == "EXPONENTIAL" && attributes)
            meshopt_decodeFilterExp(out, count, stride);
        else if (filter != "NONE")
            errors.fail(at + ": filter \"" + filter.substr(0, 40) + "\" with mode " + mode +
                        " and byteStride " + std::to_string(stride) + " is not allowed");
        rewrites.push_back({v, start, size_t(count * stride)});
    }
    if (rewrites.empty()) return false;
    // The decoded buffer takes the first fallback buffer's place, or comes last; the other
    // fallback buffers become empty (they hold no data, and the decoded bytes are read once).
    size_t target = buffers->size();
    for (size_t b = 0; b < buffers->size(); ++b)
        if (isMeshoptFallback((*buffers)[b])) {
            const bool first = target == buffers->size();
            if (first) target = b;
            (*buffers)[b] = {{"uri", first ? kMeshoptDecodedUri : kMeshoptEmptyUri},
                             {"byteLength", first ? decoded.size() : 0}};
        }
    if (target == buffers->size())
        buffers->push_back({{"uri", kMeshoptDecodedUri}, {"byteLength", decoded.size()}});
    for (const Rewrite& r : rewrites) {
        Json& view = (*views)[r.view];
        view["buffer"] = target;
        view["byteOffset"] = r.offset;
        view["byteLength"] = r.length;
        view["extensions"].erase("EXT_meshopt_compression");
        if (view["extensions"].empty()) view.erase("extensions");
    }
    return true;
}

}  // namespace caustic
