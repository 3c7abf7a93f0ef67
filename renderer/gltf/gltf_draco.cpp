#include "gltf/gltf_draco.h"

#include <draco/compression/decode.h>

#include <memory>
#include <string>

namespace caustic {
namespace {

// The bytes of the extension's bufferView, checked against its buffer.
std::pair<const char*, size_t> viewBytes(const tinygltf::Model& m, int view, const std::string& at,
                                         const MeshErrors& errors) {
    if (view < 0 || size_t(view) >= m.bufferViews.size())
        errors.fail(at + "KHR_draco_mesh_compression: bufferView " + std::to_string(view) +
                    " does not exist (" + std::to_string(m.bufferViews.size()) + " bufferViews)");
    const tinygltf::BufferView& v = m.bufferViews[size_t(view)];
    if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
        errors.fail(at + "KHR_draco_mesh_compression: bufferView " + std::to_string(view) +
                    " names no buffer");
    const std::vector<unsigned char>& buffer = m.buffers[size_t(v.buffer)].data;
    if (v.byteLength == 0 || v.byteLength > buffer.size() ||
        v.byteOffset > buffer.size() - v.byteLength)
        errors.fail(at + "KHR_draco_mesh_compression: bufferView " + std::to_string(view) + ": " +
                    std::to_string(v.byteLength) + " bytes at offset " +
                    std::to_string(v.byteOffset) + " do not fit buffer " +
                    std::to_string(v.buffer) + " (" + std::to_string(buffer.size()) + " bytes)");
    return {reinterpret_cast<const char*>(buffer.data() + v.byteOffset), v.byteLength};
}

template <typename V>
std::vector<V> attributeValues(const draco::Mesh& mesh, const tinygltf::Value& ids,
                               const char* name, const std::string& at, const MeshErrors& errors) {
    if (!ids.Has(name)) return {};
    const int id = ids.Get(name).GetNumberAsInt();
    const draco::PointAttribute* a = id >= 0 ? mesh.GetAttributeByUniqueId(uint32_t(id)) : nullptr;
    if (!a)
        errors.fail(at + "KHR_draco_mesh_compression: no Draco attribute " + std::to_string(id) +
                    " for " + name);
    constexpr int kComponents = V::length();
    if (a->num_components() < kComponents)
        errors.fail(at + "KHR_draco_mesh_compression: " + name + " has " +
                    std::to_string(a->num_components()) + " components, not " +
                    std::to_string(kComponents));
    std::vector<V> out(mesh.num_points());
    for (uint32_t p = 0; p < mesh.num_points(); ++p) {
        float value[4] = {0, 0, 0, 0};
        if (!a->ConvertValue<float>(a->mapped_index(draco::PointIndex(p)), int8_t(kComponents),
                                    value))
            errors.fail(at + "KHR_draco_mesh_compression: " + name + " does not convert to float");
        for (int c = 0; c < kComponents; ++c) out[p][c] = value[c];
        if (!isFinite(out[p]))
            errors.fail(at + "KHR_draco_mesh_compression: " + name + " value " + std::to_string(p) +
                        " is not finite");
    }
    return out;
}

}  // namespace

const tinygltf::Value* dracoExtension(const tinygltf::Primitive& prim) {
    auto it = prim.extensions.find("KHR_draco_mesh_compression");
    return it == prim.extensions.end() ? nullptr : &it->second;
}

DracoPrimitive decodeDraco(const tinygltf::Model& m, const tinygltf::Primitive& prim,
                           bool texcoords, const std::string& at, const MeshErrors& errors) {
    const tinygltf::Value& ext = *dracoExtension(prim);
    if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Has("attributes") ||
        !ext.Get("attributes").IsObject())
        errors.fail(at + "KHR_draco_mesh_compression needs a bufferView and attributes");
    const auto [bytes, size] = viewBytes(m, ext.Get("bufferView").GetNumberAsInt(), at, errors);
    draco::DecoderBuffer buffer;
    buffer.Init(bytes, size);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok())
        errors.fail(at + "KHR_draco_mesh_compression: the data does not decode (" +
                    decoded.status().error_msg_string() + ")");
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    const tinygltf::Value& ids = ext.Get("attributes");
    DracoPrimitive out;
    out.positions = attributeValues<Vec3>(*mesh, ids, "POSITION", at, errors);
    if (out.positions.empty())
        errors.fail(at + "KHR_draco_mesh_compression: no POSITION attribute");
    out.normals = attributeValues<Vec3>(*mesh, ids, "NORMAL", at, errors);
    if (texcoords) out.texcoords = attributeValues<Vec2>(*mesh, ids, "TEXCOORD_0", at, errors);
    out.indices.reserve(size_t(mesh->num_faces()) * 3);
    for (uint32_t f = 0; f < mesh->num_faces(); ++f)
        for (draco::PointIndex p : mesh->face(draco::FaceIndex(f))) {
            if (p.value() >= mesh->num_points())
                errors.fail(at + "KHR_draco_mesh_compression: face " + std::to_string(f) +
                            " names point " + std::to_string(p.value()) + " of " +
                            std::to_string(mesh->num_points()));
            out.indices.push_back(p.value());
        }
    // The accessors' counts are what admission counted: the data must agree.
    const auto expect = [&](int accessor, size_t count, const char* what) {
        if (accessor >= 0 && size_t(accessor) < m.accessors.size() &&
            m.accessors[size_t(accessor)].count != count)
            errors.fail(at + "KHR_draco_mesh_compression: " + what + " decodes to " +
                        std::to_string(count) + " values, its accessor says " +
                        std::to_string(m.accessors[size_t(accessor)].count));
    };
    expect(prim.attributes.at("POSITION"), out.positions.size(), "POSITION");
    expect(prim.indices, out.indices.size(), "the indices");
    return out;
}

}  // namespace caustic
