#include "scene/glb_accessors.h"

#include <cstring>
#include <sstream>
#include <string>

namespace caustic {
namespace {

struct Named {
    int code;
    const char* name;
};
constexpr Named kComponentTypes[] = {
    {TINYGLTF_COMPONENT_TYPE_BYTE, "BYTE"},
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, "UNSIGNED_BYTE"},
    {TINYGLTF_COMPONENT_TYPE_SHORT, "SHORT"},
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, "UNSIGNED_SHORT"},
    {TINYGLTF_COMPONENT_TYPE_INT, "INT"},
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, "UNSIGNED_INT"},
    {TINYGLTF_COMPONENT_TYPE_FLOAT, "FLOAT"},
    {TINYGLTF_COMPONENT_TYPE_DOUBLE, "DOUBLE"},
};
constexpr Named kTypes[] = {
    {TINYGLTF_TYPE_SCALAR, "SCALAR"}, {TINYGLTF_TYPE_VEC2, "VEC2"}, {TINYGLTF_TYPE_VEC3, "VEC3"},
    {TINYGLTF_TYPE_VEC4, "VEC4"},     {TINYGLTF_TYPE_MAT2, "MAT2"}, {TINYGLTF_TYPE_MAT3, "MAT3"},
    {TINYGLTF_TYPE_MAT4, "MAT4"},
};

// "FLOAT VEC3", or the numbers of what glTF does not define.
std::string typeName(const tinygltf::Accessor& a) {
    auto nameIn = [](const auto& table, int code, const char* kind) {
        for (const Named& n : table)
            if (n.code == code) return std::string(n.name);
        return std::string(kind) + " " + std::to_string(code);
    };
    return nameIn(kComponentTypes, a.componentType, "componentType") + " " +
           nameIn(kTypes, a.type, "type");
}

std::string at(int accessor) {
    return "accessor " + std::to_string(accessor) + ": ";
}

const tinygltf::Accessor& accessorAt(const tinygltf::Model& m, int index,
                                     const MeshErrors& errors) {
    if (index < 0 || size_t(index) >= m.accessors.size())
        errors.fail(at(index) + "does not exist (" + std::to_string(m.accessors.size()) +
                    " accessors)");
    return m.accessors[size_t(index)];
}

// Elements of `elementSize` bytes, `stride` apart, all inside the accessor's bufferView, which is
// inside its buffer.
struct ElementBytes {
    const unsigned char* first;
    size_t elementSize;
    size_t stride;
    size_t count;
    const unsigned char* operator[](size_t i) const { return first + i * stride; }
};

ElementBytes elementsOf(const tinygltf::Model& m, int index, size_t elementSize,
                        const MeshErrors& errors) {
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    if (a.sparse.isSparse) errors.fail(at(index) + "sparse accessors are not read");
    if (a.bufferView < 0) errors.fail(at(index) + "has no bufferView (it would be all zeros)");
    if (size_t(a.bufferView) >= m.bufferViews.size())
        errors.fail(at(index) + "bufferView " + std::to_string(a.bufferView) + " does not exist (" +
                    std::to_string(m.bufferViews.size()) + " bufferViews)");
    const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
    const std::string view = "bufferView " + std::to_string(a.bufferView) + ": ";
    if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
        errors.fail(view + "buffer " + std::to_string(v.buffer) + " does not exist (" +
                    std::to_string(m.buffers.size()) + " buffers)");
    const std::vector<unsigned char>& buffer = m.buffers[size_t(v.buffer)].data;
    if (v.byteLength > buffer.size() || v.byteOffset > buffer.size() - v.byteLength)
        errors.fail(view + std::to_string(v.byteLength) + " bytes at offset " +
                    std::to_string(v.byteOffset) + " run past the end of buffer " +
                    std::to_string(v.buffer) + " (" + std::to_string(buffer.size()) + " bytes)");
    const size_t stride = v.byteStride != 0 ? v.byteStride : elementSize;
    if (stride < elementSize)
        errors.fail(view + "byteStride " + std::to_string(stride) + " is less than the " +
                    std::to_string(elementSize) + "-byte elements of accessor " +
                    std::to_string(index));
    if (a.count == 0) errors.fail(at(index) + "has no elements (count 0)");
    // The last element ends at byteOffset + stride (count - 1) + elementSize; each step is checked
    // against the room left, so that no sum can wrap around.
    const size_t room = v.byteLength;
    bool fits = a.byteOffset <= room && elementSize <= room - a.byteOffset &&
                a.count - 1 <= (room - a.byteOffset - elementSize) / stride;
    if (!fits)
        errors.fail(at(index) + std::to_string(a.count) + " elements of " +
                    std::to_string(elementSize) + " bytes, " + std::to_string(stride) +
                    " apart from offset " + std::to_string(a.byteOffset) +
                    ", run past the end of bufferView " + std::to_string(a.bufferView) + " (" +
                    std::to_string(room) + " bytes)");
    return {buffer.data() + v.byteOffset + a.byteOffset, elementSize, stride, a.count};
}

// The accessor's elements once its type suits `use` and its bytes are in range.
ElementBytes checkedElements(const tinygltf::Model& m, int index, AccessorUse use,
                             const MeshErrors& errors) {
    const tinygltf::Accessor& a = accessorAt(m, index, errors);
    if (use == AccessorUse::Positions) {
        if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            errors.fail(at(index) + "POSITION must be FLOAT VEC3, not " + typeName(a));
        return elementsOf(m, index, sizeof(float) * 3, errors);
    }
    size_t size = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                  : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                  : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                              : 0;
    if (a.type != TINYGLTF_TYPE_SCALAR || size == 0)
        errors.fail(at(index) +
                    "indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, "
                    "not " +
                    typeName(a));
    if (a.count % 3 != 0)
        errors.fail(at(index) + std::to_string(a.count) +
                    " indices are not whole triangles (a multiple of 3)");
    return elementsOf(m, index, size, errors);
}

}  // namespace

size_t checkAccessor(const tinygltf::Model& m, int index, AccessorUse use,
                     const MeshErrors& errors) {
    return checkedElements(m, index, use, errors).count;
}

std::vector<Vec3> readPositions(const tinygltf::Model& m, int index, const MeshErrors& errors) {
    ElementBytes bytes = checkedElements(m, index, AccessorUse::Positions, errors);
    std::vector<Vec3> positions(bytes.count);
    for (size_t i = 0; i < bytes.count; ++i) {
        std::memcpy(&positions[i], bytes[i], sizeof(float) * 3);
        const Vec3& p = positions[i];
        if (!isFinite(p)) {
            std::ostringstream text;
            text << "vertex " << i << " is not finite (" << p.x << ", " << p.y << ", " << p.z
                 << ")";
            errors.fail(at(index) + text.str());
        }
    }
    return positions;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& m, int index, size_t vertexCount,
                                  const MeshErrors& errors) {
    ElementBytes bytes = checkedElements(m, index, AccessorUse::Indices, errors);
    std::vector<uint32_t> indices(bytes.count);
    for (size_t i = 0; i < bytes.count; ++i) {
        uint32_t value = 0;  // little-endian: the low bytes of a uint32_t hold a narrower value
        std::memcpy(&value, bytes[i], bytes.elementSize);
        if (value >= vertexCount)
            errors.fail(at(index) + "index " + std::to_string(value) +
                        " is out of range (POSITION has " + std::to_string(vertexCount) +
                        " vertices)");
        indices[i] = value;
    }
    return indices;
}

}  // namespace caustic
