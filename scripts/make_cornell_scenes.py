#!/usr/bin/env python3
"""Writes the shipped Cornell-box scenes (scenes/cornell-*.json, and the ones with participating
media in scenes/media/) from one description, so the box, its materials and its light stay
identical across them.

Geometry follows the Cornell box measurements (https://www.graphics.cornell.edu/online/box/data.html),
in metres, axis-aligned: x 0..0.556 (red wall at x = 0.556, seen on the left), y 0..0.5488 up,
z 0..0.5592 away from the camera, open towards -z where the camera stands.

    python3 scripts/make_cornell_scenes.py [OUT_DIR]     (default: scenes/)
"""
import json
import math
import os
import sys

W, H, D = 0.556, 0.5488, 0.5592

MATERIALS = {
    "white": {"name": "white", "rho_d": [0.73, 0.73, 0.73]},
    "red": {"name": "red", "rho_d": [0.63, 0.065, 0.05]},
    "green": {"name": "green", "rho_d": [0.14, 0.45, 0.091]},
    "mirror": {"name": "mirror", "specular": {"kind": "mirror", "rho_s": [0.9, 0.9, 0.9]}},
    "glass": {"name": "glass", "specular": {"kind": "dielectric", "rho_s": [1.0, 1.0, 1.0], "ior": 1.5}},
    "glossy-floor": {"name": "glossy-floor", "rho_d": [0.45, 0.45, 0.45],
                     "specular": {"kind": "glossy", "rho_s": [0.3, 0.3, 0.3], "exponent": 60}},
}

# Ceiling lamp: 0.13 x 0.105 m, 1 mm below the ceiling, facing down. Radiance 40 W m^-2 sr^-1
# (warm white) lights the white walls to a radiance of roughly 0.3-1.
LIGHT_RADIANCE = [40.0, 34.0, 26.0]
LAMP_CORNER = [0.213, H - 0.001, 0.227]
LAMP_U, LAMP_V = [0.13, 0.0, 0.0], [0.0, 0.0, 0.105]
LAMP_AREA = 0.13 * 0.105


def quad(name, material, corner, u, v):
    return {"type": "quad", "name": name, "material": material, "corner": corner, "edge_u": u, "edge_v": v}


def walls(floor="white"):
    # Each quad's normal cross(edge_u, edge_v) points into the box.
    return [
        quad("floor", floor, [0, 0, 0], [0, 0, D], [W, 0, 0]),
        quad("ceiling", "white", [0, H, 0], [W, 0, 0], [0, 0, D]),
        quad("back", "white", [0, 0, D], [0, H, 0], [W, 0, 0]),
        quad("left-red", "red", [W, 0, 0], [0, 0, D], [0, H, 0]),
        quad("right-green", "green", [0, 0, 0], [0, H, 0], [0, 0, D]),
    ]


def block(name, top, height):
    """A box with the given 4 top corners (x, z) at `height`: 5 faces (no bottom), 10 triangles,
    each wound so its normal points out of the block."""
    positions = [[x, height, z] for x, z in top] + [[x, 0.0, z] for x, z in top]
    cx = sum(p[0] for p in positions[:4]) / 4
    cz = sum(p[2] for p in positions[:4]) / 4
    centre = [cx, height / 2, cz]
    faces = [(0, 1, 2, 3)] + [(i, (i + 1) % 4, 4 + (i + 1) % 4, 4 + i) for i in range(4)]
    indices = []
    for a, b, c, d in faces:
        for tri in ((a, b, c), (a, c, d)):
            p0, p1, p2 = (positions[k] for k in tri)
            e1 = [p1[i] - p0[i] for i in range(3)]
            e2 = [p2[i] - p0[i] for i in range(3)]
            n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
            out = [p0[i] - centre[i] for i in range(3)]
            if sum(n[i] * out[i] for i in range(3)) < 0:
                tri = (tri[0], tri[2], tri[1])
            indices += list(tri)
    return {"type": "mesh", "name": name, "material": "white",
            "positions": [round(c, 4) for p in positions for c in p], "indices": indices}


BLOCKS = [
    block("short-block", [(0.130, 0.065), (0.082, 0.225), (0.240, 0.272), (0.290, 0.114)], 0.165),
    block("tall-block", [(0.423, 0.247), (0.265, 0.296), (0.314, 0.456), (0.472, 0.406)], 0.330),
]

CAMERA = {"type": "pinhole", "position": [0.278, 0.273, -0.800], "look_at": [0.278, 0.273, 0.0],
          "up": [0, 1, 0], "fov": 39.3, "resolution": [256, 256]}

AREA_LIGHT = {"type": "area", "name": "ceiling-lamp", "shape": "quad", "corner": LAMP_CORNER,
              "edge_u": LAMP_U, "edge_v": LAMP_V, "radiance": LIGHT_RADIANCE}

# The same lamp given by total power: Φ = π·A·L.
AREA_LIGHT_BY_POWER = dict(AREA_LIGHT)
del AREA_LIGHT_BY_POWER["radiance"]
AREA_LIGHT_BY_POWER["power"] = [round(math.pi * LAMP_AREA * L, 6) for L in LIGHT_RADIANCE]

