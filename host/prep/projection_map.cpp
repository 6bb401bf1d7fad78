// Projection maps: which cells of a light's sample square can send a photon straight at a
// specular object (Jensen 1996 §3.1). Conservative by construction:
//
//  * every specular object is covered by bounding balls, each covering the object's motion over
//    the shutter and inflated a little for float rounding in the tracer: one per sphere; for
//    meshes up to 512 triangles, one per piece of each triangle split (four ways, up to four
//    times) towards 1/32 of the scene's radius; for larger meshes, one per run of at most 1/256
//    of the mesh's triangles;
//  * a cell of a direction warp (point, spot, triangle) is covered by a cone of directions: axis
//    the direction at the cell centre, half-angle the largest angle to directions sampled densely
//    on the cell border plus the largest gap between neighbouring border samples (a point between
//    two samples lies within the arc between them). Each warp is continuous and one-to-one on the
//    open cell, so the image's boundary is the image of the border and the largest angle is
//    reached there. The spot warp jumps at s1 = P_in (inner cone → falloff band), so a cell that
//    straddles it is treated as two rectangles, each with its own branch;
//  * a ray from an emission point e, |e − p| ≤ r_light, hits a ball (C, ρ) only if the half-line
//    from p in the same direction passes within ρ + r_light of C, i.e. only if its direction lies
//    in the cone around C − p of half-angle asin((ρ + r_light)/|C − p|). Two cones meet iff the
//    angle between their axes is at most the sum of their half-angles. Point and spot lights have
//    r_light = 0; a triangle light is covered by pieces (p, r_light): one ball around the whole
//    triangle over the shutter (a quick rejection), then its sub-triangles (up to 64), and a
//    cell is marked when some piece's cone meets some ball's. A piece touching a ball marks all;
//  * directional lights: all rays of a disc patch are parallel to the axis, so the patch hits a
//    ball iff its footprint on the disc plane comes within ρ of the ball centre's projection; the
//    footprint is covered by a circle found the same way as the cones.
#include "prep/projection_map.h"

#include "core/math.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace {

constexpr int kGrid = static_cast<int>(PCL_PROJ_GRID);
constexpr int kEdgeSamples = 16;         // border samples per cell edge
constexpr double kGapFactor = 1.5;       // arc length between border samples ≤ 1.5 × chord angle
constexpr int kMeshGroups = 256;         // balls per large specular mesh
constexpr size_t kSplitTriangles = 512;  // meshes up to this many triangles get split balls
constexpr size_t kSplitBalls = 4096;     // ... up to this many balls in all
constexpr size_t kAimBudget = 200000;    // lights × emitter pieces × balls: bounds the marking work

struct D3 {
    double x = 0, y = 0, z = 0;
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double length(D3 a) { return std::sqrt(dot(a, a)); }
D3 normalize(D3 a) {
    double l = length(a);
    return l > 0 ? a * (1.0 / l) : a;
}
// Angle between two directions, accurate for small and large angles alike.
double angle(D3 a, D3 b) { return std::atan2(length(cross(a, b)), dot(a, b)); }
D3 d3(const float v[4]) { return {v[0], v[1], v[2]}; }
D3 d3(Vec3 v) { return {v.x, v.y, v.z}; }
Vec3 toVec3(D3 v) { return Vec3(float(v.x), float(v.y), float(v.z)); }

struct Frame {
    D3 t, b, n;
    D3 toWorld(double x, double y, double z) const { return t * x + b * y + n * z; }
};
// makeBasis in float, exactly as the kernel builds the frame (kernels/README.md "Frames").
Frame frameOf(const float axis[4]) {
    Vec3 n(axis[0], axis[1], axis[2]), t, b;
    makeBasis(n, t, b);
    return {d3(t), d3(b), d3(n)};
}

// Shirley–Chiu concentric map of [0,1]² onto the unit disk (kernels/README.md "emit").
void concentric(double s1, double s2, double& x, double& y) {
    double a = 2.0 * s1 - 1.0, b = 2.0 * s2 - 1.0;
    if (a == 0.0 && b == 0.0) {
        x = y = 0.0;
        return;
    }
    double r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = (kPiD / 4.0) * (b / a);
    } else {
        r = b;
        phi = kPiD / 2.0 - (kPiD / 4.0) * (a / b);
    }
    x = r * std::cos(phi);
    y = r * std::sin(phi);
}

