#include "scene/mesh_tangents.h"

#include <algorithm>
#include <cmath>

namespace pcl {
namespace {

// The angle between the unit directions of a and b (0 when either has length 0).
float angleBetween(Vec3 a, Vec3 b) {
    const float la = length(a), lb = length(b);
    if (!(la > 0.0f) || !(lb > 0.0f)) return 0.0f;
    return std::acos(std::clamp(dot(a, b) / (la * lb), -1.0f, 1.0f));
}

// v projected onto the plane ⟂ unit n, normalised; 0 when nothing is left.
Vec3 tangentPart(Vec3 v, Vec3 n) {
    const Vec3 t = v - n * dot(n, v);
    const float l = length(t);
    return l > 0.0f ? t / l : Vec3(0.0f);
}

}  // namespace

std::vector<float> generateTangents(const TriangleMesh& mesh, int uvSet) {
    const size_t n = mesh.positions.size();
    const std::vector<float>& uv = mesh.uv[uvSet];
    // The vertex normals: the mesh's, else angle-weighted face normals.
    std::vector<Vec3> normal(n, Vec3(0.0f));
    const bool haveNormals = mesh.normals.size() == n;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t* idx = &mesh.indices[3 * t];
        const Vec3 face =
            cross(mesh.positions[idx[1]] - mesh.positions[idx[0]], mesh.positions[idx[2]] - mesh.positions[idx[0]]);
        const float area2 = length(face);
        for (int k = 0; k < 3 && !haveNormals && area2 > 0.0f; ++k) {
            const Vec3 p = mesh.positions[idx[k]];
            const float angle =
                angleBetween(mesh.positions[idx[(k + 1) % 3]] - p, mesh.positions[idx[(k + 2) % 3]] - p);
            normal[idx[k]] = normal[idx[k]] + face / area2 * angle;
        }
    }
    for (size_t v = 0; v < n; ++v) {
        const Vec3 m = haveNormals ? mesh.normals[v] : normal[v];
        const float l = length(m);
        normal[v] = l > 0.0f ? m / l : Vec3(0.0f, 0.0f, 1.0f);
    }

    std::vector<Vec3> tangent(n, Vec3(0.0f)), bitangent(n, Vec3(0.0f));
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t* idx = &mesh.indices[3 * t];
        const Vec3 e1 = mesh.positions[idx[1]] - mesh.positions[idx[0]];
        const Vec3 e2 = mesh.positions[idx[2]] - mesh.positions[idx[0]];
        const float du1 = uv[2 * idx[1]] - uv[2 * idx[0]], dv1 = uv[2 * idx[1] + 1] - uv[2 * idx[0] + 1];
        const float du2 = uv[2 * idx[2]] - uv[2 * idx[0]], dv2 = uv[2 * idx[2] + 1] - uv[2 * idx[0] + 1];
        const float det = du1 * dv2 - du2 * dv1;
        if (!(std::fabs(det) > 0.0f) || !std::isfinite(det)) continue;  // degenerate coordinates
        // e1 = du1 T + dv1 B, e2 = du2 T + dv2 B solved for T = ∂p/∂u, B = ∂p/∂v.
        const Vec3 T = (e1 * dv2 - e2 * dv1) / det, B = (e2 * du1 - e1 * du2) / det;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = idx[k];
            const Vec3 p = mesh.positions[v];
            const float angle =
                angleBetween(mesh.positions[idx[(k + 1) % 3]] - p, mesh.positions[idx[(k + 2) % 3]] - p);
            tangent[v] = tangent[v] + tangentPart(T, normal[v]) * angle;
            bitangent[v] = bitangent[v] + tangentPart(B, normal[v]) * angle;
        }
    }

    std::vector<float> out(4 * n);
    for (size_t v = 0; v < n; ++v) {
        const Vec3 N = normal[v];
        Vec3 T = tangentPart(tangent[v], N);
        if (!(length(T) > 0.0f)) {  // no coordinates here: any perpendicular
            T = tangentPart(std::fabs(N.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0), N);
        }
        const float w = dot(cross(N, T), -bitangent[v]) < 0.0f ? -1.0f : 1.0f;
        out[4 * v] = T.x;
        out[4 * v + 1] = T.y;
        out[4 * v + 2] = T.z;
        out[4 * v + 3] = w;
    }
    return out;
}

void addMissingTangents(Scene& scene) {
    for (TriangleMesh& mesh : scene.meshes) {
        if (!mesh.tangents.empty() || mesh.material < 0 || size_t(mesh.material) >= scene.materials.size()) continue;
        const int t = scene.materials[size_t(mesh.material)].normalTexture;
        if (t < 0 || size_t(t) >= scene.textures.size()) continue;
        const int set = scene.textures[size_t(t)].texCoord;
        if (mesh.uv[set].size() != 2 * mesh.positions.size()) continue;  // validateScene refuses it
        mesh.tangents = generateTangents(mesh, set);
    }
}

}  // namespace pcl
