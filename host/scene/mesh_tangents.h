// Per-vertex tangents for normal mapping when a mesh has none (glTF TANGENT absent, JSON meshes),
// by MikkTSpace (Mikkelsen 2008, the algorithm of its reference mikktspace.c with its default
// 180° angular threshold), which glTF names for this case and against which Blender and
// Substance bake their normal maps. Written here for triangle meshes (no Debian package ships
// mikktspace.c) and held to the reference implementation by tests/data/mikktspace-tangents.json
// (scripts/make_mikktspace_references.py compiles mikktspace.c and records its output):
//   1. corners with identical position, normal and coordinates are welded into one vertex;
//   2. per triangle, T = ∂p/∂u and B = ∂p/∂v from the edges and the UV deltas, and its
//      orientation, the sign of its UV area (a triangle of zero UV area takes the orientation of
//      the first group that reaches it);
//   3. per welded vertex, its triangles that share it and edges with it and have one orientation
//      form a group (a mirrored UV layout gives a vertex two groups);
//   4. a group's tangent is the sum of its triangles' T projected onto the vertex normal and
//      normalised, weighted by the triangle's angle at the vertex, normalised.
// MikkTSpace's tangents belong to triangle corners: a vertex whose corners got different tangents
// (two groups, or flat normals that make one position several vertices) is split into copies.
// glTF's handedness w is the opposite of MikkTSpace's sign: the bitangent N × T · w points up the
// image (toward decreasing v, glTF's v runs down), where MikkTSpace's points along +v.
#pragma once
#include <vector>

#include "scene/scene.h"

namespace pcl {

// x, y, z, w per triangle corner (3 per triangle, in index order) of `mesh`, from its texture
// coordinate set `uvSet` (which the mesh must have) and its normals (the faces' where it has none).
std::vector<float> mikkTSpaceCornerTangents(const TriangleMesh& mesh, int uvSet);

// Sets mesh.tangents from the corners' tangents (mikkTSpaceCornerTangents), splitting each vertex
// whose corners disagree into one copy per distinct tangent (positions, normals and coordinates
// copied). A vertex no triangle uses gets any unit vector perpendicular to its normal, w = +1.
void setCornerTangents(TriangleMesh& mesh, const std::vector<float>& cornerTangents);

// Both of the above: the mesh's tangents from `uvSet`, vertices split where MikkTSpace says.
void generateTangents(TriangleMesh& mesh, int uvSet);

// Generates the tangents of every mesh whose material has a normal map and that has none (from
// the map's coordinate set); validateScene calls it, and so must a caller that builds a scene in
// code without validating it.
void addMissingTangents(Scene& scene);

}  // namespace pcl