// Spot warp: cosθ from s1 by inverting the smoothstep falloff's CDF. Piece 0 is the inner
// cone (s1 ∈ [0, P_in]), piece 1 the falloff band (s1 ∈ [P_in, 1]); each is continuous on its
// closed interval, the warp jumps between them.
struct SpotWarp {
    double cosInner, cosOuter, wIn, pIn;
    explicit SpotWarp(const PclLight& l) : cosInner(l.cosInner), cosOuter(l.cosOuter) {
        wIn = 1.0 - cosInner;
        double wFall = 0.5 * (cosInner - cosOuter);
        pIn = wIn + wFall > 0.0 ? wIn / (wIn + wFall) : 1.0;
    }
    int piece(double s1) const { return (s1 < pIn || pIn >= 1.0) ? 0 : 1; }
    double cosTheta(double s1, int piece) const {
        if (piece == 0) return pIn > 0.0 ? 1.0 - std::min(1.0, s1 / pIn) * wIn : 1.0;
        double v = std::clamp((s1 - pIn) / (1.0 - pIn), 0.0, 1.0);
        double lo = 0.0, hi = 1.0;  // 2t³ − t⁴ is increasing on [0, 1]
        for (int i = 0; i < 60; ++i) {
            double t = 0.5 * (lo + hi);
            (2.0 * t * t * t - t * t * t * t < v ? lo : hi) = t;
        }
        return cosOuter + 0.5 * (lo + hi) * (cosInner - cosOuter);
    }
};

D3 uniformSphere(double s1, double s2) {
    double z = 1.0 - 2.0 * s1, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPiD * s2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// Direction of sample (s1, s2) of a point, spot or triangle light; piece: the spot branch.
D3 warpDirection(const PclLight& light, const Frame& f, const SpotWarp& spot, double s1, double s2, int piece) {
    switch (light.type) {
        case PCL_LIGHT_POINT: return uniformSphere(s1, s2);
        case PCL_LIGHT_SPOT: {
            double c = std::clamp(spot.cosTheta(s1, piece), -1.0, 1.0), s = std::sqrt(std::max(0.0, 1.0 - c * c));
            double phi = 2.0 * kPiD * s2;
            return f.toWorld(s * std::cos(phi), s * std::sin(phi), c);
        }
        default: {  // triangle: Malley's cosine hemisphere around the emitting side's normal
            double x, y;
            concentric(s1, s2, x, y);
            return f.toWorld(x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y)));
        }
    }
}

struct Ball {
    D3 c;
    double r;
};

Ball boundingBall(const std::vector<D3>& points) {
    D3 lo = points[0], hi = points[0];
    for (const D3& p : points) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    Ball b{(lo + hi) * 0.5, 0.0};
    for (const D3& p : points) b.r = std::max(b.r, length(p - b.c));
    return b;
}

// The ball around a set of balls: centred on their box, reaching the farthest one's far side.
Ball enclosingBall(const std::vector<Ball>& balls) {
    D3 lo = balls[0].c, hi = balls[0].c;
    for (const Ball& b : balls) {
        lo = {std::min(lo.x, b.c.x - b.r), std::min(lo.y, b.c.y - b.r), std::min(lo.z, b.c.z - b.r)};
        hi = {std::max(hi.x, b.c.x + b.r), std::max(hi.y, b.c.y + b.r), std::max(hi.z, b.c.z + b.r)};
    }
    Ball out{(lo + hi) * 0.5, 0.0};
    for (const Ball& b : balls) out.r = std::max(out.r, length(b.c - out.c) + b.r);
    return out;
}

