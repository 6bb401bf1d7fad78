#include "scene/validate.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "scene/mesh_tangents.h"
#include "scene/mesh_topology.h"
#include "scene/scene_error.h"

namespace pcl {

namespace {

std::string show(Vec3 v) {
    auto f = [](float x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", double(x));
        return std::string(buf);
    };
    return "[" + f(v.x) + "," + f(v.y) + "," + f(v.z) + "]";
}
std::string at(const char* what, size_t i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

bool inUnitRange(Vec3 v) { return isFinite(v) && v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x <= 1 && v.y <= 1 && v.z <= 1; }
bool nonNegative(Vec3 v) { return isFinite(v) && v.x >= 0 && v.y >= 0 && v.z >= 0; }

void checkMaterials(const Scene& s) {
    for (size_t i = 0; i < s.materials.size(); ++i) {
        const Material& m = s.materials[i];
        std::string f = at("materials", i) + " (\"" + m.name + "\")";
        if (!inUnitRange(m.rhoD)) failInput(s.path, f + ".rho_d", "3 numbers in [0,1]", show(m.rhoD));
        if (!inUnitRange(m.rhoS)) failInput(s.path, f + ".rho_s", "3 numbers in [0,1]", show(m.rhoS));
        if (maxComponent(m.rhoD + m.rhoS) > 1.0f + 1e-6f)
            failInput(s.path, f, "rho_d + rho_s <= 1 in every channel", show(m.rhoD + m.rhoS));
        if (!nonNegative(m.emission)) failInput(s.path, f + ".emission", "3 finite numbers >= 0", show(m.emission));
        if (m.specular == SpecularKind::Glossy && !(m.phongExponent > 0 && std::isfinite(m.phongExponent)))
            failInput(s.path, f + ".exponent", "a Phong exponent > 0", std::to_string(m.phongExponent));
        if (m.specular == SpecularKind::Dielectric && !(m.ior > 0 && std::isfinite(m.ior)))
            failInput(s.path, f + ".ior", "an index of refraction > 0", std::to_string(m.ior));
    }
}

bool degenerate(Vec3 a, Vec3 b, Vec3 c) {
    if (!isFinite(a) || !isFinite(b) || !isFinite(c)) return true;
    Vec3 e1 = b - a, e2 = c - a, e3 = c - b;
    float n = length(cross(e1, e2));
    float longest = std::max(dot(e1, e1), std::max(dot(e2, e2), dot(e3, e3)));
    // Zero area, or so thin that the normal is float round-off (below ~ε of the longest edge²).
    return !(n > 1e-7f * longest) || !std::isfinite(n);
}

// Drops degenerate triangles, then meshes left empty (remapping Light::mesh).
void dropDegenerateTriangles(Scene& s) {
    size_t dropped = 0;
    for (auto& m : s.meshes) {
        std::vector<uint32_t> kept;
        kept.reserve(m.indices.size());
        for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            uint32_t i0 = m.indices[t], i1 = m.indices[t + 1], i2 = m.indices[t + 2];
            if (degenerate(m.positions[i0], m.positions[i1], m.positions[i2])) {
                ++dropped;
                continue;
            }
            kept.insert(kept.end(), {i0, i1, i2});
        }
        m.indices.swap(kept);
    }
    if (dropped > 0) {
        warnInput(s.path, "dropped " + std::to_string(dropped) + " degenerate (zero-area or non-finite) triangle" +
                              (dropped == 1 ? "" : "s"));
        s.droppedDegenerateTriangles += dropped;
    }
    std::vector<int> newIndex(s.meshes.size(), -1);
    std::vector<TriangleMesh> kept;
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        if (s.meshes[i].indices.empty()) continue;
        newIndex[i] = int(kept.size());
        kept.push_back(std::move(s.meshes[i]));
    }
    s.meshes.swap(kept);
    std::vector<Light> lights;
    for (auto& l : s.lights) {
        if (l.type == LightType::Area) {
            if (l.mesh < 0 || size_t(l.mesh) >= newIndex.size())
                failInput(s.path, "lights (\"" + l.name + "\")", "an area light on an existing mesh",
                          "mesh index " + std::to_string(l.mesh));
            if (newIndex[size_t(l.mesh)] < 0) {
                warnInput(s.path, "area light \"" + l.name + "\" lost all its triangles and is dropped");
                continue;
            }
            l.mesh = newIndex[size_t(l.mesh)];
        }
        lights.push_back(l);
    }
    s.lights.swap(lights);
}

void checkMeshes(Scene& s) {
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        TriangleMesh& m = s.meshes[i];
        std::string f = at("meshes", i) + " (\"" + m.name + "\")";
        if (m.material < 0 || size_t(m.material) >= s.materials.size())
            failInput(s.path, f + ".material", "a material index below " + std::to_string(s.materials.size()),
                      std::to_string(m.material));
        if (m.indices.size() % 3 != 0)
            failInput(s.path, f + ".indices", "a multiple of 3 indices", std::to_string(m.indices.size()));
        for (uint32_t k : m.indices)
            if (k >= m.positions.size())
                failInput(s.path, f + ".indices", "vertex indices below " + std::to_string(m.positions.size()),
                          std::to_string(k));
        if (!m.normals.empty() && m.normals.size() != m.positions.size())
            failInput(s.path, f + ".normals", std::to_string(m.positions.size()) + " normals (one per position)",
                      std::to_string(m.normals.size()));
        if (!isFinite(m.motion)) failInput(s.path, f + ".motion", "3 finite numbers", show(m.motion));
        // Shading normals that cannot be normalised are useless; fall back to geometric normals.
        for (auto& n : m.normals) {
            float l = length(n);
            if (!(l > 0) || !std::isfinite(l)) {
                warnInput(s.path, f + ": zero or non-finite normals; using geometric normals for this mesh");
                m.normals.clear();
                break;
            }
            n = n / l;
        }
    }
}

