// A .glb's triangles (mesh_file_parts.h): the container checked, tinygltf reading the JSON with
// every way to open a file refused, then every node of every scene walked with its transform.
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "scene/glb_accessors.h"
#include "scene/mesh_file.h"
#include "scene/mesh_file_parts.h"

namespace caustic {
namespace {

// tinygltf's file callbacks, all refusing: checkGlbContainer has refused every URI already, so
// these are a second lock on the same door.
bool noFileExists(const std::string&, void*) {
    return false;
}
std::string noExpansion(const std::string& file, void*) {
    return file;
}
bool noFileRead(std::vector<unsigned char>*, std::string* err, const std::string& file, void*) {
    if (err) *err += "refused to open \"" + file + "\"\n";
    return false;
}
bool noFileWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "refused to write a file\n";
    return false;
}
// Materials are ignored, so images are never decoded (stb_image on untrusted bytes, for nothing).
bool noImageDecoding(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                     const unsigned char*, int, void*) {
    return true;
}

tinygltf::Model loadModel(std::string_view bytes, const MeshErrors& errors) {
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&noFileExists, &noExpansion, &noFileRead, &noFileWrite, nullptr});
    loader.SetImageLoader(&noImageDecoding, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    // checkGlbContainer checked the length against the header's 32-bit field.
    if (!loader.LoadBinaryFromMemory(&model, &err, &warn,
                                     reinterpret_cast<const unsigned char*>(bytes.data()),
                                     static_cast<unsigned int>(bytes.size()))) {
        err = err.substr(0, err.find('\n'));
        errors.fail("glTF: " + (err.empty() ? std::string("tinygltf cannot read it") : err));
    }
    return model;
}

const char* modeName(int mode) {
    constexpr const char* kNames[] = {"points",    "lines",          "line loop",   "line strip",
                                      "triangles", "triangle strip", "triangle fan"};
    return mode >= 0 && mode < 7 ? kNames[mode] : "unknown";
}

// Walks the node trees and gathers the instanced triangles.
class NodeWalk {
public:
    NodeWalk(const tinygltf::Model& model, const MeshTransform& transform, const MeshErrors& errors)
        : m_(model), transform_(transform), errors_(errors) {}

    TriangleMesh run() {
        std::vector<int> parents = parentsOf();
        checkAcyclic(parents);
        std::vector<bool> drawn(m_.nodes.size(), false);
        // Every scene's roots, or every parentless node when the file has no scene.
        for (int root : roots(parents)) {
            if (drawn[size_t(root)]) continue;  // in two scenes, or twice in one: drawn once
            drawn[size_t(root)] = true;
            drawTree(root);
        }
        if (mesh_.triangles.empty())
            errors_.fail("has no triangles (no node of a scene has a triangle mesh)");
        return std::move(mesh_);
    }

private:
    std::string node(size_t i) const { return "node " + std::to_string(i); }

    // Each node's parent (-1 for none); a node may have one (glTF 2.0, "Nodes and Hierarchy").
    std::vector<int> parentsOf() const {
        std::vector<int> parents(m_.nodes.size(), -1);
        for (size_t i = 0; i < m_.nodes.size(); ++i)
            for (int child : m_.nodes[i].children) {
                if (child < 0 || size_t(child) >= m_.nodes.size())
                    errors_.fail(node(i) + ": child " + std::to_string(child) +
                                 " does not exist (" + std::to_string(m_.nodes.size()) + " nodes)");
                if (parents[size_t(child)] != -1)
                    errors_.fail(node(size_t(child)) + ": a child of both node " +
                                 std::to_string(parents[size_t(child)]) + " and node " +
                                 std::to_string(i) + " (a node has one parent)");
                parents[size_t(child)] = int(i);
            }
        return parents;
    }

    // With one parent each, the nodes form trees unless a chain of parents loops.
    void checkAcyclic(const std::vector<int>& parents) const {
        enum : uint8_t { kNew, kOnChain, kDone };
        std::vector<uint8_t> state(parents.size(), kNew);
        std::vector<size_t> chain;
        for (size_t start = 0; start < parents.size(); ++start) {
            int i = int(start);
            for (; i != -1 && state[size_t(i)] == kNew; i = parents[size_t(i)]) {
                state[size_t(i)] = kOnChain;
                chain.push_back(size_t(i));
            }
            if (i != -1 && state[size_t(i)] == kOnChain)
                errors_.fail(node(size_t(i)) +
                             ": its own ancestor (the node hierarchy has a cycle)");
            for (size_t c : chain) state[c] = kDone;
            chain.clear();
        }
    }

    std::vector<int> roots(const std::vector<int>& parents) const {
        std::vector<int> roots;
        if (m_.scenes.empty()) {
            for (size_t i = 0; i < parents.size(); ++i)
                if (parents[i] == -1) roots.push_back(int(i));
            return roots;
        }
        for (size_t s = 0; s < m_.scenes.size(); ++s)
            for (int n : m_.scenes[s].nodes) {
                std::string at = "scene " + std::to_string(s) + ": ";
                if (n < 0 || size_t(n) >= m_.nodes.size())
                    errors_.fail(at + "node " + std::to_string(n) + " does not exist (" +
                                 std::to_string(m_.nodes.size()) + " nodes)");
                if (parents[size_t(n)] != -1)
                    errors_.fail(at + "node " + std::to_string(n) +
                                 " is a root but a child of node " +
                                 std::to_string(parents[size_t(n)]));
                roots.push_back(n);
            }
        return roots;
    }