// Balls covering a triangle (vertices at τ = 0; it moves by m over the shutter), split
// `depth` times into four by its edge midpoints.
void triangleBalls(D3 a, D3 b, D3 c, D3 m, int depth, std::vector<Ball>& out) {
    if (depth == 0) {
        out.push_back(boundingBall({a, b, c, a + m, b + m, c + m}));
        return;
    }
    D3 ab = (a + b) * 0.5, bc = (b + c) * 0.5, ca = (c + a) * 0.5;
    triangleBalls(a, ab, ca, m, depth - 1, out);
    triangleBalls(ab, b, bc, m, depth - 1, out);
    triangleBalls(ca, bc, c, m, depth - 1, out);
    triangleBalls(ab, bc, ca, m, depth - 1, out);
}

// Splits (each one into four) that bring a ball of radius r down to `target`, at most 4.
int splitsFor(double r, double target) {
    int d = 0;
    while (d < 4 && r / double(1 << d) > target) ++d;
    return d;
}

// Bounding balls of every specular primitive over the whole shutter interval: a primitive at
// time τ is a convex combination of its positions at τ = 0 and τ = 1. Spheres get one ball.
// Triangles of small meshes are split until their balls are about 1/32 of the scene's radius
// (a large glossy floor would otherwise be one ball holding the lights); large meshes get at
// most kMeshGroups balls, each around a run of consecutive triangles.
std::vector<Ball> specularBalls(const Scene& scene, const SceneBuffers& buffers, bool (*target)(const PclMaterial&)) {
    auto specular = [&](int material) {
        return material >= 0 && material < static_cast<int>(buffers.materials.size()) &&
               target(buffers.materials[material]);
    };
    // Float rounding in the tracer: hits may land a hair outside the exact surface.
    double slack = 1e-5 * (buffers.sceneRadius + length(d3(buffers.sceneCentre))) + 1e-7;
    std::vector<Ball> balls;
    for (const Sphere& s : scene.spheres) {
        if (!specular(s.material)) continue;
        D3 m = d3(s.motion);
        balls.push_back({d3(s.centre) + m * 0.5, s.radius + 0.5 * length(m)});
    }

    struct Tri {
        D3 a, b, c, m;
        double r;
    };
    std::vector<Tri> small;
    for (const TriangleMesh& mesh : scene.meshes) {
        if (!specular(mesh.material) || mesh.triangleCount() == 0) continue;
        size_t n = mesh.triangleCount();
        D3 m = d3(mesh.motion);
        auto vertex = [&](size_t t, int k) { return d3(mesh.positions[mesh.indices[3 * t + k]]); };
        if (n <= kSplitTriangles) {
            for (size_t t = 0; t < n; ++t) {
                Tri tri{vertex(t, 0), vertex(t, 1), vertex(t, 2), m, 0.0};
                tri.r = boundingBall({tri.a, tri.b, tri.c}).r;
                small.push_back(tri);
            }
            continue;
        }
        size_t group = (n + kMeshGroups - 1) / kMeshGroups;
        for (size_t first = 0; first < n; first += group) {
            std::vector<D3> points;
            for (size_t t = first; t < std::min(n, first + group); ++t)
                for (int k = 0; k < 3; ++k) {
                    points.push_back(vertex(t, k));
                    points.push_back(vertex(t, k) + m);
                }
            balls.push_back(boundingBall(points));
        }
    }
    double size = std::max(buffers.sceneRadius, 1e-6f) / 32.0;  // wanted ball radius
    for (;;) {
        size_t count = 0;
        for (const Tri& t : small) count += size_t(1) << (2 * splitsFor(t.r, size));
        if (count <= kSplitBalls) break;
        size *= 2.0;
    }
    for (const Tri& t : small) triangleBalls(t.a, t.b, t.c, t.m, splitsFor(t.r, size), balls);
    for (Ball& b : balls) b.r = b.r * (1.0 + 1e-5) + slack;
    return balls;
}