void checkSpheres(const Scene& s) {
    for (size_t i = 0; i < s.spheres.size(); ++i) {
        const Sphere& sp = s.spheres[i];
        std::string f = at("spheres", i) + " (\"" + sp.name + "\")";
        if (!isFinite(sp.centre)) failInput(s.path, f + ".centre", "3 finite numbers", show(sp.centre));
        if (!(sp.radius > 0) || !std::isfinite(sp.radius))
            failInput(s.path, f + ".radius", "a number > 0", std::to_string(sp.radius));
        if (sp.material < 0 || size_t(sp.material) >= s.materials.size())
            failInput(s.path, f + ".material", "a material index below " + std::to_string(s.materials.size()),
                      std::to_string(sp.material));
        if (s.materials[size_t(sp.material)].emits())
            failInput(s.path, f + ".material", "a non-emissive material (emitting spheres are not supported)",
                      "\"" + s.materials[size_t(sp.material)].name + "\"");
        if (!isFinite(sp.motion)) failInput(s.path, f + ".motion", "3 finite numbers", show(sp.motion));
    }
}

// Every emissive mesh gets exactly one Light{Area}, whichever loader made it.
void linkEmitters(Scene& s) {
    std::vector<bool> hasLight(s.meshes.size(), false);
    for (const auto& l : s.lights)
        if (l.type == LightType::Area) hasLight[size_t(l.mesh)] = true;
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        if (hasLight[i] || !s.materials[size_t(s.meshes[i].material)].emits()) continue;
        Light l;
        l.type = LightType::Area;
        l.name = s.meshes[i].name;
        l.mesh = int(i);
        s.lights.push_back(l);
    }
}

void checkLights(const Scene& s) {
    if (s.lights.empty() && !s.environment.active())
        failInput(s.path, "lights", "at least one light, emissive surface or environment", "none");
    std::vector<int> areaLightsPerMesh(s.meshes.size(), 0);
    for (size_t i = 0; i < s.lights.size(); ++i) {
        const Light& l = s.lights[i];
        std::string f = at("lights", i) + " (\"" + l.name + "\")";
        switch (l.type) {
            case LightType::Point:
            case LightType::Spot:
                if (!isFinite(l.position)) failInput(s.path, f + ".position", "3 finite numbers", show(l.position));
                if (!nonNegative(l.intensity) || !(maxComponent(l.intensity) > 0))
                    failInput(s.path, f + ".intensity", "3 finite numbers >= 0, not all zero", show(l.intensity));
                if (l.type == LightType::Spot) {
                    if (!isFinite(l.direction) || std::abs(length(l.direction) - 1.0f) > 1e-3f)
                        failInput(s.path, f + ".direction", "a unit vector", show(l.direction));
                    if (!(l.cosOuter >= 0.0f && l.cosOuter < 1.0f && l.cosInner >= l.cosOuter && l.cosInner <= 1.0f))
                        failInput(s.path, f, "0 <= inner angle <= outer angle <= 90 degrees, outer > 0",
                                  "cos inner " + std::to_string(l.cosInner) + ", cos outer " +
                                      std::to_string(l.cosOuter));
                }
                break;
            case LightType::Directional:
                if (!isFinite(l.direction) || std::abs(length(l.direction) - 1.0f) > 1e-3f)
                    failInput(s.path, f + ".direction", "a unit vector", show(l.direction));
                if (!nonNegative(l.irradiance) || !(maxComponent(l.irradiance) > 0))
                    failInput(s.path, f + ".irradiance", "3 finite numbers >= 0, not all zero", show(l.irradiance));
                break;
            case LightType::Area:
                if (l.mesh < 0 || size_t(l.mesh) >= s.meshes.size())
                    failInput(s.path, f + ".mesh", "a mesh index below " + std::to_string(s.meshes.size()),
                              std::to_string(l.mesh));
                if (!s.materials[size_t(s.meshes[size_t(l.mesh)].material)].emits())
                    failInput(s.path, f, "an area light on a mesh with an emissive material",
                              "mesh \"" + s.meshes[size_t(l.mesh)].name + "\" that does not emit");
                if (++areaLightsPerMesh[size_t(l.mesh)] > 1)
                    failInput(s.path, f, "one area light per emissive mesh",
                              "a second one on mesh " + std::to_string(l.mesh));
                break;
        }
    }
}

