// The scene model: plain structs in world space, SI radiometric units. Loaders (JSON, glTF)
// fill it; geometry/ flattens it into the arrays that kernels and the CPU twin read.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "image/image.h"
#include "scene/texture.h"

namespace pcl {

enum class SpecularKind { None, Mirror, Glossy, Dielectric };

// Jensen's mixed surface: a diffuse part ρd and a specular part ρs, ρd + ρs ≤ 1 per channel.
// Photons pick diffuse with probability ρd, specular with ρs, absorption otherwise.
struct Material {
    std::string name;
    Vec3 rhoD{0.0f};
    Vec3 rhoS{0.0f};
    SpecularKind specular = SpecularKind::None;
    float phongExponent = 0.0f;  // Glossy: normalised Phong lobe (n+2)/(2π) cos^n around the mirror direction
    float ior = 1.5f;            // Dielectric: index of refraction inside (outside is 1)
    Vec3 emission{0.0f};         // one-sided emitted radiance, W m^-2 sr^-1, on the geometric-normal side
    // No surface at all: rays pass straight through. Only the boundary of a medium (a shape with
    // a medium and no material in the scene file) has it; it reflects nothing and emits nothing.
    bool interface = false;
    // Texture slots (kernels/shared/texture.h), each an index into Scene::textures or -1; meshes
    // only (spheres have no coordinates). Without metallicRoughness (the Phong mapping):
    //   rhoDTexture      ρd at a point is rhoD × the texture there (rhoD: the texture's factor)
    //   rhoSTexture      ρs = rhoS × the texture (mirror, glossy)
    //   exponentTexture  glossy: exponent = lo + (hi − lo) × the texture's R, [lo, hi] = exponentRange
    //   emissionTexture  emitted radiance = emission × the texture (either mapping; glTF
    //                    emissiveTexture, its factor emissiveFactor × emissive strength)
    // With metallicRoughness (glTF with a metallicRoughnessTexture), rhoDTexture is the base
    // colour and exponentTexture the metallic (B) and roughness (G) texture; ρd, ρs and the
    // exponent come per texel from them and the factors below (scenes/README.md, "Materials").
    int rhoDTexture = -1;
    // Index into Scene::textures, or -1: a tangent-space normal map (glTF normalTexture; linear
    // texels, rgb = (n + 1)/2), its x and y scaled by normalScale. Meshes only; they get
    // tangents (TriangleMesh::tangents) from the file or scene/mesh_tangents.h.
    int normalTexture = -1;
    float normalScale = 1.0f;
    int rhoSTexture = -1;
    int exponentTexture = -1;
    int emissionTexture = -1;
    float exponentRange[2] = {0.0f, 0.0f};
    struct MetallicRoughness {
        bool active = false;
        Vec3 baseColor{1.0f};                     // baseColorFactor
        float metallic = 1.0f, roughness = 1.0f;  // metallicFactor, roughnessFactor
        float f0 = 0.04f;                         // the dielectric coat's F0 = ((n − 1)/(n + 1))²
    } metallicRoughness;
    bool emits() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
    bool textured() const {
        return rhoDTexture >= 0 || rhoSTexture >= 0 || exponentTexture >= 0 || emissionTexture >= 0;
    }
};

// A homogeneous participating medium (pbrt-v4 §11.1): absorption σa and scattering σs per
// channel in 1/m, and the Henyey–Greenstein asymmetry g in (−1, 1) (g > 0 scatters forward).
// It fills the inside of the closed shapes that name it, or the whole scene (Scene::globalMedium).
struct Medium {
    std::string name;
    Vec3 sigmaA{0.0f};
    Vec3 sigmaS{0.0f};
    float g = 0.0f;
    Vec3 sigmaT() const { return sigmaA + sigmaS; }
};

// Triangle soup with shared vertices. Winding is counter-clockwise seen from the front side;
// the geometric normal is normalize(cross(p1 - p0, p2 - p0)).
struct TriangleMesh {
    std::string name;
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // optional per-vertex shading normals (empty: geometric)
    // Optional per-vertex tangents for normal maps: x, y, z, w (glTF TANGENT: unit xyz along
    // ∂p/∂u, w = ±1 the bitangent's sign, B = (N × T) w); filled by addMissingTangents for the
    // meshes of normal-mapped materials that have none.
    std::vector<float> tangents;
    std::vector<uint32_t> indices;  // three per triangle
    // Texture coordinate sets 0 and 1: (u, v) per vertex, or empty. A mesh whose material has a
    // texture has the set it names.
    std::vector<float> uv[2];
    int material = 0;
    Vec3 motion{0.0f};  // translation over the shutter interval
    int medium = -1;    // index into Scene::media filling the inside (closed, outward-facing mesh), or -1
    size_t triangleCount() const { return indices.size() / 3; }
};

struct Sphere {
    std::string name;
    Vec3 centre{0.0f};
    float radius = 1.0f;
    int material = 0;
    Vec3 motion{0.0f};
    int medium = -1;  // index into Scene::media filling the inside, or -1
};

enum class LightType { Point, Spot, Area, Directional };

// Lights are stored by intensity / irradiance / radiance whichever way the file gave them;
// the loader converts power-specified lights so that power() is exact.
struct Light {
    LightType type = LightType::Point;
    std::string name;
    Vec3 position{0.0f};       // Point, Spot
    Vec3 direction{0, -1, 0};  // Spot: cone axis; Directional: direction light travels (unit)
    Vec3 intensity{0.0f};      // Point, Spot: W/sr on the axis
    float cosInner = 1.0f;     // Spot: full intensity inside, smoothstep falloff to cosOuter
    float cosOuter = 0.0f;
    Vec3 irradiance{0.0f};  // Directional: W/m^2 on a surface facing the light
    int mesh = -1;          // Area: index into Scene::meshes; radiance is that mesh's material emission
};

// Light arriving from infinitely far away in every direction: a sky. Radiance scale × the
// equirectangular image's texel the direction falls in (prep/environment_map.h has the mapping),
// or the scale alone when there is no image (a constant environment). Turned by
// `rotationDegrees` about +y.
struct Environment {
    Vec3 scale{0.0f};       // W m^-2 sr^-1 per unit of the image (constant radiance without one)
    std::string imagePath;  // the file it came from ("" for a constant environment)
    Image image;            // linear RGB, every texel finite and >= 0; empty for a constant one
    float rotationDegrees = 0.0f;
    bool active() const { return scale.x > 0 || scale.y > 0 || scale.z > 0; }
};

enum class CameraModel { Pinhole, ThinLens };

struct Camera {
    CameraModel model = CameraModel::Pinhole;
    Vec3 position{0, 0, 5};
    Vec3 lookAt{0, 0, 0};
    Vec3 up{0, 1, 0};
    float vfovDegrees = 40.0f;
    int width = 256, height = 256;
    float apertureRadius = 0.0f;                    // ThinLens
    float focusDistance = 1.0f;                     // ThinLens
    float shutterOpen = 0.0f, shutterClose = 0.0f;  // seconds; motion is spread over this interval
};

struct Scene {
    std::string path;  // the file it came from, for messages and metadata
    std::vector<Material> materials;
    std::vector<TriangleMesh> meshes;
    std::vector<Sphere> spheres;
    std::vector<Light> lights;
    std::vector<Medium> media;
    std::vector<Texture> textures;  // what Material's texture slots index
    int globalMedium = -1;          // index into media filling all space outside the shapes with their own (fog), or -1
    Environment environment;        // inactive (scale 0) unless the file names one
    Camera camera;
    size_t droppedDegenerateTriangles = 0;

    size_t triangleCount() const {
        size_t n = 0;
        for (const auto& m : meshes) n += m.triangleCount();
        return n;
    }
    // Whether any medium is in use (a shape's or the global one); an unused entry in media is not.
    bool hasMedia() const {
        if (globalMedium >= 0) return true;
        for (const auto& m : meshes)
            if (m.medium >= 0) return true;
        for (const auto& s : spheres)
            if (s.medium >= 0) return true;
        return false;
    }
    bool hasTextures() const {
        for (const auto& m : materials)
            if (m.textured() || m.normalTexture >= 0) return true;
        return false;
    }
    bool hasMotion() const {
        for (const auto& m : meshes)
            if (!(m.motion == Vec3(0.0f))) return true;
        for (const auto& s : spheres)
            if (!(s.motion == Vec3(0.0f))) return true;
        return false;
    }
};

}  // namespace pcl
