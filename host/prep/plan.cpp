#include "prep/plan.h"

#include "prep/environment_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "prep/projection_map.h"

namespace pcl {
namespace {

// What the plan needs to know of one primitive.
struct Prim {
    bool diffuse, specular, pureSpecular, glossy, sphere;
    bool litInside;    // sphere: a light sits inside it, so its inside sees itself (the furnace)
    Vec3 n, p;         // triangle: unit normal and a vertex (the plane); sphere: unused
    bool leavesPlane;  // triangle moving off its own plane over the shutter
    uint32_t material;
};

std::vector<Prim> gather(const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers) {
    std::vector<Prim> prims;
    prims.reserve(geometry.primitiveCount());
    for (uint32_t id = 0; id < geometry.primitiveCount(); ++id) {
        const PclPrimInfo& info = buffers.primInfo[id];
        const PclMaterial& m = buffers.materials[info.material];
        Prim p{};
        p.material = info.material;
        p.diffuse = isDiffuse(m);
        p.specular = isSpecular(m);
        p.pureSpecular = isPureSpecular(m);
        p.glossy = p.specular && m.specular == PCL_SPECULAR_GLOSSY;
        PrimitiveRef ref = geometry.primitive(id);
        p.sphere = ref.kind == PrimitiveRef::Sphere;
        if (p.sphere) {
            // Conservative over the shutter: the radius grown by the sphere's motion.
            const Vec3 c(info.a, info.b, info.c);
            const float reach = info.radius + length(Vec3(info.mx, info.my, info.mz));
            for (const PclLight& l : buffers.lights)
                if (l.type != PCL_LIGHT_DIRECTIONAL && l.type != PCL_LIGHT_ENVIRONMENT &&
                    length(Vec3(l.p[0], l.p[1], l.p[2]) - c) < reach)
                    p.litInside = true;
        } else {
            const TriangleMesh& mesh = scene.meshes[ref.object];
            p.n = Vec3(info.a, info.b, info.c);
            p.p = mesh.positions[mesh.indices[3 * ref.index]];
            p.leavesPlane = std::abs(dot(p.n, mesh.motion)) > 0.0f;
        }
        prims.push_back(p);
    }
    return prims;
}

// Whether some primitive of A and some primitive of B can see each other: they exist, are
// distinct, and are not all triangles of one plane; or a sphere with a light inside is in both
// (its inside sees itself: the furnace). plan.h states the rule and its limits.
template <typename A, typename B>
bool canSee(const std::vector<Prim>& prims, float scale, A inA, B inB) {
    bool anyA = false, anyB = false, flat = true, sphereInBoth = false;
    size_t n = 0;
    const Prim* ref = nullptr;
    for (const Prim& p : prims) {
        bool a = inA(p), b = inB(p);
        if (!a && !b) continue;
        anyA |= a;
        anyB |= b;
        sphereInBoth |= a && b && p.sphere && p.litInside;
        ++n;
        if (p.sphere || p.leavesPlane) {
            flat = false;
        } else if (!ref) {
            ref = &p;
        } else if (flat) {
            bool parallel = std::abs(dot(ref->n, p.n)) > 1.0f - 1e-5f;
            bool onPlane = std::abs(dot(ref->n, p.p - ref->p)) <= 1e-5f * scale;
            flat = parallel && onPlane;
        }
    }
    return sphereInBoth || (anyA && anyB && n >= 2 && !flat);
}

std::string names(const Scene& scene, const std::vector<Prim>& prims, bool (*pick)(const Prim&)) {
    std::set<uint32_t> used;
    for (const Prim& p : prims)
        if (pick(p)) used.insert(p.material);
    std::string s;
    for (uint32_t m : used) {
        std::string name = m < scene.materials.size() ? scene.materials[m].name : std::string();
        // glTF materials are named "<file>.gltf:<name>" (or .glb): keep the name.
        for (const char* ext : {".gltf:", ".glb:"}) {
            size_t at = name.find(ext);
            if (at != std::string::npos) name = name.substr(at + std::char_traits<char>::length(ext));
        }
        if (name.empty()) name = "material " + std::to_string(m);
        s += (s.empty() ? "" : ", ") + name;
    }
    return s;
}

std::string plural(size_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); }

}  // namespace