void checkCamera(const Scene& s) {
    const Camera& c = s.camera;
    if (!isFinite(c.position) || !isFinite(c.lookAt) || !isFinite(c.up) || !(length(c.lookAt - c.position) > 0))
        failInput(s.path, "camera", "finite position, look_at and up with look_at != position",
                  show(c.position) + " -> " + show(c.lookAt));
    if (!(length(cross(normalize(c.lookAt - c.position), normalize(c.up))) > 1e-4f))
        failInput(s.path, "camera.up", "a direction not parallel to the viewing direction", show(c.up));
    if (!(c.vfovDegrees > 0 && c.vfovDegrees < 180))
        failInput(s.path, "camera.fov", "degrees in (0, 180)", std::to_string(c.vfovDegrees));
    if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384)
        failInput(s.path, "camera.resolution", "width and height in [1, 16384]",
                  std::to_string(c.width) + "x" + std::to_string(c.height));
    if (c.model == CameraModel::ThinLens && !(c.apertureRadius > 0 && std::isfinite(c.apertureRadius) &&
                                              c.focusDistance > 0 && std::isfinite(c.focusDistance)))
        failInput(s.path, "camera", "a thin lens with aperture_radius > 0 and focus_distance > 0",
                  std::to_string(c.apertureRadius) + ", " + std::to_string(c.focusDistance));
    if (!(c.shutterOpen >= 0 && c.shutterOpen <= c.shutterClose && std::isfinite(c.shutterClose)))
        failInput(s.path, "camera.shutter", "0 <= open <= close",
                  "[" + std::to_string(c.shutterOpen) + "," + std::to_string(c.shutterClose) + "]");
    // Motion is the displacement over the shutter interval; with a closed shutter it cannot show.
    if (s.hasMotion() && !(c.shutterClose > c.shutterOpen))
        failInput(s.path, "camera.shutter", "an interval with close > open, since objects have motion",
                  "[" + std::to_string(c.shutterOpen) + "," + std::to_string(c.shutterClose) + "]");
}

// Media: coefficients, g, the references to them, and shapes that can hold one (after degenerate
// triangles are dropped, which may open a mesh).
void checkMedia(const Scene& s) {
    for (size_t i = 0; i < s.media.size(); ++i) {
        const Medium& m = s.media[i];
        std::string f = at("media", i) + " (\"" + m.name + "\")";
        if (!nonNegative(m.sigmaA)) failInput(s.path, f + ".sigma_a", "3 finite numbers >= 0 (1/m)", show(m.sigmaA));
        if (!nonNegative(m.sigmaS)) failInput(s.path, f + ".sigma_s", "3 finite numbers >= 0 (1/m)", show(m.sigmaS));
        if (!(maxComponent(m.sigmaT()) > 0))
            failInput(s.path, f, "sigma_a + sigma_s > 0 in some channel", show(m.sigmaT()));
        if (!(std::abs(m.g) < 1.0f))
            failInput(s.path, f + ".g", "a Henyey-Greenstein g in (-1, 1)", std::to_string(m.g));
    }
    auto checkRef = [&](int medium, const std::string& f) {
        if (medium < -1 || medium >= int(s.media.size()))
            failInput(s.path, f, "a medium index below " + std::to_string(s.media.size()) + " (or none)",
                      std::to_string(medium));
    };
    checkRef(s.globalMedium, "medium");
    for (size_t i = 0; i < s.spheres.size(); ++i)
        checkRef(s.spheres[i].medium, at("spheres", i) + " (\"" + s.spheres[i].name + "\").medium");
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        const TriangleMesh& m = s.meshes[i];
        std::string f = at("meshes", i) + " (\"" + m.name + "\").medium";
        checkRef(m.medium, f);
        if (m.medium < 0) continue;
        std::string problem = closedMeshProblem(m);
        if (!problem.empty())
            failInput(s.path, f,
                      "a closed mesh to hold medium \"" + s.media[size_t(m.medium)].name +
                          "\" (every edge shared by exactly two triangles, consistently wound, facing outward)",
                      problem);
    }
    // A boundary that is no surface must bound something.
    for (size_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].interface &&
            (s.materials[i].emits() || maxComponent(s.materials[i].rhoD + s.materials[i].rhoS) > 0))
            failInput(s.path, at("materials", i), "an invisible medium boundary that neither reflects nor emits",
                      "\"" + s.materials[i].name + "\"");
}