# A point light 10 cm below the lamp with the lamp's total power (Φ = π·A·L): the scene receives
# the same flux; the point light spreads it over the whole sphere of directions.
POINT_LIGHT = {"type": "point", "name": "ceiling-point", "position": [0.278, H - 0.10, 0.2795],
               "power": AREA_LIGHT_BY_POWER["power"]}


SPHERES = [
    {"type": "sphere", "name": "mirror-ball", "material": "mirror", "centre": [0.40, 0.10, 0.37], "radius": 0.10},
    {"type": "sphere", "name": "glass-ball", "material": "glass", "centre": [0.17, 0.10, 0.19], "radius": 0.10},
]


def scene(comment, materials, shapes, lights, media=None):
    s = {"comment": comment, "camera": CAMERA, "materials": [MATERIALS[m] for m in materials]}
    if media:
        s["media"] = media
        s["medium"] = media[0]["name"]  # the first one fills the scene
    s.update({"shapes": shapes, "lights": lights})
    return s


# Thin grey fog filling the scene (also outside the open box): optical depth ~0.35 across the
# box, slightly forward scattering; enough to show the lamp's light and the volume caustic the
# glass ball focuses below itself.
FOG = {"name": "fog", "sigma_a": [0.05, 0.05, 0.05], "sigma_s": [0.6, 0.6, 0.6], "g": 0.2}
# Haze for light shafts: more forward scattering, so the spot's cone glows toward the camera.
HAZE = {"name": "haze", "sigma_a": [0.02, 0.02, 0.02], "sigma_s": [0.8, 0.8, 0.8], "g": 0.5}

# A spot light high in the left-front corner aimed at the floor between the blocks: the cone
# shows in the haze, cut by the blocks' shadows. Power chosen to light the floor about as the lamp does.
SPOT_LIGHT = {"type": "spot", "name": "corner-spot", "position": [0.50, H - 0.03, 0.05],
              "direction": [-0.45, -0.80, 0.40], "power": [1.6, 1.45, 1.2], "inner_angle": 12, "outer_angle": 18}


SCENES = {
    "cornell-box.json": scene(
        "The Cornell box: diffuse walls, red and green sides, two white blocks, an area lamp in the ceiling.",
        ["white", "red", "green"], walls() + BLOCKS, [AREA_LIGHT]),
    "cornell-spheres.json": scene(
        "The Cornell box with a mirror sphere and a glass sphere (caustics); lamp given by total power.",
        ["white", "red", "green", "mirror", "glass"], walls() + SPHERES, [AREA_LIGHT_BY_POWER]),
    "cornell-spheres-point.json": scene(
        "cornell-spheres lit by a point light of the lamp's power just below it (sharp shadows, point caustics).",
        ["white", "red", "green", "mirror", "glass"], walls() + SPHERES, [POINT_LIGHT]),
    "cornell-glossy.json": scene(
        "The Cornell box with a glossy floor (normalised Phong, exponent 60) reflecting the blocks.",
        ["white", "red", "green", "glossy-floor"], walls(floor="glossy-floor") + BLOCKS, [AREA_LIGHT]),
    # Participating media: rendered only by --method path until the volume photon map lands, so
    # kept in scenes/media/, where the tests over every shipped scene (photon methods) do not look.
    "media/cornell-fog.json": scene(
        "cornell-spheres in thin fog (global medium): the lamp's light in the air and the volume caustic "
        "under the glass ball (which holds no fog).",
        ["white", "red", "green", "mirror", "glass"], walls() + SPHERES, [AREA_LIGHT_BY_POWER], media=[FOG]),
    "media/hazy-room.json": scene(
        "The Cornell box with its blocks in haze, lit by a spot light from a high corner: light shafts "
        "cut by the blocks' shadows.",
        ["white", "red", "green"], walls() + BLOCKS, [SPOT_LIGHT], media=[HAZE]),
}


def dumps(value, indent=0):
    """JSON with objects one key per line and number arrays kept on one line (wrapped when long),
    which reads better than json.dump(indent=2) for coordinates."""
    pad = "  " * indent
    if isinstance(value, dict):
        items = [f'{pad}  {json.dumps(k)}: {dumps(v, indent + 1)}' for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list) and all(not isinstance(v, (dict, list)) for v in value):
        parts = [json.dumps(v) for v in value]
        lines, line = [], ""
        for part in parts:
            if line and len(line) + len(part) > 90:
                lines.append(line)
                line = ""
            line += (", " if line else "") + part
        lines.append(line)
        if len(lines) == 1:
            return "[" + lines[0] + "]"
        return "[\n" + ",\n".join(pad + "  " + l for l in lines) + "\n" + pad + "]"
    if isinstance(value, list):
        return "[\n" + ",\n".join(pad + "  " + dumps(v, indent + 1) for v in value) + "\n" + pad + "]"
    return json.dumps(value)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "scenes")
    for name, content in SCENES.items():
        os.makedirs(os.path.dirname(os.path.join(out, name)), exist_ok=True)
        with open(os.path.join(out, name), "w") as f:
            f.write(dumps(content) + "\n")


if __name__ == "__main__":
    main()