// The points of the closed rectangle [a0,a1] × [b0,b1]'s border, in order around it.
template <typename F>
void forBorder(double a0, double a1, double b0, double b1, F&& f) {
    for (int j = 0; j < kEdgeSamples; ++j) f(a0 + (a1 - a0) * j / kEdgeSamples, b0);
    for (int j = 0; j < kEdgeSamples; ++j) f(a1, b0 + (b1 - b0) * j / kEdgeSamples);
    for (int j = 0; j < kEdgeSamples; ++j) f(a1 - (a1 - a0) * j / kEdgeSamples, b1);
    for (int j = 0; j < kEdgeSamples; ++j) f(a0, b1 - (b1 - b0) * j / kEdgeSamples);
}

struct Cone {
    D3 axis;
    double half;
};

// The cone of directions of cell (cx, cy) of a point, spot or triangle light.
Cone cellCone(const PclLight& light, const Frame& f, const SpotWarp& spot, int cx, int cy) {
    double a0 = double(cx) / kGrid, a1 = double(cx + 1) / kGrid;
    double b0 = double(cy) / kGrid, b1 = double(cy + 1) / kGrid;
    double ac = 0.5 * (a0 + a1), bc = 0.5 * (b0 + b1);
    Cone cone{warpDirection(light, f, spot, ac, bc, spot.piece(ac)), 0.0};

    // The rectangles on which the warp is continuous: the cell, or its two parts either side
    // of the spot's jump at P_in.
    struct Rect {
        double a0, a1;
        int piece;
    };
    // The kernel decides s1 < P_in in float, so a cell within a hair of P_in gets both branches.
    Rect rects[2] = {{a0, a1, light.type == PCL_LIGHT_SPOT ? spot.piece(ac) : 0}, {a0, a1, 0}};
    int count = 1;
    const double hair = 1e-5;
    if (light.type == PCL_LIGHT_SPOT && spot.pIn > 0.0 && spot.pIn < 1.0 && a0 <= spot.pIn + hair &&
        spot.pIn - hair <= a1) {
        rects[0] = {a0, std::clamp(spot.pIn, a0, a1), 0};
        rects[1] = {std::clamp(spot.pIn, a0, a1), a1, 1};
        count = 2;
    }
    for (int i = 0; i < count; ++i) {
        const Rect& r = rects[i];
        std::vector<D3> border;
        forBorder(r.a0, r.a1, b0, b1,
                  [&](double s1, double s2) { border.push_back(warpDirection(light, f, spot, s1, s2, r.piece)); });
        double widest = 0.0, gap = 0.0;
        for (size_t k = 0; k < border.size(); ++k) {
            widest = std::max(widest, angle(cone.axis, border[k]));
            gap = std::max(gap, angle(border[k], border[(k + 1) % border.size()]));
        }
        cone.half = std::max(cone.half, widest + kGapFactor * gap + 1e-6);
    }
    return cone;
}

// The disc patch of cell (cx, cy) of a directional light, in unit-disc coordinates: a circle
// (mx, my, radius) covering the concentric map's image of the cell.
void cellPatch(int cx, int cy, double& mx, double& my, double& radius) {
    double a0 = double(cx) / kGrid, a1 = double(cx + 1) / kGrid;
    double b0 = double(cy) / kGrid, b1 = double(cy + 1) / kGrid;
    concentric(0.5 * (a0 + a1), 0.5 * (b0 + b1), mx, my);
    std::vector<std::pair<double, double>> border;
    forBorder(a0, a1, b0, b1, [&](double s1, double s2) {
        double x, y;
        concentric(s1, s2, x, y);
        border.emplace_back(x, y);
    });
    double widest = 0.0, gap = 0.0;
    for (size_t i = 0; i < border.size(); ++i) {
        const auto& p = border[i];
        const auto& q = border[(i + 1) % border.size()];
        widest = std::max(widest, std::hypot(p.first - mx, p.second - my));
        gap = std::max(gap, std::hypot(p.first - q.first, p.second - q.second));
    }
    radius = widest + kGapFactor * gap + 1e-9;
}

