// Scenes and scene pieces built in code for the tests (unit and stages), and the list of
// shipped scene files: no test data to ship or load.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pcl::test_scenes {

// Every shipped scene file under scenes/, sorted: JSON, and glTF where the build can load it.
inline std::vector<std::filesystem::path> shippedSceneFiles() {
    namespace fs = std::filesystem;
    fs::path dir = fs::path(PHOTONCL_SOURCE_DIR) / "scenes";
    std::vector<fs::path> files;
    if (fs::is_directory(dir))
        for (const auto& e : fs::directory_iterator(dir)) {
            const fs::path& p = e.path();
            bool scene = p.extension() == ".json";
#ifdef PHOTONCL_HAVE_GLTF
            scene = scene || p.extension() == ".gltf" || p.extension() == ".glb";
#endif
            if (scene) files.push_back(p);
        }
    std::sort(files.begin(), files.end());
    return files;
}

// n unconnected triangles with centres uniform in [-1, 1]³ and vertices up to `size` from them
// on each axis, all moving by `motion`.
inline TriangleMesh randomSoup(size_t n, uint32_t seed, float size, Vec3 motion = Vec3(0.0f)) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    TriangleMesh m;
    m.motion = motion;
    for (size_t i = 0; i < n; ++i) {
        Vec3 c(u(rng), u(rng), u(rng));
        for (int k = 0; k < 3; ++k) {
            m.positions.push_back(c + Vec3(u(rng), u(rng), u(rng)) * size);
            m.indices.push_back(static_cast<uint32_t>(m.positions.size() - 1));
        }
    }
    return m;
}

// A material named "m<its index>"; returns the index.
inline int addMaterial(Scene& s, Vec3 rhoD, Vec3 rhoS = Vec3(0.0f), SpecularKind kind = SpecularKind::None,
                       Vec3 emission = Vec3(0.0f), float phongExponent = 50.0f) {
    Material m;
    m.name = "m" + std::to_string(s.materials.size());
    m.rhoD = rhoD;
    m.rhoS = rhoS;
    m.specular = kind;
    m.phongExponent = phongExponent;
    m.emission = emission;
    s.materials.push_back(m);
    return static_cast<int>(s.materials.size()) - 1;
}

// A diffuse emitter (or, with emission 0, a plain Lambertian material); returns the index.
inline int addEmitter(Scene& s, Vec3 rhoD, Vec3 emission) {
    return addMaterial(s, rhoD, Vec3(0.0f), SpecularKind::None, emission);
}

// A pinhole camera at pos looking at `at`, vfov degrees, w × h pixels.
inline void setCamera(Scene& scene, Vec3 pos, Vec3 at, Vec3 up, float vfov, int w, int h) {
    scene.camera.position = pos;
    scene.camera.lookAt = at;
    scene.camera.up = up;
    scene.camera.vfovDegrees = vfov;
    scene.camera.width = w;
    scene.camera.height = h;
}

// The pinhole ray through film position (fx, fy) ∈ [0,1)² of pixel (x, y), from the camera's
// definition, independently of reference/camera.cpp.
inline Vec3 pinholeDirection(const Camera& cam, int x, int y, float fx, float fy) {
    Vec3 f = normalize(cam.lookAt - cam.position), r = normalize(cross(f, cam.up)), u = cross(r, f);
    float th = std::tan(cam.vfovDegrees * (3.14159265358979f / 360.0f)), tw = th * cam.width / cam.height;
    float sx = (2.0f * (x + fx) / cam.width - 1.0f) * tw, sy = (1.0f - 2.0f * (y + fy) / cam.height) * th;
    return normalize(f + r * sx + u * sy);
}

// g averaged over the points of the plane y = 0 seen in pixel (x, y) (an n×n grid).
template <class G>
double pixelAverageOnGround(const Camera& cam, int x, int y, G g, int n = 8) {
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            Vec3 d = pinholeDirection(cam, x, y, (i + 0.5f) / n, (j + 0.5f) / n);
            sum += g(cam.position + d * (-cam.position.y / d.y));
        }
    return sum / (n * n);
}

// The quad corner, corner + u, corner + u + v, corner + v as one mesh of two triangles; returns
// the mesh index.
inline int addQuad(Scene& s, Vec3 corner, Vec3 u, Vec3 v, int material, Vec3 motion = Vec3(0.0f),
                   std::string name = "") {
    TriangleMesh m;
    m.name = std::move(name);
    m.positions = {corner, corner + u, corner + u + v, corner + v};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    m.motion = motion;
    s.meshes.push_back(m);
    return static_cast<int>(s.meshes.size()) - 1;
}

inline void addSphere(Scene& s, Vec3 c, float r, int material, Vec3 motion = Vec3(0.0f)) {
    Sphere sp;
    sp.centre = c;
    sp.radius = r;
    sp.material = material;
    sp.motion = motion;
    s.spheres.push_back(sp);
}