LightPaths classifyLightPaths(const Scene& scene, const SceneGeometry& geometry, const SceneBuffers& buffers) {
    LightPaths lp;
    std::vector<Prim> prims = gather(scene, geometry, buffers);
    float scale = std::max(buffers.sceneRadius, 1e-6f);

    lp.lights = buffers.lights.size();
    size_t facing = 0;
    for (const PclLight& l : buffers.lights) {
        if (l.type != PCL_LIGHT_TRIANGLE) continue;
        ++lp.areaTriangles;
        Vec3 p0 = Vec3(l.p[0], l.p[1], l.p[2]) + Vec3(l.motion[0], l.motion[1], l.motion[2]) * 0.5f;
        if (dot(Vec3(l.axis[0], l.axis[1], l.axis[2]), scene.camera.position - p0) > 0.0f) ++facing;
    }
    for (const Prim& p : prims) {
        lp.diffusePrims += p.diffuse;
        lp.specularPrims += p.specular;
        lp.pureSpecularPrims += p.pureSpecular;
        lp.glossyPrims += p.glossy;
    }
    for (const PclLight& l : buffers.lights) {
        lp.markedCells += l.projCount;
        if (l.type == PCL_LIGHT_ENVIRONMENT) lp.skyCells += l.projCount;
    }
    lp.skySpread = skyCausticsByEyeRays(scene);
    auto diffuse = [](const Prim& p) { return p.diffuse; };
    auto specular = [](const Prim& p) { return p.specular; };
    lp.diffuseSeesDiffuse = canSee(prims, scale, diffuse, diffuse);
    lp.diffuseSeesSpecular = canSee(prims, scale, diffuse, specular);

    const bool lit = lp.lights > 0;
    const uint32_t cells = uint32_t(lp.lights) * PCL_PROJ_GRID * PCL_PROJ_GRID;
    std::string specNames = names(scene, prims, [](const Prim& p) { return p.specular; });

    // LE
    const bool sky = scene.environment.active();
    lp.visibleEmitters = facing > 0 || sky;
    std::string why;
    if (sky) why = "the sky, where eye rays leave the scene";
    else if (lp.areaTriangles == 0) why = "no emitting surfaces (point, spot and directional lights are not visible)";
    else if (facing == 0) why = "no emitting triangle faces the camera";
    else why = std::to_string(facing) + " of " + plural(lp.areaTriangles, "emitting triangle") + " face the camera";
    lp.list.push_back({"LE", "emitters seen directly", lp.visibleEmitters, why});

    // LDE
    lp.direct = lit && lp.diffusePrims > 0;
    why = lp.diffusePrims == 0 ? "no diffuse surfaces"
                               : plural(lp.diffusePrims, "diffuse primitive") + " (" +
                                     names(scene, prims, [](const Prim& p) { return p.diffuse; }) + ")";
    lp.list.push_back({"LDE", "direct diffuse", lp.direct, why});

    // LS+E
    lp.specularOfLights = lit && lp.markedCells > 0;
    if (lp.specularPrims == 0) why = "no specular surfaces";
    else if (lp.markedCells == 0)
        why = "no light reaches a specular surface (" + specNames + "): projection maps empty";
    else
        why = "lights reach " + specNames + " (" + std::to_string(lp.markedCells) + " of " + std::to_string(cells) +
              " projection-map cells)";
    lp.list.push_back({"LS+E", "lights seen in specular surfaces", lp.specularOfLights, why});

    // LDS+E
    lp.diffuseInSpecular = lp.direct && lp.diffuseSeesSpecular;
    why = lp.diffuseInSpecular    ? "specular surfaces (" + specNames + ") see lit diffuse ones"
          : lp.specularPrims == 0 ? "no specular surfaces"
          : lp.diffusePrims == 0  ? "no diffuse surfaces"
                                  : "specular and diffuse surfaces lie in one plane";
    lp.list.push_back({"LDS+E", "diffuse surfaces seen in specular ones", lp.diffuseInSpecular, why});

    // LS+DE
    lp.caustics = lp.specularOfLights && lp.diffusePrims > 0 && lp.diffuseSeesSpecular;
    why = !lp.specularOfLights      ? "no light reaches a specular surface"
          : lp.diffusePrims == 0    ? "no diffuse surface to receive them"
          : !lp.diffuseSeesSpecular ? "specular and diffuse surfaces lie in one plane"
                                    : "lights reach " + specNames + ", which see diffuse surfaces";
    lp.list.push_back({"LS+DE", "caustics", lp.caustics, why});

    // LD(S|D)*DE
    lp.indirectDiffuse = lp.direct && (lp.diffuseSeesDiffuse || lp.diffuseSeesSpecular);
    if (lp.diffusePrims == 0) why = "no diffuse surfaces";
    else if (lp.diffuseSeesDiffuse)
        why = plural(lp.diffusePrims, "diffuse primitive") + " not all in one plane see each other";
    else if (lp.diffuseSeesSpecular) why = "diffuse surfaces light each other through specular ones (LDS+DE)";
    else if (lp.diffusePrims == 1) why = "a single diffuse primitive and no specular surface to return its light";
    else why = "all diffuse primitives lie in one plane and no specular surface returns their light";
    lp.list.push_back({"LD(S|D)*DE", "indirect diffuse", lp.indirectDiffuse, why});

    // L(S|D|V)*V(S|D|V)*E: a medium in use that scatters.
    std::vector<int> used;
    if (scene.globalMedium >= 0) used.push_back(scene.globalMedium);
    for (const auto& m : scene.meshes)
        if (m.medium >= 0) used.push_back(m.medium);
    for (const auto& s : scene.spheres)
        if (s.medium >= 0) used.push_back(s.medium);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    std::string scattering, absorbing;
    for (int i : used) {
        const Medium& m = scene.media[size_t(i)];
        const bool scatters = maxComponent(m.sigmaS) > 0.0f;
        lp.scatteringMedia += scatters;
        std::string& list = scatters ? scattering : absorbing;
        list += (list.empty() ? "" : ", ") + m.name + (i == scene.globalMedium ? " (global)" : "");
    }
    lp.media = used.size();
    lp.volume = lit && lp.scatteringMedia > 0;
    why = lp.media == 0             ? "no participating media"
          : lp.scatteringMedia == 0 ? "media absorb only (" + absorbing + "): no scattering events"
                                    : "scattering media: " + scattering;
    lp.list.push_back({"L(S|D|V)*V(S|D|V)*E", "volume scattering (V: in a medium)", lp.volume, why});
    return lp;
}

