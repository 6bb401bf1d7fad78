// Per-vertex tangents for normal mapping when a mesh has none (glTF TANGENT absent, JSON meshes):
// MikkTSpace-style, not bit-exact MikkTSpace (no Debian package of it exists, and the normal maps
// this project ships or tests are tangent-space maps of smooth or flat surfaces, where the two
// agree up to the weighting of a vertex's triangles):
//   1. per triangle, the tangent T = ∂p/∂u and bitangent B = ∂p/∂v from the edges and the UV
//      deltas (Lengyel 2001; skipped where the UV triangle is degenerate);
//   2. per vertex, T and B of its triangles projected onto the plane of the vertex normal,
//      normalised and accumulated weighted by the triangle's angle at the vertex (MikkTSpace's
//      weighting); the vertex normal is the mesh's, else the angle-weighted face normal;
//   3. T Gram–Schmidt orthonormalised against the vertex normal, and the handedness
//      w = sign((N × T) · (−B)): glTF's bitangent N × T · w points up the image, toward
//      decreasing v (glTF's v runs down), so a mirrored UV layout gets w = −1.
// A vertex no triangle gives a tangent gets any unit vector perpendicular to its normal, w = +1.
#pragma once
#include <vector>

#include "scene/scene.h"

namespace pcl {

// x, y, z, w per vertex of `mesh` (unit xyz ⟂ the vertex normal, w = ±1), from the texture
// coordinate set `uvSet` (which the mesh must have).
std::vector<float> generateTangents(const TriangleMesh& mesh, int uvSet);

// Generates the tangents of every mesh whose material has a normal map and that has none (from
// the map's coordinate set); validateScene calls it, and so must a caller that builds a scene in
// code without validating it.
void addMissingTangents(Scene& scene);

}  // namespace pcl
