#!/usr/bin/env python3
"""A photoncl JSON scene as a Mitsuba 3 scene, for independent references (tests/data/mitsuba-*.exr).

Only what Mitsuba expresses *exactly* is converted; anything else is refused with
Unexpressible(scene, field, why), never approximated. What maps to what (photoncl's conventions
from host/reference/{camera,bsdf,light_sampling,path_tracer}.cpp and host/scene/json_loader.cpp):

- camera: pinhole -> `perspective`, thin_lens -> `thinlens` (both: vertical fov, look_at frame,
  focus plane perpendicular to the view axis, uniform disk aperture); film `hdrfilm` with a `box`
  filter (photoncl's film averages the samples jittered inside each pixel). Shutter times are
  irrelevant without motion (motion is refused).
- materials (f = rho_d/pi + specular, two-sided: photoncl faces the shading normal to wo):
  diffuse -> twosided(diffuse); mirror -> twosided(conductor 'none', specular_reflectance rho_s);
  diffuse + mirror -> twosided(blendbsdf(w, diffuse(rho_d/(1-w)), conductor(rho_s/w))), with w
  chosen so both stay reflectances <= 1 (needs max rho_d + max rho_s <= 1, else refused);
  dielectric -> dielectric(int_ior eta, ext_ior 1, both scales rho_s) on spheres only, with the
  camera, every point light and every area light's vertices outside it: Mitsuba scales radiance by eta^2 at each crossing
  (photoncl does not), which cancels only on paths that enter and leave a closed body.
- lights: point -> `point` (intensity; power / 4 pi), directional -> `directional` (irradiance),
  area -> an emissive one-sided `area` emitter on the triangles (front = cross(u, v), as
  photoncl), radiance or power / (pi A); the lamp's surface is black, as in photoncl.
- environment: a constant sky -> `constant` (radiance); an image sky is refused (photoncl reads the
  nearest texel, Mitsuba's `envmap` interpolates).
- shapes: sphere -> `sphere`; quad -> the two triangles photoncl makes (c, c+u, c+u+v, c+v);
  inline mesh -> a Mitsuba mesh with the same triangles and winding.
- media: `homogeneous` with sigma_t = sigma_a + sigma_s (an RGB in [0, 1] times `scale` = its
  largest channel, so chromatic media stay exact), albedo sigma_s / sigma_t and an `hg` phase
  function with photoncl's g (both: g > 0 scatters forward). The global medium is the sensor's
  medium and every shape's exterior; a shape's medium is its interior (its surface a `null` BSDF
  when the shape has no material: photoncl's invisible boundary); a glass sphere without a medium
  has a vacuum interior, as in photoncl. Shapes holding media must not be nested in each other
  and must not hold the camera (refused).
- integrator: `path` with max_depth 65 (photoncl's path tracer follows 64 bounces after the
  camera ray; Mitsuba's max_depth 1 is emitters seen directly), `volpath` when the scene has
  media (its depth counts scattering in media too, as photoncl's maxDepth does). Russian roulette
  in either does not bias.

Refused: nested media, a camera or light inside a shape with a medium, glossy (normalised Phong: no Mitsuba BSDF is that lobe), spot lights (photoncl's
smoothstep in cos theta is not Mitsuba's linear fall-off in angle), motion, glTF (includes and
mesh files), shading normals (the two renderers treat them differently below the geometric
surface), mesh transforms (not implemented here; no shipped scene needs one), dielectric with a
diffuse part or on triangles, emissive spheres.

Usage: python3 scripts/mitsuba_scene.py SCENE.json [--width W] [--check]
  prints the conversion (or the refusal) of a scene.
"""
import argparse
import json
import math
import os
import sys


class Unexpressible(Exception):
    """A scene feature Mitsuba cannot render exactly as photoncl does."""

    def __init__(self, scene, field, why):
        super().__init__(f"{scene}: {field}: not expressible in Mitsuba exactly: {why}")
        self.scene, self.field, self.why = scene, field, why


def _vec(v):
    return [float(x) for x in v]


def _sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def _add(a, b):
    return [a[i] + b[i] for i in range(3)]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _norm(a):
    return math.sqrt(sum(x * x for x in a))