    // The node's matrix, or translation * rotation * scale (glTF 2.0, "Transformations").
    glm::dmat4 localOf(size_t i) const {
        const tinygltf::Node& n = m_.nodes[i];
        auto expect = [&](const std::vector<double>& v, const char* what, size_t size) {
            if (!v.empty() && v.size() != size)
                errors_.fail(node(i) + ": " + what + " has " + std::to_string(v.size()) +
                             " numbers, not " + std::to_string(size));
        };
        expect(n.matrix, "matrix", 16);
        expect(n.translation, "translation", 3);
        expect(n.rotation, "rotation", 4);
        expect(n.scale, "scale", 3);
        if (!n.matrix.empty()) return glm::make_mat4(n.matrix.data());  // column-major, as glTF
        glm::dmat4 m(1.0);
        if (!n.translation.empty()) m = glm::translate(m, glm::make_vec3(n.translation.data()));
        if (!n.rotation.empty()) {
            // glTF stores (x, y, z, w); exporters round, so the quaternion is normalized.
            const std::vector<double>& r = n.rotation;
            glm::dquat q(r[3], r[0], r[1], r[2]);
            double length = glm::length(q);
            if (!(length > 0.0 && length < std::numeric_limits<double>::infinity()))
                errors_.fail(node(i) + ": rotation is not a unit quaternion");
            m = m * glm::mat4_cast(q / length);
        }
        if (!n.scale.empty()) m = glm::scale(m, glm::make_vec3(n.scale.data()));
        return m;
    }

    // Depth first with a stack of its own: a chain of nodes may be as long as the file allows.
    void drawTree(int root) {
        std::vector<std::pair<size_t, glm::dmat4>> stack{{size_t(root), glm::dmat4(1.0)}};
        while (!stack.empty()) {
            auto [i, parentWorld] = stack.back();
            stack.pop_back();
            glm::dmat4 world = parentWorld * localOf(i);
            const tinygltf::Node& n = m_.nodes[i];
            if (n.mesh >= 0) drawMesh(i, world);
            for (int child : n.children) stack.emplace_back(size_t(child), world);
        }
    }

    void drawMesh(size_t nodeIndex, const glm::dmat4& world) {
        int meshIndex = m_.nodes[nodeIndex].mesh;
        if (size_t(meshIndex) >= m_.meshes.size())
            errors_.fail(node(nodeIndex) + ": mesh " + std::to_string(meshIndex) +
                         " does not exist (" + std::to_string(m_.meshes.size()) + " meshes)");
        const tinygltf::Mesh& mesh = m_.meshes[size_t(meshIndex)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            std::string at =
                "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p) + ": ";
            drawPrimitive(mesh.primitives[p], at, nodeIndex, world);
        }
    }

    void drawPrimitive(const tinygltf::Primitive& prim, const std::string& at, size_t nodeIndex,
                       const glm::dmat4& world) {
        if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
            errors_.fail(at + "mode " + std::to_string(prim.mode) + " (" + modeName(prim.mode) +
                         ") is not read; only triangles (mode 4)");
        auto position = prim.attributes.find("POSITION");
        if (position == prim.attributes.end()) errors_.fail(at + "has no POSITION attribute");
        std::vector<Vec3> points = readPositions(m_, position->second, errors_);
        std::vector<uint32_t> indices;
        if (prim.indices >= 0) {
            indices = readIndices(m_, prim.indices, points.size(), errors_);
        } else {
            // Unindexed: each three vertices in order are a triangle.
            if (points.size() % 3 != 0)
                errors_.fail(at + std::to_string(points.size()) +
                             " unindexed vertices are not whole triangles (a multiple of 3)");
            for (uint32_t v = 0; v < points.size(); ++v) indices.push_back(v);
        }
        const uint64_t total =
            mesh_.positions.size() + mesh_.triangles.size() + points.size() + indices.size() / 3;
        if (total > kMaxGlbElements)
            errors_.fail(node(nodeIndex) + ": the nodes' meshes make more than " +
                         std::to_string(kMaxGlbElements) +
                         " vertices and triangles together, the most a .glb may make");

        const uint32_t base = uint32_t(mesh_.positions.size());
        for (size_t v = 0; v < points.size(); ++v) {
            Vec3 p = transform_.apply(Vec3(world * glm::dvec4(glm::dvec3(points[v]), 1.0)));
            if (!isFinite(p))
                errors_.fail(node(nodeIndex) + ": vertex " + std::to_string(v) + " of accessor " +
                             std::to_string(position->second) + " is not finite once transformed");
            mesh_.positions.push_back(p);
        }
        // A mirroring transform turns counter-clockwise faces clockwise; swapping two corners keeps
        // the front side where the file meant it (glTF 2.0, "Meshes": a negative determinant of
        // the node's global transform reverses the winding order).
        const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
        for (size_t t = 0; t + 2 < indices.size(); t += 3) {
            glm::uvec3 tri(base + indices[t], base + indices[t + 1], base + indices[t + 2]);
            if (mirrored) std::swap(tri.y, tri.z);
            mesh_.triangles.push_back(tri);
        }
    }

    const tinygltf::Model& m_;
    const MeshTransform& transform_;
    const MeshErrors& errors_;
    TriangleMesh mesh_;
};

}  // namespace

TriangleMesh parseGlb(std::string_view bytes, const MeshTransform& transform,
                      const MeshErrors& errors) {
    checkGlbContainer(bytes, errors);
    tinygltf::Model model = loadModel(bytes, errors);
    return NodeWalk(model, transform, errors).run();
}

}  // namespace caustic
