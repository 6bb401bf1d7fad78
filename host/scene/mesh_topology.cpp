#include "scene/mesh_topology.h"

#include <array>
#include <map>
#include <utility>
#include <vector>

namespace pcl {

double enclosedVolume(const TriangleMesh& mesh) {
    double v = 0.0;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const Vec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                   c = mesh.positions[mesh.indices[t + 2]];
        v += (double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) +
              double(a.y) * (double(b.z) * c.x - double(b.x) * c.z) +
              double(a.z) * (double(b.x) * c.y - double(b.y) * c.x)) /
             6.0;
    }
    return v;
}

std::string closedMeshProblem(const TriangleMesh& mesh) {
    if (mesh.indices.empty()) return "no triangles";
    // Weld vertices by exact position.
    std::map<std::array<float, 3>, uint32_t> welded;
    std::vector<uint32_t> id(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3 p = mesh.positions[i];
        id[i] = welded.emplace(std::array<float, 3>{p.x, p.y, p.z}, uint32_t(welded.size())).first->second;
    }
    // Directed edges: a closed, consistently wound mesh uses each once, and its reverse once.
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) ++directed[{id[mesh.indices[t + k]], id[mesh.indices[t + (k + 1) % 3]]}];
    for (const auto& [edge, count] : directed) {
        const auto reverse = directed.find({edge.second, edge.first});
        const int reverseCount = reverse == directed.end() ? 0 : reverse->second;
        const std::string name = "edge (" + std::to_string(edge.first) + "," + std::to_string(edge.second) + ")";
        if (count + reverseCount != 2)
            return name + " is used by " + std::to_string(count + reverseCount) + " triangle" +
                   (count + reverseCount == 1 ? " (the mesh is open)" : "s");
        if (count != 1) return name + ": its two triangles are wound the same way (inconsistent winding)";
    }
    const double volume = enclosedVolume(mesh);
    if (!(volume > 0.0)) return "its triangles face inward (enclosed volume " + std::to_string(volume) + " <= 0)";
    return {};
}

}  // namespace pcl