class _Converter:
    def __init__(self, path, width, height):
        self.path = path
        self.name = os.path.basename(path)
        self.width, self.height = width, height
        if not path.endswith(".json"):
            self.refuse("(file)", "glTF scenes are not converted (materials and lights come from the glTF mapping)")
        with open(path) as f:
            self.doc = json.load(f)
        self.materials = {}
        self.emission = {}  # material name -> radiance
        self.dielectric_spheres = []
        self.media = {}  # medium name -> Mitsuba medium object
        self.global_medium = None
        self.medium_spheres = []  # (centre, radius, field) of spheres holding a medium

    def refuse(self, field, why):
        raise Unexpressible(self.name, field, why)

    # ---- materials -------------------------------------------------------------------

    def material(self, i, m):
        field = f"materials[{i}]"
        rho_d = _vec(m.get("rho_d", [0, 0, 0]))
        emission = _vec(m.get("emission", [0, 0, 0]))
        spec = m.get("specular")
        kind = spec.get("kind") if spec else None
        if kind == "glossy":
            self.refuse(field + ".specular", "a normalised Phong lobe ((n+2)/2pi cos^n) has no exact Mitsuba BSDF")
        diffuse = {"type": "diffuse", "reflectance": {"type": "rgb", "value": rho_d}}
        if kind is None:
            bsdf = {"type": "twosided", "bsdf": diffuse}
        elif kind == "mirror":
            rho_s = _vec(spec["rho_s"])
            mirror = {"type": "conductor", "material": "none", "specular_reflectance": {"type": "rgb", "value": rho_s}}
            if max(rho_d) == 0:
                bsdf = {"type": "twosided", "bsdf": mirror}
            else:
                md, ms = max(rho_d), max(rho_s)
                if md + ms > 1 + 1e-6:
                    self.refuse(field, f"rho_d + rho_s as a blend needs max(rho_d) + max(rho_s) <= 1, got {md + ms:.6g}")
                w = ms / (md + ms)  # blend weight of the mirror: w >= ms and 1 - w >= md
                diffuse["reflectance"]["value"] = [x / (1 - w) for x in rho_d]
                mirror["specular_reflectance"]["value"] = [x / w for x in rho_s]
                bsdf = {"type": "twosided", "bsdf": {"type": "blendbsdf", "weight": w, "bsdf_0": diffuse, "bsdf_1": mirror}}
        elif kind == "dielectric":
            if max(rho_d) > 0:
                self.refuse(field, "a dielectric with a diffuse part (the eta^2 radiance scaling is not verified there)")
            rho_s = _vec(spec.get("rho_s", [1, 1, 1]))
            bsdf = {"type": "dielectric", "int_ior": float(spec.get("ior", 1.5)), "ext_ior": 1.0,
                    "specular_reflectance": {"type": "rgb", "value": rho_s},
                    "specular_transmittance": {"type": "rgb", "value": rho_s}}
        else:
            self.refuse(field + ".specular.kind", f"unknown kind {kind!r}")
        self.materials[m["name"]] = (bsdf, kind)
        if max(emission) > 0:
            self.emission[m["name"]] = emission

    # ---- media -----------------------------------------------------------------------

    def medium(self, i, m):
        import mitsuba as mi

        field = f"media[{i}]"
        for key in m:
            if key not in ("name", "sigma_a", "sigma_s", "g"):
                self.refuse(f"{field}.{key}", "unknown key")
        sigma_a, sigma_s = _vec(m.get("sigma_a", [0, 0, 0])), _vec(m.get("sigma_s", [0, 0, 0]))
        sigma_t = [a + s for a, s in zip(sigma_a, sigma_s)]
        scale = max(sigma_t)
        if not scale > 0:
            self.refuse(field, "sigma_a + sigma_s is zero in every channel")
        albedo = [s / t if t > 0 else 0.0 for s, t in zip(sigma_s, sigma_t)]
        self.media[m["name"]] = mi.load_dict({
            "type": "homogeneous", "scale": scale,
            "sigma_t": {"type": "rgb", "value": [t / scale for t in sigma_t]},
            "albedo": {"type": "rgb", "value": albedo},
            "phase": {"type": "hg", "g": float(m.get("g", 0.0))}})

    def media_of(self, s, field):
        """(interior, exterior) Mitsuba media of shape s (None: vacuum)."""
        if "medium" not in s:
            return None, self.global_medium
        if s["medium"] not in self.media:
            self.refuse(field + ".medium", f"unknown medium {s['medium']!r}")
        return self.media[s["medium"]], self.global_medium

    # ---- shapes ----------------------------------------------------------------------

    def mesh(self, name, positions, faces, material, field, interior=None, exterior=None):
        import mitsuba as mi

        if material is None:  # an invisible medium boundary
            return self.mesh_with(name, positions, faces, mi.load_dict({"type": "null"}), None, interior, exterior)
        bsdf, kind = self.materials[material]
        if kind == "dielectric":
            self.refuse(field + ".material", "dielectric on triangles: exact only on closed bodies (spheres here)")
        return self.mesh_with(name, positions, faces, mi.load_dict(bsdf), self.emission.get(material), interior,
                              exterior)

    @staticmethod
    def mesh_with(name, positions, faces, bsdf, radiance, interior=None, exterior=None):
        import mitsuba as mi

        props = mi.Properties()
        props["bsdf"] = bsdf
        if interior is not None:
            props["interior"] = interior
        if exterior is not None:
            props["exterior"] = exterior
        if radiance is not None:
            props["emitter"] = mi.load_dict({"type": "area", "radiance": {"type": "rgb", "value": radiance}})
        mesh = mi.Mesh(name, len(positions), len(faces), has_vertex_normals=False, has_vertex_texcoords=False,
                       props=props)
        params = mi.traverse(mesh)
        params["vertex_positions"] = [c for p in positions for c in p]
        params["faces"] = [i for f in faces for i in f]
        params.update()
        return mesh

    def shape(self, i, s):
        field = f"shapes[{i}]"
        if "motion" in s and any(float(x) != 0 for x in s["motion"]):
            self.refuse(field + ".motion", "motion blur is not converted")
        t = s["type"]
        interior, exterior = self.media_of(s, field)
        if t == "sphere":
            centre, radius = _vec(s["centre"]), float(s["radius"])
            if "material" in s:
                bsdf, kind = self.materials[s["material"]]
                if s["material"] in self.emission:
                    self.refuse(field, "emissive sphere")
            else:
                bsdf, kind = {"type": "null"}, None
            if kind == "dielectric" or interior is not None:
                for c2, r2, other in self.dielectric_spheres + self.medium_spheres:
                    if _norm(_sub(centre, c2)) < radius + r2:
                        self.refuse(field, f"overlaps or nests in {other}: nested media are not converted")
            if kind == "dielectric":
                self.dielectric_spheres.append((centre, radius, field))
            elif interior is not None:
                self.medium_spheres.append((centre, radius, field))
            d = {"type": "sphere", "center": centre, "radius": radius, "bsdf": bsdf}
            if interior is not None:
                d["interior"] = interior
            if exterior is not None:
                d["exterior"] = exterior
            return d
        if t == "quad":
            c, u, v = _vec(s["corner"]), _vec(s["edge_u"]), _vec(s["edge_v"])
            return self.mesh(s.get("name", field), [c, _add(c, u), _add(_add(c, u), v), _add(c, v)],
                             [[0, 1, 2], [0, 2, 3]], s.get("material"), field, interior, exterior)
        if t == "mesh":
            for key, why in (("gltf", "glTF meshes are not converted"),
                             ("normals", "shading normals: photoncl and Mitsuba differ below the geometric surface"),
                             ("transform", "mesh transforms are not implemented in this converter")):
                if key in s:
                    self.refuse(f"{field}.{key}", why)
            p, idx = s["positions"], s["indices"]
            positions = [_vec(p[k:k + 3]) for k in range(0, len(p), 3)]
            faces = [[int(x) for x in idx[k:k + 3]] for k in range(0, len(idx), 3)]
            # photoncl drops zero-area triangles; so does nothing here, so refuse them instead.
            for f in faces:
                a, b, c = (positions[j] for j in f)
                if not _norm(_cross(_sub(b, a), _sub(c, a))) > 0:
                    self.refuse(field + ".indices", f"degenerate triangle {f}")
            return self.mesh(s.get("name", field), positions, faces, s.get("material"), field, interior, exterior)
        self.refuse(field + ".type", f"unknown shape type {t!r}")

    # ---- lights ----------------------------------------------------------------------

    def light(self, i, l):
        field = f"lights[{i}]"
        t = l["type"]
        if t == "point":
            intensity = _vec(l["intensity"]) if "intensity" in l else [x / (4 * math.pi) for x in l["power"]]
            self.check_outside_dielectrics(_vec(l["position"]), field + ".position")
            return {"type": "point", "position": _vec(l["position"]), "intensity": {"type": "rgb", "value": intensity}}
        if t == "directional":
            return {"type": "directional", "direction": _vec(l["direction"]),
                    "irradiance": {"type": "rgb", "value": _vec(l["irradiance"])}}
        if t == "spot":
            self.refuse(field, "spot fall-off: photoncl's smoothstep in cos theta is not Mitsuba's linear ramp in angle")
        if t == "area":
            if l.get("shape") == "quad":
                c, u, v = _vec(l["corner"]), _vec(l["edge_u"]), _vec(l["edge_v"])
                positions, faces = [c, _add(c, u), _add(_add(c, u), v), _add(c, v)], [[0, 1, 2], [0, 2, 3]]
            elif l.get("shape") == "triangle":
                positions, faces = [_vec(p) for p in l["vertices"]], [[0, 1, 2]]
            else:
                self.refuse(field + ".shape", f"unknown area light shape {l.get('shape')!r}")
            for k, p in enumerate(positions):
                self.check_outside_dielectrics(p, f"{field} vertex {k}")
            area = sum(0.5 * _norm(_cross(_sub(positions[f[1]], positions[f[0]]), _sub(positions[f[2]], positions[f[0]])))
                       for f in faces)
            radiance = _vec(l["radiance"]) if "radiance" in l else [x / (math.pi * area) for x in l["power"]]
            import mitsuba as mi

            black = mi.load_dict({"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}}})
            return self.mesh_with(l.get("name", field), positions, faces, black, radiance, None, self.global_medium)
        self.refuse(field + ".type", f"unknown light type {t!r}")

    def environment(self, e):
        # photoncl reads the nearest texel, Mitsuba's envmap interpolates bilinearly: only a
        # constant sky is the same light in both.
        if "image" in e:
            self.refuse("environment.image", "an image sky (photoncl: nearest texel; Mitsuba: bilinear)")
        return {"type": "constant", "radiance": {"type": "rgb", "value": [float(x) for x in e["radiance"]]}}

    def check_outside_dielectrics(self, p, field):
        for centre, radius, sphere in self.dielectric_spheres:
            if _norm(_sub(p, centre)) <= radius:
                self.refuse(field, f"inside the dielectric {sphere}: the eta^2 radiance scaling would not cancel")
        for centre, radius, sphere in self.medium_spheres:
            if _norm(_sub(p, centre)) <= radius:
                self.refuse(field, f"inside {sphere}, which holds a medium (only the global medium is converted there)")

    # ---- camera ----------------------------------------------------------------------

    def camera(self, c):
        import mitsuba as mi

        for key in c:
            if key not in ("type", "position", "look_at", "up", "fov", "resolution", "aperture_radius",
                           "focus_distance", "shutter"):
                self.refuse("camera." + key, "unknown key")
        w, h = c.get("resolution", [256, 256])
        width = self.width or w
        height = self.height or max(1, width * h // w)
        position, look_at = _vec(c["position"]), _vec(c["look_at"])
        self.check_outside_dielectrics(position, "camera.position")
        sensor = {
            "to_world": mi.ScalarTransform4f().look_at(origin=position, target=look_at, up=_vec(c.get("up", [0, 1, 0]))),
            "fov": float(c["fov"]),
            "fov_axis": "y",
            "near_clip": 1e-4,
            "far_clip": 1e7,
            "film": {"type": "hdrfilm", "width": int(width), "height": int(height), "rfilter": {"type": "box"},
                     "pixel_format": "rgb", "component_format": "float32"},
            "sampler": {"type": "independent", "sample_count": 1},
        }
        if self.global_medium is not None:
            sensor["medium"] = self.global_medium
        if c.get("type", "pinhole") == "thin_lens":
            sensor["type"] = "thinlens"
            sensor["aperture_radius"] = float(c["aperture_radius"])
            sensor["focus_distance"] = float(c["focus_distance"]) if "focus_distance" in c else _norm(_sub(look_at, position))
        else:
            sensor["type"] = "perspective"
        return sensor

    def convert(self):
        d = self.doc
        if "include" in d:
            self.refuse("include", "glTF includes are not converted")
        for i, m in enumerate(d.get("materials", [])):
            self.material(i, m)
        for i, m in enumerate(d.get("media", [])):
            self.medium(i, m)
        if "medium" in d:
            if d["medium"] not in self.media:
                self.refuse("medium", f"unknown medium {d['medium']!r}")
            self.global_medium = self.media[d["medium"]]
        integrator = "volpath" if self.media else "path"
        scene = {"type": "scene", "integrator": {"type": integrator, "max_depth": 65, "hide_emitters": False}}
        # Spheres first, so that the dielectric list is complete before lights and camera are checked.
        shapes = list(enumerate(d["shapes"]))
        shapes.sort(key=lambda s: s[1]["type"] != "sphere")
        for i, s in shapes:
            scene[f"shape_{i}"] = self.shape(i, s)
        for i, l in enumerate(d.get("lights", [])):
            scene[f"light_{i}"] = self.light(i, l)
        if "environment" in d:
            scene["environment"] = self.environment(d["environment"])
        if "camera" not in d:
            self.refuse("camera", "no camera")
        scene["sensor"] = self.camera(d["camera"])
        return scene


def mitsuba_scene_dict(path, width=None, height=None):
    """The Mitsuba scene dict of a photoncl JSON scene (width: override; height then keeps the
    aspect ratio unless given). Raises Unexpressible. Needs mi.set_variant('scalar_rgb') first."""
    return _Converter(path, width, height).convert()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--width", type=int)
    args = ap.parse_args()
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    status = 0
    for path in args.scenes:
        try:
            d = mitsuba_scene_dict(path, args.width)
            mi.load_dict(d)
            print(f"{path}: expressible ({sum(1 for k in d if k.startswith('shape_'))} shapes, "
                  f"{sum(1 for k in d if k.startswith('light_'))} lights)")
        except Unexpressible as e:
            print(e)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