RenderPlan makePlan(const Scene& scene, const LightPaths& lp, const PlanSettings& settings) {
    RenderPlan plan;

    plan.globalMap = lp.indirectDiffuse;
    plan.globalPhotons = plan.globalMap ? settings.globalPhotons : 0;
    if (plan.globalMap)
        plan.reasons.push_back("diffuse interreflection is present (LD(S|D)*DE): final gathering reads it");
    else if (lp.diffusePrims == 0) plan.reasons.push_back("no diffuse surfaces: no photon would ever be stored");
    else
        plan.reasons.push_back("no diffuse interreflection (LD(S|D)*DE absent): direct light by shadow rays" +
                               std::string(lp.caustics ? " and caustics" : "") + " cover every diffuse path");

    // The caustic pass follows specular bounces off mixed surfaces too (kernels/README.md,
    // trace_photons step 1), so every LS+D path the scene allows ends in the caustic map: a
    // light reaching any specular surface (pure or mixed) that sees a diffuse one (a mixed
    // surface counts as diffuse when another specular surface sees it).
    plan.skyCausticPhotons = lp.skyCells > 0 && (settings.skyCaustics || !lp.skySpread);
    plan.causticMap = lp.caustics && (lp.markedCells > lp.skyCells || plan.skyCausticPhotons);
    const bool skyOnly = lp.caustics && !plan.causticMap;
    plan.causticPhotons = plan.causticMap ? settings.causticPhotons : 0;
    if (skyOnly)
        plan.reasons.push_back("caustics (LS+DE) come from the sky alone: the gather rays find them through the "
                               "specular surfaces, no caustic map");
    else if (plan.causticMap)
        plan.reasons.push_back("caustics (LS+DE): lights reach specular surfaces (" + std::to_string(lp.markedCells) +
                               " projection-map cells) that see diffuse ones");
    else if (lp.specularPrims == 0) plan.reasons.push_back("no specular surfaces");
    else if (lp.markedCells == 0)
        plan.reasons.push_back("no light reaches a specular surface (every projection map is empty)");
    else
        plan.reasons.push_back(lp.diffusePrims == 0 ? "no diffuse surface to receive caustics"
                                                    : "specular and diffuse surfaces cannot see each other");

    plan.finalGather = plan.globalMap;
    plan.reasons.push_back(plan.finalGather ? "indirect diffuse light is gathered from the global map"
                                            : "no global map: no indirect diffuse light to gather");

    const Camera& cam = scene.camera;
    plan.lensSampling = cam.model == CameraModel::ThinLens && cam.apertureRadius > 0.0f;
    if (plan.lensSampling) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "thin lens, aperture radius %g m focused at %g m: depth of field",
                      double(cam.apertureRadius), double(cam.focusDistance));
        plan.reasons.push_back(buf);
    } else {
        plan.reasons.push_back(cam.model == CameraModel::Pinhole ? "pinhole camera" : "lens aperture is zero");
    }

    size_t moving = 0;
    for (const auto& m : scene.meshes) moving += !(m.motion == Vec3(0.0f));
    for (const auto& s : scene.spheres) moving += !(s.motion == Vec3(0.0f));
    bool shutterOpen = cam.shutterClose > cam.shutterOpen;
    plan.timeSampling = moving > 0 && shutterOpen;
    if (plan.timeSampling) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%zu moving object%s, shutter open [%g, %g] s: motion blur", moving,
                      moving == 1 ? "" : "s", double(cam.shutterOpen), double(cam.shutterClose));
        plan.reasons.push_back(buf);
    } else {
        plan.reasons.push_back(moving == 0 ? "nothing moves" : "the shutter is closed: no motion blur");
    }

    plan.areaLightSampling = lp.areaTriangles > 0 || scene.environment.active();
    if (scene.environment.active())
        plan.reasons.push_back("the sky: directions sampled by its map" +
                               (lp.areaTriangles > 0 ? ", and " + plural(lp.areaTriangles, "emitting triangle") : ""));
    else
        plan.reasons.push_back(plan.areaLightSampling ? plural(lp.areaTriangles, "emitting triangle") +
                                                            ": soft shadows by sampling points on them"
                                                      : "point, spot and directional lights only: one shadow ray each");

    plan.glossySampling = lp.glossyPrims > 0;
    plan.reasons.push_back(plan.glossySampling
                               ? plural(lp.glossyPrims, "glossy primitive") + ": glossy lobes are sampled"
                               : "no glossy surfaces");

    plan.volumeMap = lp.volume;
    plan.volumePhotons = plan.volumeMap ? settings.globalPhotons : 0;  // the global pass stores them
    plan.reasons.push_back(plan.volumeMap  ? "light scatters in media (L(S|D|V)*V(S|D|V)*E): volume photons at the "
                                             "photon passes' scattering events, read along the eye's medium "
                                             "segments (progressive, direct; fg does not carry media yet)"
                           : lp.media == 0 ? "no participating media"
                                           : "media absorb only: no scattering events to store photons at");
    return plan;
}

