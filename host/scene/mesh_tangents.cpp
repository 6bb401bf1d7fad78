#include "scene/mesh_tangents.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <map>
#include <utility>

#include "core/math.h"

namespace pcl {
namespace {

// MikkTSpace's tests for zero, and its normalisation (by the reciprocal length).
bool notZero(float x) { return std::fabs(x) > FLT_MIN; }
bool notZero(Vec3 v) { return notZero(v.x) || notZero(v.y) || notZero(v.z); }
Vec3 normalized(Vec3 v) { return v * (1.0f / length(v)); }
Vec3 normalizedIfNotZero(Vec3 v) { return notZero(v) ? normalized(v) : v; }
// v's part in the plane ⟂ unit n, normalised where not zero.
Vec3 projected(Vec3 v, Vec3 n) { return normalizedIfNotZero(v - n * dot(n, v)); }

struct Corner {
    Vec3 p, n;
    float u, v;
};

struct Triangle {
    std::array<int, 3> welded;     // welded vertex per corner
    std::array<int, 3> neighbour;  // the triangle across edge k (corners k, k + 1), or −1
    std::array<int, 3> group;      // the group of corner k, or −1
    Vec3 os, ot;                   // unit ∂p/∂u and ∂p/∂v (0 where undefined)
    bool orientPreserving = false;
    bool groupWithAny = true;  // zero UV area or derivative: joins whichever group reaches it
    int source = 0;            // the mesh's triangle
};

struct Group {
    int vertex;  // the welded vertex it belongs to
    bool orientPreserving;
    std::vector<int> triangles;
};

struct TangentSpace {
    Vec3 os{1.0f, 0.0f, 0.0f};  // MikkTSpace's default where no group reaches a corner
    bool orientPreserving = false;
};

int cornerOf(const Triangle& t, int vertex) {
    for (int k = 0; k < 3; ++k)
        if (t.welded[size_t(k)] == vertex) return k;
    return -1;
}

// Triangles that share `g`'s vertex and reach it across edges through that vertex, with its
// orientation (MikkTSpace's AssignRecur).
void assignToGroup(std::vector<Triangle>& tris, std::vector<Group>& groups, int t, int g) {
    Triangle& tri = tris[size_t(t)];
    const int k = cornerOf(tri, groups[size_t(g)].vertex);
    if (tri.group[size_t(k)] >= 0) return;
    if (tri.groupWithAny && tri.group[0] < 0 && tri.group[1] < 0 && tri.group[2] < 0)
        tri.orientPreserving = groups[size_t(g)].orientPreserving;  // the first group decides
    if (tri.orientPreserving != groups[size_t(g)].orientPreserving) return;
    groups[size_t(g)].triangles.push_back(t);
    tri.group[size_t(k)] = g;
    const int left = tri.neighbour[size_t(k)], right = tri.neighbour[size_t((k + 2) % 3)];
    if (left >= 0) assignToGroup(tris, groups, left, g);
    if (right >= 0) assignToGroup(tris, groups, right, g);
}

// The angle-weighted average of the members' projected ∂p/∂u at `vertex` (EvalTspace).
Vec3 groupTangent(const std::vector<Triangle>& tris, const std::vector<Corner>& welded, const std::vector<int>& members,
                  int vertex) {
    Vec3 sum(0.0f);
    for (int t : members) {
        const Triangle& tri = tris[size_t(t)];
        if (tri.groupWithAny) continue;
        const int k = cornerOf(tri, vertex);
        const Vec3 n = welded[size_t(vertex)].n;
        const Vec3 p0 = welded[size_t(tri.welded[size_t((k + 2) % 3)])].p;
        const Vec3 p1 = welded[size_t(vertex)].p;
        const Vec3 p2 = welded[size_t(tri.welded[size_t((k + 1) % 3)])].p;
        const float cosine = std::clamp(dot(projected(p0 - p1, n), projected(p2 - p1, n)), -1.0f, 1.0f);
        sum = sum + projected(tri.os, n) * float(std::acos(double(cosine)));
    }
    return normalizedIfNotZero(sum);
}

}  // namespace

std::vector<float> mikkTSpaceCornerTangents(const TriangleMesh& mesh, int uvSet) {
    const size_t triCount = mesh.triangleCount();
    const std::vector<float>& uv = mesh.uv[uvSet];
    const bool haveNormals = mesh.normals.size() == mesh.positions.size();

    // 1. Corners, welded where position, normal and coordinates are equal (+0 for −0, as == does).
    std::vector<Corner> welded;
    std::vector<int> cornerVertex(3 * triCount);
    std::map<std::array<float, 8>, int> weldIndex;
    for (size_t t = 0; t < triCount; ++t) {
        const uint32_t* idx = &mesh.indices[3 * t];
        const Vec3 face =
            cross(mesh.positions[idx[1]] - mesh.positions[idx[0]], mesh.positions[idx[2]] - mesh.positions[idx[0]]);
        for (int k = 0; k < 3; ++k) {
            Corner c{mesh.positions[idx[k]], Vec3(0.0f), uv[2 * idx[k]], uv[2 * idx[k] + 1]};
            if (haveNormals) {
                c.n = mesh.normals[idx[k]];
                const float l = length(c.n);
                if (std::fabs(l - 1.0f) > 1e-5f && l > 0.0f) c.n = c.n / l;
            } else if (length(face) > 0.0f) {
                c.n = normalize(face);  // glTF: flat normals where a mesh has none
            }
            const std::array<float, 8> key{c.p.x + 0.0f, c.p.y + 0.0f, c.p.z + 0.0f, c.n.x + 0.0f,
                                           c.n.y + 0.0f, c.n.z + 0.0f, c.u + 0.0f,   c.v + 0.0f};
            const auto [it, added] = weldIndex.emplace(key, int(welded.size()));
            if (added) welded.push_back(c);
            cornerVertex[3 * t + size_t(k)] = it->second;
        }
    }

    // 2. The triangles whose corners are three positions, in the mesh's order; their derivatives.
    std::vector<Triangle> tris;
    std::vector<size_t> degenerate;
    for (size_t t = 0; t < triCount; ++t) {
        Triangle tri;
        for (int k = 0; k < 3; ++k) tri.welded[size_t(k)] = cornerVertex[3 * t + size_t(k)];
        const Corner &c1 = welded[size_t(tri.welded[0])], &c2 = welded[size_t(tri.welded[1])],
                     &c3 = welded[size_t(tri.welded[2])];
        if (c1.p == c2.p || c1.p == c3.p || c2.p == c3.p) {
            degenerate.push_back(t);
            continue;
        }
        tri.neighbour = {-1, -1, -1};
        tri.group = {-1, -1, -1};
        tri.source = int(t);
        const float t21x = c2.u - c1.u, t21y = c2.v - c1.v, t31x = c3.u - c1.u, t31y = c3.v - c1.v;
        const Vec3 d1 = c2.p - c1.p, d2 = c3.p - c1.p;
        const float signedArea = t21x * t31y - t21y * t31x;
        const Vec3 os = d1 * t31y - d2 * t21y, ot = d1 * -t31x + d2 * t21x;  // Mikkelsen eq. 18, 19
        tri.orientPreserving = signedArea > 0.0f;
        tri.os = tri.ot = Vec3(0.0f);
        if (notZero(signedArea)) {
            const float s = tri.orientPreserving ? 1.0f : -1.0f;
            const float lenOs = length(os), lenOt = length(ot);
            if (notZero(lenOs)) tri.os = os * (s / lenOs);
            if (notZero(lenOt)) tri.ot = ot * (s / lenOt);
            const float area = std::fabs(signedArea);
            tri.groupWithAny = !(notZero(lenOs / area) && notZero(lenOt / area));
        }
        tris.push_back(tri);
    }

    // 3. Neighbours across edges walked in opposite directions, paired in the order of
    //    (lower vertex, higher vertex, triangle) as MikkTSpace's sort leaves them.
    std::vector<std::array<int, 3>> edges;
    for (size_t t = 0; t < tris.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = tris[t].welded[size_t(k)], b = tris[t].welded[size_t((k + 1) % 3)];
            edges.push_back({std::min(a, b), std::max(a, b), int(t)});
        }
    std::sort(edges.begin(), edges.end());
    auto edgeOf = [&](int t, int a, int b) {  // the edge number of {a, b} in t, and its direction
        const auto& w = tris[size_t(t)].welded;
        if (w[0] == a || w[0] == b) {
            if (w[1] == a || w[1] == b) return std::array<int, 3>{0, w[0], w[1]};
            return std::array<int, 3>{2, w[2], w[0]};
        }
        return std::array<int, 3>{1, w[1], w[2]};
    };
    for (size_t i = 0; i < edges.size(); ++i) {
        const auto [lo, hi, f] = edges[i];
        const auto a = edgeOf(f, lo, hi);
        if (tris[size_t(f)].neighbour[size_t(a[0])] >= 0) continue;
        for (size_t j = i + 1; j < edges.size() && edges[j][0] == lo && edges[j][1] == hi; ++j) {
            const int t = edges[j][2];
            const auto b = edgeOf(t, lo, hi);
            if (a[1] == b[2] && a[2] == b[1] && tris[size_t(t)].neighbour[size_t(b[0])] < 0) {
                tris[size_t(f)].neighbour[size_t(a[0])] = t;
                tris[size_t(t)].neighbour[size_t(b[0])] = f;
                break;
            }
        }
    }

    // 4. Groups, started by the corners of triangles with a defined orientation.
    std::vector<Group> groups;
    for (size_t f = 0; f < tris.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            Triangle& tri = tris[f];
            if (tri.groupWithAny || tri.group[size_t(k)] >= 0) continue;
            const int g = int(groups.size());
            groups.push_back({tri.welded[size_t(k)], tri.orientPreserving, {int(f)}});
            tri.group[size_t(k)] = g;
            const int left = tri.neighbour[size_t(k)], right = tri.neighbour[size_t((k + 2) % 3)];
            if (left >= 0) assignToGroup(tris, groups, left, g);
            if (right >= 0) assignToGroup(tris, groups, right, g);
        }

    // 5. Per group, the members whose projected derivatives lie within the angular threshold
    //    (180°: all but exactly opposite ones) share one tangent space (GenerateTSpaces).
    const float thresholdCos = float(std::cos(double(180.0f * kPi / 180.0f)));
    std::vector<TangentSpace> space(3 * triCount);
    for (const Group& group : groups) {
        std::vector<std::pair<std::vector<int>, Vec3>> subgroups;
        const Vec3 n = welded[size_t(group.vertex)].n;
        for (int f : group.triangles) {
            const Triangle& tri = tris[size_t(f)];
            const Vec3 os = projected(tri.os, n), ot = projected(tri.ot, n);
            std::vector<int> members;
            for (int t : group.triangles) {
                const Triangle& other = tris[size_t(t)];
                if (tri.groupWithAny || other.groupWithAny || t == f ||
                    (dot(os, projected(other.os, n)) > thresholdCos && dot(ot, projected(other.ot, n)) > thresholdCos))
                    members.push_back(t);
            }
            std::sort(members.begin(), members.end());
            auto sub =
                std::find_if(subgroups.begin(), subgroups.end(), [&](const auto& s) { return s.first == members; });
            if (sub == subgroups.end()) {
                const Vec3 tangent = groupTangent(tris, welded, members, group.vertex);
                sub = subgroups.insert(subgroups.end(), {std::move(members), tangent});
            }
            int k = 0;
            while (tri.group[size_t(k)] != &group - groups.data()) ++k;
            space[3 * size_t(tri.source) + size_t(k)] = {sub->second, group.orientPreserving};
        }
    }

    // 6. A degenerate triangle's corner copies the space of the first good corner of its vertex.
    for (size_t t : degenerate)
        for (int k = 0; k < 3; ++k) {
            const int v = cornerVertex[3 * t + size_t(k)];
            for (const Triangle& tri : tris) {
                const int c = cornerOf(tri, v);
                if (c < 0) continue;
                space[3 * t + size_t(k)] = space[3 * size_t(tri.source) + size_t(c)];
                break;
            }
        }

    std::vector<float> out(4 * 3 * triCount);
    for (size_t c = 0; c < 3 * triCount; ++c) {
        out[4 * c] = space[c].os.x;
        out[4 * c + 1] = space[c].os.y;
        out[4 * c + 2] = space[c].os.z;
        out[4 * c + 3] = space[c].orientPreserving ? -1.0f : 1.0f;  // glTF's w: −MikkTSpace's sign
    }
    return out;
}

void setCornerTangents(TriangleMesh& mesh, const std::vector<float>& cornerTangents) {
    const size_t vertexCount = mesh.positions.size();
    // Per vertex, its distinct tangents and the vertex (itself or a copy) that holds each.
    std::vector<std::vector<std::pair<std::array<float, 4>, uint32_t>>> copies(vertexCount);
    std::vector<float> tangents(4 * vertexCount);
    for (size_t v = 0; v < vertexCount; ++v) {  // unused vertices: any perpendicular, w = +1
        const Vec3 n = mesh.normals.size() == vertexCount && length(mesh.normals[v]) > 0.0f ? normalize(mesh.normals[v])
                                                                                            : Vec3(0.0f, 0.0f, 1.0f);
        const Vec3 a = std::fabs(n.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        const Vec3 t = normalize(a - n * dot(n, a));
        tangents[4 * v] = t.x;
        tangents[4 * v + 1] = t.y;
        tangents[4 * v + 2] = t.z;
        tangents[4 * v + 3] = 1.0f;
    }
    auto copyVertex = [&](uint32_t v) {
        const uint32_t copy = uint32_t(mesh.positions.size());
        mesh.positions.push_back(mesh.positions[v]);
        if (!mesh.normals.empty()) mesh.normals.push_back(mesh.normals[v]);
        for (std::vector<float>& set : mesh.uv)
            if (!set.empty()) set.insert(set.end(), {set[2 * v], set[2 * v + 1]});
        tangents.insert(tangents.end(), 4, 0.0f);
        return copy;
    };
    for (size_t c = 0; c < mesh.indices.size(); ++c) {
        const uint32_t v = mesh.indices[c];
        const std::array<float, 4> t{cornerTangents[4 * c], cornerTangents[4 * c + 1], cornerTangents[4 * c + 2],
                                     cornerTangents[4 * c + 3]};
        auto& seen = copies[v];
        const auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& e) { return e.first == t; });
        if (it != seen.end()) {
            mesh.indices[c] = it->second;
            continue;
        }
        const uint32_t target = seen.empty() ? v : copyVertex(v);
        seen.push_back({t, target});
        std::copy(t.begin(), t.end(), tangents.begin() + 4 * std::ptrdiff_t(target));
        mesh.indices[c] = target;
    }
    mesh.tangents = std::move(tangents);
}

void generateTangents(TriangleMesh& mesh, int uvSet) { setCornerTangents(mesh, mikkTSpaceCornerTangents(mesh, uvSet)); }

void addMissingTangents(Scene& scene) {
    for (TriangleMesh& mesh : scene.meshes) {
        if (!mesh.tangents.empty() || mesh.material < 0 || size_t(mesh.material) >= scene.materials.size()) continue;
        const int t = scene.materials[size_t(mesh.material)].normalTexture;
        if (t < 0 || size_t(t) >= scene.textures.size()) continue;
        const int set = scene.textures[size_t(t)].texCoord;
        if (mesh.uv[set].size() != 2 * mesh.positions.size()) continue;  // validateScene refuses it
        generateTangents(mesh, set);
    }
}

}  // namespace pcl
