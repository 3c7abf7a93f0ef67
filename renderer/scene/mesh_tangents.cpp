#include "scene/mesh_tangents.h"

#include <mikktspace.h>

#include <cstring>
#include <map>
#include <tuple>

namespace caustic {

namespace {

struct MikkMesh {
    const TriangleMesh& mesh;
    std::vector<glm::vec4> cornerTangents;  // 3 a triangle

    static MikkMesh& of(const SMikkTSpaceContext* c) {
        return *static_cast<MikkMesh*>(c->m_pUserData);
    }
    uint32_t vertex(int face, int corner) const { return mesh.triangles[size_t(face)][corner]; }
    Vec3 faceNormal(int face) const {
        const glm::uvec3& t = mesh.triangles[size_t(face)];
        const Vec3 c = glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                  mesh.positions[t.z] - mesh.positions[t.x]);
        const float length = glm::length(c);
        return length > 0.0f ? c / length : Vec3(0.0f, 0.0f, 1.0f);
    }
};

int faceCount(const SMikkTSpaceContext* c) {
    return int(MikkMesh::of(c).mesh.triangles.size());
}
int cornerCount(const SMikkTSpaceContext*, const int) {
    return 3;
}
void position(const SMikkTSpaceContext* c, float out[], const int face, const int corner) {
    const MikkMesh& m = MikkMesh::of(c);
    const Vec3& p = m.mesh.positions[m.vertex(face, corner)];
    out[0] = p.x, out[1] = p.y, out[2] = p.z;
}
void normal(const SMikkTSpaceContext* c, float out[], const int face, const int corner) {
    const MikkMesh& m = MikkMesh::of(c);
    Vec3 n = m.mesh.normals.empty() ? Vec3(0.0f) : m.mesh.normals[m.vertex(face, corner)];
    if (!(glm::dot(n, n) > 0.0f)) n = m.faceNormal(face);
    out[0] = n.x, out[1] = n.y, out[2] = n.z;
}
void texcoord(const SMikkTSpaceContext* c, float out[], const int face, const int corner) {
    const MikkMesh& m = MikkMesh::of(c);
    const Vec2& st = m.mesh.texcoords[m.vertex(face, corner)];
    // MikkTSpace in the bakers' (s, v) with v up the image, as the glTF sample viewer and Blender
    // compute it: the bitangent then points up the image, glTF's normal-map +y.
    out[0] = st.x, out[1] = 1.0f - st.y;
}
void setTangent(const SMikkTSpaceContext* c, const float t[], const float sign, const int face,
                const int corner) {
    MikkMesh& m = MikkMesh::of(c);
    m.cornerTangents[3 * size_t(face) + size_t(corner)] = glm::vec4(t[0], t[1], t[2], sign);
}

}  // namespace

std::vector<glm::vec4> generateTangents(TriangleMesh& mesh) {
    if (mesh.texcoords.empty() || mesh.triangles.empty()) return {};
    MikkMesh m{mesh, std::vector<glm::vec4>(3 * mesh.triangles.size(), glm::vec4(0.0f))};
    SMikkTSpaceInterface interface {};
    interface.m_getNumFaces = faceCount;
    interface.m_getNumVerticesOfFace = cornerCount;
    interface.m_getPosition = position;
    interface.m_getNormal = normal;
    interface.m_getTexCoord = texcoord;
    interface.m_setTSpaceBasic = setTangent;
    SMikkTSpaceContext context{&interface, &m};
    if (!genTangSpaceDefault(&context)) return {};

    // One vertex for each distinct (vertex, tangent) pair, in order of first use.
    std::map<std::tuple<uint32_t, float, float, float, float>, uint32_t> vertexOf;
    TriangleMesh split;
    std::vector<glm::vec4> tangents;
    split.triangles.resize(mesh.triangles.size());
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
        for (int corner = 0; corner < 3; ++corner) {
            const uint32_t v = mesh.triangles[f][corner];
            const glm::vec4& t = m.cornerTangents[3 * f + size_t(corner)];
            auto [it, added] =
                vertexOf.try_emplace({v, t.x, t.y, t.z, t.w}, uint32_t(split.positions.size()));
            if (added) {
                split.positions.push_back(mesh.positions[v]);
                if (!mesh.normals.empty()) split.normals.push_back(mesh.normals[v]);
                split.texcoords.push_back(mesh.texcoords[v]);
                tangents.push_back(t);
            }
            split.triangles[f][corner] = it->second;
        }
    }
    mesh = std::move(split);
    return tangents;
}

}  // namespace caustic
