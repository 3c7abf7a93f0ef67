// A .glb's triangles (mesh_file_parts.h): the container checked, tinygltf reading the JSON with
// every way to open a file refused, then every node of every scene walked with its transform.
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
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
    bool loaded = false;
    try {
        loaded = loader.LoadBinaryFromMemory(&model, &err, &warn,
                                             reinterpret_cast<const unsigned char*>(bytes.data()),
                                             static_cast<unsigned int>(bytes.size()));
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

constexpr double kFloatMax = std::numeric_limits<float>::max();

const char* modeName(int mode) {
    constexpr const char* kNames[] = {"points",    "lines",          "line loop",   "line strip",
                                      "triangles", "triangle strip", "triangle fan"};
    return mode >= 0 && mode < 7 ? kNames[mode] : "unknown";
}

// Walks the node trees and gathers the instanced triangles.
class NodeWalk {
public:
    struct Instance {
        size_t node;
        glm::dmat4 world;  ///< The node's global transform: its parents' and its own.
    };

    NodeWalk(const tinygltf::Model& model, const MeshTransform& transform, const MeshErrors& errors)
        : m_(model), transform_(transform), errors_(errors) {}

    TriangleMesh run() {
        std::vector<Instance> instances = instancesOf(rootsOf(parentsOf()));
        // Counted before any element is read: nodes may instance one mesh many times.
        uint64_t elements = 0;
        for (const Instance& instance : instances) {
            elements += elementsOf(instance.node);
            if (elements > kMaxGlbElements)
                errors_.fail(node(instance.node) + ": the nodes' meshes make more than " +
                             std::to_string(kMaxGlbElements) +
                             " vertices and triangles together, the most a .glb may make");
        }
        for (const Instance& instance : instances) drawMesh(instance);
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

    // Every scene's roots, or every parentless node when the file has no scene.
    std::vector<int> rootsOf(const std::vector<int>& parents) const {
        checkAcyclic(parents);
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

    // The nodes with a mesh and their world transforms, depth first with a stack of its own (a
    // chain of nodes may be as long as the file allows). A root in two scenes, or twice in one,
    // is drawn once; any other node has one parent and so is reached once.
    std::vector<Instance> instancesOf(const std::vector<int>& roots) const {
        std::vector<Instance> instances;
        std::vector<bool> reached(m_.nodes.size(), false);
        std::vector<Instance> stack;
        for (int root : roots) {
            if (reached[size_t(root)]) continue;
            reached[size_t(root)] = true;
            stack.push_back({size_t(root), glm::dmat4(1.0)});
            while (!stack.empty()) {
                Instance parent = stack.back();
                stack.pop_back();
                const tinygltf::Node& n = m_.nodes[parent.node];
                Instance self{parent.node, parent.world * localOf(parent.node)};
                if (n.mesh >= 0) instances.push_back(self);
                for (int child : n.children) stack.push_back({size_t(child), self.world});
            }
        }
        return instances;
    }

    const tinygltf::Mesh& meshOf(size_t nodeIndex) const {
        int meshIndex = m_.nodes[nodeIndex].mesh;
        if (size_t(meshIndex) >= m_.meshes.size())
            errors_.fail(node(nodeIndex) + ": mesh " + std::to_string(meshIndex) +
                         " does not exist (" + std::to_string(m_.meshes.size()) + " meshes)");
        return m_.meshes[size_t(meshIndex)];
    }

    std::string primitiveName(size_t nodeIndex, size_t p) const {
        return "mesh " + std::to_string(m_.nodes[nodeIndex].mesh) + " primitive " +
               std::to_string(p) + ": ";
    }

    // The POSITION accessor of a triangle primitive.
    int positionsOf(const tinygltf::Primitive& prim, const std::string& at) const {
        if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
            errors_.fail(at + "mode " + std::to_string(prim.mode) + " (" + modeName(prim.mode) +
                         ") is not read; only triangles (mode 4)");
        auto position = prim.attributes.find("POSITION");
        if (position == prim.attributes.end()) errors_.fail(at + "has no POSITION attribute");
        return position->second;
    }

    // The vertices and triangles the node's mesh adds, from its accessors' checked counts.
    uint64_t elementsOf(size_t nodeIndex) const {
        const tinygltf::Mesh& mesh = meshOf(nodeIndex);
        uint64_t elements = 0;
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            size_t vertices = checkAccessor(m_, positionsOf(prim, primitiveName(nodeIndex, p)),
                                            AccessorUse::Positions, errors_);
            size_t corners = prim.indices >= 0
                                 ? checkAccessor(m_, prim.indices, AccessorUse::Indices, errors_)
                                 : vertices;
            elements += uint64_t(vertices) + corners / 3;
        }
        return elements;
    }

    void drawMesh(const Instance& instance) {
        const tinygltf::Mesh& mesh = meshOf(instance.node);
        for (size_t p = 0; p < mesh.primitives.size(); ++p)
            drawPrimitive(mesh.primitives[p], primitiveName(instance.node, p), instance);
    }

    void drawPrimitive(const tinygltf::Primitive& prim, const std::string& at,
                       const Instance& instance) {
        const int positionAccessor = positionsOf(prim, at);
        std::vector<Vec3> points = readPositions(m_, positionAccessor, errors_);
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
        const glm::dmat4& world = instance.world;
        const uint32_t base = uint32_t(mesh_.positions.size());
        for (size_t v = 0; v < points.size(); ++v) {
            // In double until the point is known to fit a float (a larger double has no float).
            glm::dvec3 q(world * glm::dvec4(glm::dvec3(points[v]), 1.0));
            bool fits = std::abs(q.x) <= kFloatMax && std::abs(q.y) <= kFloatMax &&
                        std::abs(q.z) <= kFloatMax;
            Vec3 p = fits ? transform_.apply(Vec3(q)) : Vec3(kInfinity);
            if (!isFinite(p))
                errors_.fail(node(instance.node) + ": vertex " + std::to_string(v) +
                             " of accessor " + std::to_string(positionAccessor) +
                             " is not finite once transformed");
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
