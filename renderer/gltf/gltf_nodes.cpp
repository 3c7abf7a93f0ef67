#include "gltf/gltf_nodes.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <limits>

namespace caustic {
namespace {

class NodeWalk {
public:
    NodeWalk(const tinygltf::Model& model, const MeshErrors& errors) : m_(model), errors_(errors) {}

    std::vector<NodeInstance> run() const { return instancesOf(rootsOf(parentsOf())); }

private:
    std::string node(size_t i) const { return gltfObjectName("node", i, m_.nodes[i].name); }

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

    // The default scene's roots ("scene", else scene 0), or every parentless node when the file
    // has no scene.
    std::vector<int> rootsOf(const std::vector<int>& parents) const {
        checkAcyclic(parents);
        std::vector<int> roots;
        if (m_.scenes.empty()) {
            for (size_t i = 0; i < parents.size(); ++i)
                if (parents[i] == -1) roots.push_back(int(i));
            return roots;
        }
        const int s = m_.defaultScene >= 0 ? m_.defaultScene : 0;
        if (size_t(s) >= m_.scenes.size())
            errors_.fail("\"scene\": scene " + std::to_string(s) + " does not exist (" +
                         std::to_string(m_.scenes.size()) + " scenes)");
        const std::string at = gltfObjectName("scene", size_t(s), m_.scenes[size_t(s)].name) + ": ";
        for (int n : m_.scenes[size_t(s)].nodes) {
            if (n < 0 || size_t(n) >= m_.nodes.size())
                errors_.fail(at + "node " + std::to_string(n) + " does not exist (" +
                             std::to_string(m_.nodes.size()) + " nodes)");
            if (parents[size_t(n)] != -1)
                errors_.fail(at + "node " + std::to_string(n) + " is a root but a child of node " +
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

    // The nodes and their world transforms, depth first in the file's order with a stack of its
    // own (a chain of nodes may be as long as the file allows). A root listed twice is reached
    // once; any other node has one parent and so is reached once.
    std::vector<NodeInstance> instancesOf(const std::vector<int>& roots) const {
        std::vector<NodeInstance> instances;
        std::vector<bool> reached(m_.nodes.size(), false);
        std::vector<NodeInstance> stack;
        for (int root : roots) {
            if (reached[size_t(root)]) continue;
            reached[size_t(root)] = true;
            stack.push_back({size_t(root), glm::dmat4(1.0)});
            while (!stack.empty()) {
                NodeInstance parent = stack.back();
                stack.pop_back();
                const tinygltf::Node& n = m_.nodes[parent.node];
                NodeInstance self{parent.node, parent.world * localOf(parent.node)};
                instances.push_back(self);
                for (auto child = n.children.rbegin(); child != n.children.rend(); ++child)
                    stack.push_back({size_t(*child), self.world});
            }
        }
        return instances;
    }

    const tinygltf::Model& m_;
    const MeshErrors& errors_;
};

}  // namespace

std::string gltfObjectName(const char* kind, size_t index, const std::string& name) {
    std::string out = std::string(kind) + " " + std::to_string(index);
    if (!name.empty()) out += " (" + name.substr(0, 80) + ")";
    return out;
}

std::vector<NodeInstance> walkNodes(const tinygltf::Model& model, const MeshErrors& errors) {
    return NodeWalk(model, errors).run();
}

}  // namespace caustic