std::vector<uint32_t> markCells(const PclLight& light, const std::vector<Ball>& balls, int pieceDepth) {
    std::vector<uint32_t> cells;
    if (balls.empty()) return cells;
    auto all = [&] {
        for (uint32_t k = 0; k < PCL_PROJ_GRID * PCL_PROJ_GRID; ++k) cells.push_back(k);
        return cells;
    };
    // The sky: a photon's fate depends on its direction and its disc position together, so its
    // caustic photons are aimed by position (buildProjectionMaps' target ball), not by cells:
    // every cell, f = 1.
    if (light.type == PCL_LIGHT_ENVIRONMENT) return all();

    if (light.type == PCL_LIGHT_DIRECTIONAL) {
        Frame f = frameOf(light.axis);
        double R = light.radius;
        if (!(R > 0.0)) return all();
        D3 centre = d3(light.p);
        for (int cy = 0; cy < kGrid; ++cy)
            for (int cx = 0; cx < kGrid; ++cx) {
                double mx, my, radius;
                cellPatch(cx, cy, mx, my, radius);
                for (const Ball& b : balls) {
                    D3 d = b.c - centre;
                    double qx = dot(d, f.t) / R, qy = dot(d, f.b) / R;
                    if (std::hypot(qx - mx, qy - my) <= b.r / R + radius) {
                        cells.push_back(static_cast<uint32_t>(cy * kGrid + cx));
                        break;
                    }
                }
            }
        return cells;
    }

    // The emission points, as pieces (centre p, radius r) covering them: p itself, or for a
    // triangle one piece around all of it (the coarse test) and its 4^pieceDepth sub-triangles
    // over the whole shutter (the fine test, run only on cells the coarse test passes).
    struct Aim {
        D3 dir;
        double half, cosHalf, sinHalf;
    };
    auto aimsFrom = [&](const std::vector<Ball>& pieces) {
        std::vector<Aim> aims;
        for (const Ball& piece : pieces)
            for (const Ball& b : balls) {
                D3 d = b.c - piece.c;
                double dist = length(d), reach = b.r + piece.r * (1.0 + 1e-5);
                if (!(dist > reach)) {  // the piece touches a specular object's ball: every direction
                    aims.push_back({{0, 0, 1}, kPiD, -1.0, 0.0});
                    continue;
                }
                double half = std::asin(std::min(1.0, reach / dist));
                aims.push_back({d * (1.0 / dist), half, std::cos(half), std::sin(half)});
            }
        return aims;
    };
    std::vector<Ball> whole, parts;
    if (light.type == PCL_LIGHT_TRIANGLE) {
        D3 m = d3(light.motion), a = d3(light.p), b = a + d3(light.e1), c = a + d3(light.e2);
        triangleBalls(a, b, c, m, 0, whole);
        triangleBalls(a, b, c, m, pieceDepth, parts);
    } else {
        whole.push_back({d3(light.p), 0.0});
    }
    std::vector<Aim> coarse = aimsFrom(whole);
    std::vector<Aim> fine = parts.empty() ? std::vector<Aim>{} : aimsFrom(parts);
    for (const Aim& a : fine.empty() ? coarse : fine)
        if (a.half >= kPiD) return all();
    Frame f = frameOf(light.axis);
    SpotWarp spot(light);
    for (int cy = 0; cy < kGrid; ++cy)
        for (int cx = 0; cx < kGrid; ++cx) {
            Cone cone = cellCone(light, f, spot, cx, cy);
            double ch = std::cos(cone.half), sh = std::sin(cone.half);
            // angle(axis, dir) ≤ half + a.half  ⇔  axis·dir ≥ cos(half + a.half) on [0, π]
            auto meets = [&](const std::vector<Aim>& aims) {
                for (const Aim& a : aims)
                    if (cone.half + a.half >= kPiD || dot(cone.axis, a.dir) >= ch * a.cosHalf - sh * a.sinHalf - 1e-12)
                        return true;
                return false;
            };
            if (meets(coarse) && (fine.empty() || meets(fine))) cells.push_back(static_cast<uint32_t>(cy * kGrid + cx));
        }
    return cells;
}

}  // namespace

bool isSpecular(const PclMaterial& m) {
    return m.specular != PCL_SPECULAR_NONE && std::max({m.rhoS[0], m.rhoS[1], m.rhoS[2]}) > 0.0f;
}

