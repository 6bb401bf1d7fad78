#include "reference/surface.h"

#include <cmath>

#include "prep/texture_buffers.h"
#include "shared/shading_frame.h"
#include "shared/texture.h"

namespace pcl {
namespace {

// Offset scale: float spacing near |p| is ~ 6e-8 |p|; stepping ~ 1e-4 relative (at least 1e-4
// absolute) clears the rounding error of the hit point by a wide margin.
float offsetScale(Vec3 p) { return 1e-4f * std::max(1.0f, maxComponent(vmax(p, -p))); }

}  // namespace

TriangleVertices triangleAt(const TriangleMesh& mesh, uint32_t index, float time) {
    Vec3 shift = mesh.motion * time;
    const uint32_t* idx = &mesh.indices[3 * static_cast<size_t>(index)];
    return {mesh.positions[idx[0]] + shift, mesh.positions[idx[1]] + shift, mesh.positions[idx[2]] + shift};
}

SurfacePoint surfaceAt(const Scene& scene, const SceneGeometry& geometry, const PclRay& ray, const PclHit& hit) {
    SurfacePoint s;
    s.prim = hit.prim;
    s.time = ray.time;
    PrimitiveRef ref = geometry.primitive(hit.prim);
    if (ref.kind == PrimitiveRef::Triangle) {
        const TriangleMesh& mesh = scene.meshes[ref.object];
        TriangleVertices v = triangleAt(mesh, ref.index, ray.time);
        // Barycentrics as the traversal defines them: p = p0 + u (p1 - p0) + v (p2 - p0).
        float w = 1.0f - hit.u - hit.v;
        s.p = v.p0 * w + v.p1 * hit.u + v.p2 * hit.v;
        s.ng = normalize(cross(v.p1 - v.p0, v.p2 - v.p0));
        // The shading normal as kernels/shared/shading_frame.h defines it: the interpolated
        // vertex normal, perturbed by the material's normal map, on the geometric side.
        const uint32_t* idx = &mesh.indices[3 * static_cast<size_t>(ref.index)];
        // The hit's coordinates in `texture`'s set, interpolated as the kernels do.
        auto texCoordAt = [&](const Texture& texture, float& u, float& v) {
            const float* uv = mesh.uv[texture.texCoord].data();
            u = w * uv[2 * idx[0]] + hit.u * uv[2 * idx[1]] + hit.v * uv[2 * idx[2]];
            v = w * uv[2 * idx[0] + 1] + hit.u * uv[2 * idx[1] + 1] + hit.v * uv[2 * idx[2] + 1];
        };
        Vec3 n = s.ng;
        bool shaded = false;
        if (!mesh.normals.empty()) {
            Vec3 m = mesh.normals[idx[0]] * w + mesh.normals[idx[1]] * hit.u + mesh.normals[idx[2]] * hit.v;
            float len = length(m);
            if (len > 0.0f) {
                n = m / len;
                shaded = true;
            }
        }
        const Material& material = scene.materials[mesh.material];
        if (material.normalTexture >= 0 && mesh.tangents.size() == 4 * mesh.positions.size()) {
            const Texture& texture = scene.textures[size_t(material.normalTexture)];
            float u, v;
            texCoordAt(texture, u, v);
            float texel[3];
            texture_bilinear(textureDescriptor(texture, 0), texture.image.rgb.data(), u, v, texel);
            const float* t = mesh.tangents.data();
            auto at = [&](int c) {
                return w * t[4 * idx[0] + c] + hit.u * t[4 * idx[1] + c] + hit.v * t[4 * idx[2] + c];
            };
            const PclV3 p = shading_perturb(sampling_v3(n.x, n.y, n.z), sampling_v3(at(0), at(1), at(2)),
                                            at(3) < 0.0f ? -1.0f : 1.0f, texel, material.normalScale);
            n = Vec3(p.x, p.y, p.z);
            shaded = true;
        }
        s.ns = !shaded ? s.ng : (dot(n, s.ng) < 0.0f ? -n : n);  // both on the geometric side
        s.material = &scene.materials[mesh.material];
        s.rhoD = s.material->rhoD;
        s.rhoS = s.material->rhoS;
        s.exponent = s.material->phongExponent;
        s.emission = s.material->emission;
        if (s.material->textured()) {  // the kernels' lookup and mapping (kernels/shared/texture.h)
            const Material& m = *s.material;
            const PclMaterialTextures t = materialTextureDescriptor(scene, m, {});
            const int slots[PCL_TEXTURE_SLOTS] = {m.rhoDTexture, m.rhoSTexture, m.exponentTexture, m.emissionTexture};
            PclTexels x{};
            for (int k = 0; k < PCL_TEXTURE_SLOTS; ++k) {
                if (slots[k] < 0) continue;
                const Texture& texture = scene.textures[size_t(slots[k])];
                float u, v;
                texCoordAt(texture, u, v);
                texture_bilinear(t.slot[k], texture.image.rgb.data(), u, v, x.value[k]);
                x.has |= 1u << k;
            }
            PclMaterial local{};
            for (int c = 0; c < 3; ++c) {
                local.rhoD[c] = s.rhoD[c];
                local.rhoS[c] = s.rhoS[c];
            }
            local.exponent = s.exponent;
            for (int c = 0; c < 3; ++c) local.emission[c] = s.emission[c];
            local.specular = m.specular == SpecularKind::Glossy ? PCL_SPECULAR_GLOSSY : PCL_SPECULAR_NONE;
            texture_material(&t, &x, &local);
            s.rhoD = Vec3(local.rhoD[0], local.rhoD[1], local.rhoD[2]);
            s.rhoS = Vec3(local.rhoS[0], local.rhoS[1], local.rhoS[2]);
            s.exponent = local.exponent;
            s.emission = Vec3(local.emission[0], local.emission[1], local.emission[2]);
        }
    } else {
        const Sphere& sphere = scene.spheres[ref.object];
        Vec3 c = sphere.centre + sphere.motion * ray.time;
        Vec3 hitP = rayOrigin(ray) + rayDirection(ray) * hit.t;
        s.ng = normalize(hitP - c);
        s.p = c + s.ng * sphere.radius;  // re-projected onto the surface
        s.ns = s.ng;
        s.material = &scene.materials[sphere.material];
        s.rhoD = s.material->rhoD;
        s.rhoS = s.material->rhoS;
        s.exponent = s.material->phongExponent;
        s.emission = s.material->emission;
    }
    return s;
}

PclRay spawnRay(Vec3 p, Vec3 n, Vec3 d, float time, float tmax) {
    return makeRay(p + n * (dot(n, d) >= 0.0f ? offsetScale(p) : -offsetScale(p)), d, time, tmax);
}

PclRay spawnShadowRay(Vec3 p, Vec3 n, Vec3 target, Vec3 targetN, float time) {
    PclRay r = spawnRay(p, n, target - p, time, 1.0f);
    Vec3 o = rayOrigin(r);
    Vec3 end = target + targetN * (dot(targetN, o - target) >= 0.0f ? offsetScale(target) : -offsetScale(target));
    Vec3 d = end - o;
    r.dx = d.x;
    r.dy = d.y;
    r.dz = d.z;
    return r;
}

}  // namespace pcl
