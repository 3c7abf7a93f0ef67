#include "gltf/gltf_accessors.h"

#include <algorithm>
#include <cmath>

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

size_t componentBytes(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

struct UseRule {
    int type;
    int components;
    std::vector<int> componentTypes;
    const char* what;  ///< what the error says is allowed
};

UseRule ruleOf(AccessorUse use) {
    constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE,
                  kUbyte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                  kShort = TINYGLTF_COMPONENT_TYPE_SHORT,
                  kUshort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                  kUint = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                  kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
    switch (use) {
        case AccessorUse::Positions:
            return {
                TINYGLTF_TYPE_VEC3,
                3,
                {kFloat, kByte, kUbyte, kShort, kUshort},
                "POSITION must be VEC3 of FLOAT (or of BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT "
                "with KHR_mesh_quantization)"};
        case AccessorUse::Normals:
            return {TINYGLTF_TYPE_VEC3,
                    3,
                    {kFloat, kByte, kShort},
                    "NORMAL must be VEC3 of FLOAT (or of normalized BYTE or SHORT with "
                    "KHR_mesh_quantization)"};
        case AccessorUse::Texcoords:
            return {
                TINYGLTF_TYPE_VEC2,
                2,
                {kFloat, kUbyte, kUshort, kByte, kShort},
                "TEXCOORD must be VEC2 of FLOAT, UNSIGNED_BYTE or UNSIGNED_SHORT (or of BYTE or "
                "SHORT with KHR_mesh_quantization)"};
        case AccessorUse::Indices:
        default:
            return {TINYGLTF_TYPE_SCALAR,
                    1,
                    {kUbyte, kUshort, kUint},
                    "indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT"};
    }
}

// The accessor once its type suits `use`.
const tinygltf::Accessor& checkedType(const tinygltf::Model& m, int index, AccessorUse use,
                                      const MeshErrors& errors) {
    const tinygltf::Accessor& a = accessorAt(m, index, errors);
    const UseRule rule = ruleOf(use);
    const bool allowed =
        a.type == rule.type && std::find(rule.componentTypes.begin(), rule.componentTypes.end(),
                                         a.componentType) != rule.componentTypes.end();
    if (!allowed) errors.fail(at(index) + rule.what + ", not " + typeName(a));
    return a;
}

// The accessor's elements once its type suits `use` and its bytes are in range.
ElementBytes checkedElements(const tinygltf::Model& m, int index, AccessorUse use,
                             const MeshErrors& errors) {
    const tinygltf::Accessor& a = checkedType(m, index, use, errors);
    return elementsOf(m, index, componentBytes(a.componentType) * size_t(ruleOf(use).components),
                      errors);
}

// Component c of an element as a float: FLOAT as stored, an integer as its value or, normalized,
// mapped to [-1, 1] or [0, 1] (glTF 2.0, "Animations", the normalization table).
float componentAt(const unsigned char* element, int componentType, bool normalized, int c) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float v;
            std::memcpy(&v, element + 4 * c, 4);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            int8_t v;
            std::memcpy(&v, element + c, 1);
            return normalized ? std::max(float(v) / 127.0f, -1.0f) : float(v);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
            uint8_t v;
            std::memcpy(&v, element + c, 1);
            return normalized ? float(v) / 255.0f : float(v);
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v;
            std::memcpy(&v, element + 2 * c, 2);
            return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
        }
        default: {  // UNSIGNED_SHORT: ruleOf allows no other
            uint16_t v;
            std::memcpy(&v, element + 2 * c, 2);
            return normalized ? float(v) / 65535.0f : float(v);
        }
    }
}

// The accessor's values, `components` floats an element, each checked finite.
template <typename V>
std::vector<V> readVectors(const tinygltf::Model& m, int index, AccessorUse use,
                           const MeshErrors& errors) {
    ElementBytes bytes = checkedElements(m, index, use, errors);
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    constexpr int kComponents = V::length();
    std::vector<V> out(bytes.count);
    for (size_t i = 0; i < bytes.count; ++i) {
        for (int c = 0; c < kComponents; ++c)
            out[i][c] = componentAt(bytes[i], a.componentType, a.normalized, c);
        if (!isFinite(out[i])) {
            std::ostringstream text;
            text << "vertex " << i << " is not finite (";
            for (int c = 0; c < kComponents; ++c) text << (c ? ", " : "") << out[i][c];
            errors.fail(at(index) + text.str() + ")");
        }
    }
    return out;
}

}  // namespace

size_t checkAccessor(const tinygltf::Model& m, int index, AccessorUse use,
                     const MeshErrors& errors) {
    return checkedElements(m, index, use, errors).count;
}

size_t checkAccessorType(const tinygltf::Model& m, int index, AccessorUse use,
                         const MeshErrors& errors) {
    const tinygltf::Accessor& a = checkedType(m, index, use, errors);
    if (a.count == 0) errors.fail(at(index) + "has no elements (count 0)");
    return a.count;
}

std::vector<Vec3> readVec3s(const tinygltf::Model& m, int index, AccessorUse use,
                            const MeshErrors& errors) {
    return readVectors<Vec3>(m, index, use, errors);
}

std::vector<Vec2> readTexcoords(const tinygltf::Model& m, int index, const MeshErrors& errors) {
    return readVectors<Vec2>(m, index, AccessorUse::Texcoords, errors);
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