std::string formatPlan(const Scene& scene, const LightPaths& lp, const RenderPlan& plan) {
    std::string out;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "scene %s: %zu light entr%s (%zu emitting triangles), %zu diffuse / %zu specular "
                  "(%zu purely specular, %zu glossy) primitives\n",
                  scene.path.c_str(), lp.lights, lp.lights == 1 ? "y" : "ies", lp.areaTriangles, lp.diffusePrims,
                  lp.specularPrims, lp.pureSpecularPrims, lp.glossyPrims);
    out += buf;
    if (scene.environment.active())
        out += "environment light: " +
               (scene.environment.imagePath.empty() ? std::string("a constant sky") : scene.environment.imagePath) +
               " (the last light entry: its photons cross a disc of the scene's bounding sphere)\n";
    out += "light paths (L light, D diffuse, S specular, V scattering in a medium, E eye):\n";
    for (const LightPath& p : lp.list) {
        std::snprintf(buf, sizeof buf, "  %-19s %-3s %-40s %s\n", p.notation.c_str(), p.present ? "yes" : "no",
                      p.name.c_str(), p.why.c_str());
        out += buf;
    }
    out += "plan:\n";
    struct Row {
        const char* what;
        bool on;
        uint32_t photons;
    };
    const Row rows[] = {{"global map", plan.globalMap, plan.globalPhotons},
                        {"caustic map", plan.causticMap, plan.causticPhotons},
                        {"final gather", plan.finalGather, 0},
                        {"lens sampling", plan.lensSampling, 0},
                        {"time sampling", plan.timeSampling, 0},
                        {"area-light sampling", plan.areaLightSampling, 0},
                        {"glossy sampling", plan.glossySampling, 0},
                        {"volume map", plan.volumeMap, plan.volumePhotons}};
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
        std::string state = rows[i].on ? "yes" : "no";
        if (rows[i].on && rows[i].photons) state += ", " + std::to_string(rows[i].photons) + " photons";
        std::snprintf(buf, sizeof buf, "  %-20s %-20s %s\n", rows[i].what, state.c_str(),
                      i < plan.reasons.size() ? plan.reasons[i].c_str() : "");
        out += buf;
    }
    return out;
}

}  // namespace pcl