bool isDiffuse(const PclMaterial& m) { return std::max({m.rhoD[0], m.rhoD[1], m.rhoD[2]}) > 0.0f; }

bool isPureSpecular(const PclMaterial& m) { return isSpecular(m) && !isDiffuse(m); }

namespace {

// Every light's marked cells, aiming at the objects whose material passes `target`.
std::vector<std::vector<uint32_t>> markAll(const SceneBuffers& buffers, const std::vector<Ball>& balls) {
    // Triangle lights are split into 4^depth pieces, each with its own cones (tighter than one
    // ball around the whole emitter), as far as the work budget allows.
    size_t triangles = 0;
    for (const PclLight& light : buffers.lights) triangles += light.type == PCL_LIGHT_TRIANGLE;
    int pieceDepth = 0;
    while (pieceDepth < 3 && triangles * (size_t(1) << (2 * (pieceDepth + 1))) * balls.size() <= kAimBudget)
        ++pieceDepth;
    std::vector<std::vector<uint32_t>> cells;
    for (const PclLight& light : buffers.lights) cells.push_back(markCells(light, balls, pieceDepth));
    return cells;
}

}  // namespace

void buildProjectionMaps(const Scene& scene, const SceneGeometry& geometry, SceneBuffers& buffers) {
    (void)geometry;  // bounds already live in buffers; the balls come from the scene's objects
    const std::vector<Ball> balls = specularBalls(scene, buffers, isSpecular);
    std::vector<std::vector<uint32_t>> cells = markAll(buffers, balls);
    buffers.projCells.clear();
    for (size_t i = 0; i < buffers.lights.size(); ++i) {
        PclLight& light = buffers.lights[i];
        light.projFirst = static_cast<uint32_t>(buffers.projCells.size());
        light.projCount = static_cast<uint32_t>(cells[i].size());
        buffers.projCells.insert(buffers.projCells.end(), cells[i].begin(), cells[i].end());
        // The sky aims its caustic photons by position instead: at the ball around every
        // specular ball (emit.cl). Every ray that meets a specular surface crosses its disc.
        if (light.type == PCL_LIGHT_ENVIRONMENT && !balls.empty()) {
            const Ball target = enclosingBall(balls);
            light.e1[0] = float(target.c.x), light.e1[1] = float(target.c.y), light.e1[2] = float(target.c.z);
            // Rounded up, so the float ball still holds every specular ball.
            light.e1[3] = std::nextafter(float(target.r), std::numeric_limits<float>::infinity());
        }
    }
}

bool skySendsCausticPhotons(const SceneBuffers& buffers) {
    for (const PclLight& l : buffers.lights)
        if (l.type == PCL_LIGHT_ENVIRONMENT && l.projCount > 0) return true;
    return false;
}

void clearSkyProjection(SceneBuffers& buffers) {
    for (PclLight& l : buffers.lights)
        if (l.type == PCL_LIGHT_ENVIRONMENT) l.projCount = 0;
}

LightSampleRay warpLightSample(const PclLight& light, double s1, double s2, double u1, double u2, double time) {
    Frame f = frameOf(light.axis);
    SpotWarp spot(light);
    D3 origin = d3(light.p), direction;
    if (light.type == PCL_LIGHT_DIRECTIONAL) {
        double x, y;
        concentric(s1, s2, x, y);
        double R = light.radius;
        origin = origin + f.t * (R * x) + f.b * (R * y) - f.n * (2.0 * R);
        direction = f.n;
    } else {
        direction = warpDirection(light, f, spot, s1, s2, spot.piece(s1));
        if (light.type == PCL_LIGHT_TRIANGLE) {
            double su = std::sqrt(u1), b0 = 1.0 - su, b1 = u2 * su;
            origin = origin + d3(light.e1) * b1 + d3(light.e2) * (1.0 - b0 - b1) + d3(light.motion) * time;
        }
    }
    return {toVec3(origin), toVec3(normalize(direction))};
}

}  // namespace pcl