// A point light of intensity 1.
inline Light pointLight(Vec3 p) {
    Light l;
    l.type = LightType::Point;
    l.position = p;
    l.intensity = Vec3(1.0f);
    return l;
}

// An invisible medium boundary (paths pass straight through); returns the material index.
inline int addBoundaryMaterial(Scene& scene) {
    int m = addMaterial(scene, Vec3(0.0f));
    scene.materials[size_t(m)].interface = true;
    return m;
}
// A clear dielectric of index ior.
inline int addGlass(Scene& scene, float ior) {
    int m = addMaterial(scene, Vec3(0.0f));
    scene.materials[size_t(m)].specular = SpecularKind::Dielectric;
    scene.materials[size_t(m)].rhoS = Vec3(1.0f);
    scene.materials[size_t(m)].ior = ior;
    return m;
}
// A homogeneous medium; returns its index (scene.globalMedium or a shape's medium).
inline int addMedium(Scene& scene, Vec3 sigmaA, Vec3 sigmaS, float g) {
    Medium m;
    m.name = "medium" + std::to_string(scene.media.size());
    m.sigmaA = sigmaA;
    m.sigmaS = sigmaS;
    m.g = g;
    scene.media.push_back(m);
    return static_cast<int>(scene.media.size()) - 1;
}

// The box lo..hi as 12 triangles facing outward (inward = true: facing inward, as six quads).
inline void addBox(Scene& scene, Vec3 lo, Vec3 hi, int material, int medium, bool inward = false) {
    TriangleMesh m;
    m.name = "box" + std::to_string(scene.meshes.size());
    for (int i = 0; i < 8; ++i)
        m.positions.push_back(Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z));
    // Outward, counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    m.indices = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                 2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
    if (inward)
        for (size_t t = 0; t < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
    m.material = material;
    m.medium = medium;
    scene.meshes.push_back(m);
}
// A sphere holding `medium` (−1: none) inside.
inline void addMediumSphere(Scene& scene, Vec3 c, float r, int material, int medium) {
    Sphere s;
    s.name = "sphere" + std::to_string(scene.spheres.size());
    s.centre = c;
    s.radius = r;
    s.material = material;
    s.medium = medium;
    scene.spheres.push_back(s);
}

// A plane of albedo rho (y = 0, 100 × 100) seen from 1 above by an 8 × 8 camera, under a sky of
// one bright texel (tx, ty) of value V in a W × H image turned 25° about +y; and what that sky
// equals: a directional light of irradiance V Ω_texel from the texel's centre direction (`sun`,
// the same scene with that light instead of the sky), and the plane's radiance in closed form,
// ρ/π · V (π/W)(sin²θ1 − sin²θ0).
struct OneTexelSkyPlane {
    Scene sky, sun;
    float expected = 0.0f;
};
inline OneTexelSkyPlane oneTexelSkyPlane(int W, int H, int tx, int ty, float V, float rho) {
    constexpr double pi = 3.14159265358979323846;
    OneTexelSkyPlane r;
    Scene& scene = r.sky;
    addQuad(scene, Vec3(-50, 0, -50), Vec3(0, 0, 100), Vec3(100, 0, 0), addMaterial(scene, Vec3(rho)));
    setCamera(scene, Vec3(0, 1, 0), Vec3(0.01f, 0, 0), Vec3(0, 0, -1), 30.0f, 8, 8);
    scene.environment.scale = Vec3(1.0f);
    scene.environment.image = Image(W, H);
    scene.environment.image.set(tx, ty, Vec3(V));
    scene.environment.imagePath = "one-texel";
    scene.environment.rotationDegrees = 25.0f;
    // E = V (2π/W) ∫ cos θ sin θ dθ over the texel's rows = V (π/W)(sin²θ1 − sin²θ0).
    const double theta0 = pi * ty / H, theta1 = pi * (ty + 1) / H;
    const double E = V * pi / W * (std::sin(theta1) * std::sin(theta1) - std::sin(theta0) * std::sin(theta0));
    r.expected = float(rho / pi * E);

    r.sun = scene;
    r.sun.environment = Environment{};
    const double omega = 2.0 * pi / W * (std::cos(theta0) - std::cos(theta1));
    const double thetaC = 0.5 * (theta0 + theta1), phiC = 2.0 * pi * (tx + 0.5) / W;
    const Vec3 local(float(std::sin(thetaC) * std::sin(phiC)), float(std::cos(thetaC)),
                     float(-std::sin(thetaC) * std::cos(phiC)));
    const double a = 25.0 * pi / 180.0;
    const Vec3 towardSky(float(std::cos(a) * local.x + std::sin(a) * local.z), local.y,
                         float(-std::sin(a) * local.x + std::cos(a) * local.z));
    Light light;
    light.type = LightType::Directional;
    light.direction = -towardSky;
    light.irradiance = Vec3(float(V * omega));
    r.sun.lights.push_back(light);
    return r;
}

}  // namespace pcl::test_scenes