// Texture references and coordinates: a textured material names an existing texture, is used by
// meshes only, and every such mesh has the coordinate set it names (2 finite numbers a vertex).
void checkTextures(const Scene& s) {
    for (size_t i = 0; i < s.materials.size(); ++i) {
        const Material& m = s.materials[i];
        const std::pair<int, const char*> slots[] = {{m.rhoDTexture, "rho_d"},
                                                     {m.rhoSTexture, "rho_s"},
                                                     {m.exponentTexture, "exponent"},
                                                     {m.emissionTexture, "emission"}};
        for (const auto& [t, name] : slots)
            if (t >= int(s.textures.size()) || t < -1)
                failInput(s.path, at("materials", i) + " (\"" + m.name + "\")." + name,
                          "a texture index below " + std::to_string(s.textures.size()), std::to_string(t));
        if (m.normalTexture >= int(s.textures.size()) || m.normalTexture < -1)
            failInput(s.path, at("materials", i) + " (\"" + m.name + "\").normal_map",
                      "a texture index below " + std::to_string(s.textures.size()), std::to_string(m.normalTexture));
        if (!std::isfinite(m.normalScale))
            failInput(s.path, at("materials", i) + " (\"" + m.name + "\").normal_map.normal_scale", "a finite number",
                      std::to_string(m.normalScale));
    }
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        const TriangleMesh& m = s.meshes[i];
        const std::string f = at("meshes", i) + " (\"" + m.name + "\")";
        for (int set = 0; set < 2; ++set) {
            const std::string field = f + ".uv" + (set == 0 ? "" : "1");
            if (!m.uv[set].empty() && m.uv[set].size() != 2 * m.positions.size())
                failInput(s.path, field, std::to_string(2 * m.positions.size()) + " numbers (u, v per position)",
                          std::to_string(m.uv[set].size()));
            for (float x : m.uv[set])
                if (!std::isfinite(x)) failInput(s.path, field, "finite texture coordinates", std::to_string(x));
        }
        if (!m.tangents.empty() && m.tangents.size() != 4 * m.positions.size())
            failInput(s.path, f + ".tangents",
                      std::to_string(m.positions.size()) + " tangents (x, y, z, w per position)",
                      std::to_string(m.tangents.size() / 4));
        if (m.material < 0 || size_t(m.material) >= s.materials.size()) continue;
        const Material& mat = s.materials[size_t(m.material)];
        for (int t : {mat.rhoDTexture, mat.rhoSTexture, mat.exponentTexture, mat.emissionTexture, mat.normalTexture}) {
            if (t < 0) continue;
            const int set = s.textures[size_t(t)].texCoord;
            if (m.uv[set].empty())
                failInput(s.path, f + ".uv" + (set == 0 ? "" : "1"),
                          "texture coordinates (set " + std::to_string(set) + ") for the texture of material \"" +
                              mat.name + "\"",
                          "none");
        }
    }
    for (size_t i = 0; i < s.spheres.size(); ++i) {
        const Sphere& sp = s.spheres[i];
        if (sp.material >= 0 && size_t(sp.material) < s.materials.size() &&
            (s.materials[size_t(sp.material)].textured() || s.materials[size_t(sp.material)].normalTexture >= 0))
            failInput(s.path, at("spheres", i) + " (\"" + sp.name + "\").material",
                      "an untextured material (spheres have no texture coordinates; use a mesh)",
                      "\"" + s.materials[size_t(sp.material)].name + "\" with a texture");
    }
}

}  // namespace

void validateScene(Scene& scene) {
    checkMaterials(scene);
    checkTextures(scene);
    checkMeshes(scene);
    checkSpheres(scene);
    dropDegenerateTriangles(scene);
    addMissingTangents(scene);
    if (scene.meshes.empty() && scene.spheres.empty())
        failInput(scene.path, "shapes", "at least one shape with non-zero area", "none");
    checkMedia(scene);
    linkEmitters(scene);
    checkLights(scene);
    checkCamera(scene);
}

}  // namespace pcl
