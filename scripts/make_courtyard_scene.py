#!/usr/bin/env python3
"""Writes scenes/courtyard/: a sunny courtyard under an image sky, photoncl's textured asset.

    python3 scripts/make_courtyard_scene.py [OUT_DIR]      (default: scenes/courtyard)

Everything is generated here, deterministically, so the asset is reproducible and carries no
third-party licence:
- courtyard.gltf: a tiled floor (baseColorTexture repeated by KHR_texture_transform), a brick
  wall (baseColorTexture), a plaster wall with a normal map of gentle bumps (normalTexture,
  repeated; tangents left to the loader), a wooden crate (baseColorTexture) and a glass ball (KHR_materials_transmission
  + KHR_materials_ior) that throws the sun's caustic on the floor; a perspective camera. One
  buffer, embedded as a base64 data URI.
- tiles.png, bricks.png, planks.png: 8-bit sRGB PNGs, 256 × 256.
- plaster-normal.png: an 8-bit linear tangent-space normal map, 128 × 128, tileable (glTF's
  convention: rgb = (n + 1)/2, +x right, +y up the image).
- sky.pfm: an equirectangular sky (photoncl's and Mitsuba's mapping: u = atan2(w.x, −w.z)/2π,
  v = acos(w.y)/π, row 0 up): a blue gradient, a darker ground, and a sun of one texel whose
  irradiance is SUN_IRRADIANCE at normal incidence.
- courtyard.json: the scene users render, the glTF `include`d under the sky.
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_gltf_scene import Buffer, MaterialMeshes, cube, quat  # noqa: E402

TEXTURE_SIZE = 256
SKY_WIDTH, SKY_HEIGHT = 256, 128
SUN_DIRECTION = (0.62, 0.72, 0.32)  # toward the sun: from the right, a little in front
SUN_IRRADIANCE = 2.5  # W m⁻² at normal incidence
SKY_ZENITH, SKY_HORIZON, GROUND = (0.10, 0.17, 0.36), (0.32, 0.36, 0.41), (0.07, 0.065, 0.06)


def normalize(v):
    length = math.sqrt(sum(c * c for c in v))
    return [c / length for c in v]


def hash01(*ints):
    """A deterministic number in [0, 1) from integers (so the textures never change)."""
    h = 2166136261
    for i in ints:
        for byte in struct.pack("<i", i):
            h = ((h ^ byte) * 16777619) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 2246822519) & 0xFFFFFFFF
    h ^= h >> 13
    return h / 4294967296.0


def write_png(path, width, height, pixel):
    """An 8-bit RGB PNG; pixel(x, y) gives three numbers in [0, 1] (already encoded)."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            rows += bytes(max(0, min(255, round(c * 255))) for c in pixel(x, y))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b""))


def tiles(x, y):
    """Sandstone tiles, 4 × 4 per texture, grout lines 4 texels wide."""
    n = TEXTURE_SIZE // 4
    tx, ty, lx, ly = x // n, y // n, x % n, y % n
    if lx < 3 or ly < 3:
        return (0.42, 0.40, 0.37)
    tone = 0.82 + 0.18 * hash01(tx, ty) + 0.04 * (hash01(x, y, 7) - 0.5)
    return (0.80 * tone, 0.68 * tone, 0.52 * tone)


def brick_cell(x, y):
    """(row, column, x within the brick, y within the brick) of a running-bond brick pattern:
    8 rows of 32 texels, bricks 64 texels long, odd rows shifted by half a brick."""
    row = y // 32
    shifted = x + (32 if row % 2 else 0)
    return row, (shifted // 64) % 4, shifted % 64, y % 32


MORTAR = 3


def bricks(x, y):
    row, col, bx, by = brick_cell(x, y)
    if bx < MORTAR or by < MORTAR:
        return (0.74, 0.72, 0.68)
    tone = 0.75 + 0.3 * hash01(row, col) + 0.05 * (hash01(x, y, 11) - 0.5)
    return (0.62 * tone, 0.30 * tone, 0.22 * tone)


def planks(x, y):
    """Horizontal wooden planks, 5 per texture, with grain stripes and dark gaps."""
    n = TEXTURE_SIZE // 5 + 1
    plank, ly = y // n, y % n
    if ly < 2:
        return (0.12, 0.08, 0.05)
    grain = 0.5 + 0.5 * math.sin(0.09 * x * (1 + hash01(plank)) + 6 * hash01(plank, 3) + 0.35 * math.sin(0.05 * x + ly))
    tone = 0.7 + 0.25 * hash01(plank, 1) + 0.12 * grain
    return (0.55 * tone, 0.36 * tone, 0.20 * tone)


PLASTER_NORMAL_SIZE = 128


def plaster_height(x, y):
    """Tileable value noise (period PLASTER_NORMAL_SIZE): two octaves of smoothly interpolated
    lattice values, the plaster's bumps in texels of height."""
    h = 0.0
    for cell, amplitude in ((16, 1.6), (8, 0.7)):
        n = PLASTER_NORMAL_SIZE // cell
        gx, gy = x / cell, y / cell
        ix, iy = int(math.floor(gx)), int(math.floor(gy))
        fx, fy = gx - ix, gy - iy
        sx, sy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)

        def lattice(i, j):
            return hash01(7, cell, i % n, j % n)

        top = lattice(ix, iy) * (1 - sx) + lattice(ix + 1, iy) * sx
        bottom = lattice(ix, iy + 1) * (1 - sx) + lattice(ix + 1, iy + 1) * sx
        h += amplitude * (top * (1 - sy) + bottom * sy)
    return h


def plaster_normal(x, y):
    """The bumps' tangent-space normal, encoded: n = normalise(−∂h/∂x, ∂h/∂row, 1) (rows run down
    the image, +y up), rgb = (n + 1)/2, linear (a normal map is not sRGB)."""
    size = PLASTER_NORMAL_SIZE
    hx = (plaster_height((x + 1) % size, y) - plaster_height((x - 1) % size, y)) / 2
    hy = (plaster_height(x, (y + 1) % size) - plaster_height(x, (y - 1) % size)) / 2
    n = normalize([-hx, hy, 1.0])
    return [(c + 1) / 2 for c in n]


def srgb(pixel):
    """Encodes a linear colour function as sRGB (the glTF colour textures' encoding)."""
    def encode(c):
        return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
    return lambda x, y: tuple(encode(c) for c in pixel(x, y))


def sky_texel_of(w):
    u = math.atan2(w[0], -w[2]) / (2 * math.pi)
    u -= math.floor(u)
    v = math.acos(max(-1.0, min(1.0, w[1]))) / math.pi
    return min(SKY_WIDTH - 1, int(u * SKY_WIDTH)), min(SKY_HEIGHT - 1, int(v * SKY_HEIGHT))


def write_sky(path):
    sun_x, sun_y = sky_texel_of(normalize(SUN_DIRECTION))
    theta0, theta1 = math.pi * sun_y / SKY_HEIGHT, math.pi * (sun_y + 1) / SKY_HEIGHT
    sun_solid_angle = 2 * math.pi / SKY_WIDTH * (math.cos(theta0) - math.cos(theta1))
    sun_radiance = SUN_IRRADIANCE / sun_solid_angle
    rows = []
    for y in range(SKY_HEIGHT):
        cos_theta = math.cos(math.pi * (y + 0.5) / SKY_HEIGHT)
        row = []
        for x in range(SKY_WIDTH):
            if (x, y) == (sun_x, sun_y):
                row.append((sun_radiance * 1.0, sun_radiance * 0.93, sun_radiance * 0.82))
            elif cos_theta > 0:
                t = cos_theta ** 0.6
                row.append(tuple(h + (z - h) * t for z, h in zip(SKY_ZENITH, SKY_HORIZON)))
            else:
                row.append(GROUND)
        rows.append(row)
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (SKY_WIDTH, SKY_HEIGHT))
        for row in reversed(rows):  # PFM stores the bottom row first
            f.write(struct.pack("<%df" % (3 * SKY_WIDTH), *[c for px in row for c in px]))
    return sun_radiance, sun_solid_angle


def plane_uv():
    """Unit square in the XZ plane, normal +Y, with texture coordinates 0..1 (v down the image
    = toward +z, so the texture reads upright from the camera's side)."""
    p = [[-0.5, 0, -0.5], [-0.5, 0, 0.5], [0.5, 0, 0.5], [0.5, 0, -0.5]]
    uv = [[0, 0], [0, 1], [1, 1], [1, 0]]
    return p, [[0, 1, 0]] * 4, uv, [0, 1, 2, 0, 2, 3]


def cube_uv():
    """cube() with each face's corners mapped to the texture's corners."""
    p, n, idx = cube()
    uv = [[0, 1], [1, 1], [1, 0], [0, 0]] * 6
    return p, n, uv, idx


def sphere(rows=24, columns=48):
    """A unit UV sphere: smooth normals, counter-clockwise seen from outside."""
    p, n, uv, idx = [], [], [], []
    for i in range(rows + 1):
        theta = math.pi * i / rows
        for j in range(columns + 1):
            phi = 2 * math.pi * j / columns
            v = [math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi)]
            p.append(v)
            n.append(v)
            uv.append([j / columns, i / rows])
    for i in range(rows):
        for j in range(columns):
            a, b = i * (columns + 1) + j, (i + 1) * (columns + 1) + j
            if i > 0:
                idx += [a, b, a + 1]
            if i < rows - 1:
                idx += [a + 1, b, b + 1]
    return p, n, uv, idx


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def look_at(position, target):
    """The rotation that turns a glTF camera (looking down −Z, up +Y) toward target."""
    d = [t - p for t, p in zip(target, position)]
    yaw = math.degrees(math.atan2(-d[0], -d[2]))
    pitch = math.degrees(math.atan2(d[1], math.hypot(d[0], d[2])))
    return quat_mul(quat([0, 1, 0], yaw), quat([1, 0, 0], pitch))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "scenes", "courtyard")
    os.makedirs(out, exist_ok=True)
    write_png(os.path.join(out, "tiles.png"), TEXTURE_SIZE, TEXTURE_SIZE, srgb(tiles))
    write_png(os.path.join(out, "bricks.png"), TEXTURE_SIZE, TEXTURE_SIZE, srgb(bricks))
    write_png(os.path.join(out, "planks.png"), TEXTURE_SIZE, TEXTURE_SIZE, srgb(planks))
    write_png(os.path.join(out, "plaster-normal.png"), PLASTER_NORMAL_SIZE, PLASTER_NORMAL_SIZE, plaster_normal)
    sun_radiance, sun_solid_angle = write_sky(os.path.join(out, "sky.pfm"))

    buf = Buffer()
    meshes = []
    for name, (p, n, uv, idx) in (("plane", plane_uv()), ("cube", cube_uv()), ("sphere", sphere())):
        attributes = {"POSITION": buf.vec3(p), "NORMAL": buf.vec3(n),
                      "TEXCOORD_0": buf.add("f", [c for t in uv for c in t], len(uv), "VEC2", 5126, 34962)}
        meshes.append({"name": name, "primitives": [{"attributes": attributes, "indices": buf.indices(idx)}]})
    PLANE, CUBE, SPHERE = range(3)

    images = [{"uri": name} for name in ("tiles.png", "bricks.png", "planks.png", "plaster-normal.png")]
    TILES, BRICKS, PLANKS, PLASTER_NORMAL = range(4)
    textures = [{"source": i, "sampler": 0} for i in range(len(images))]
    samplers = [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}]  # linear, repeat

    def texture(index, repeat=None):
        t = {"index": index}
        if repeat:
            t["extensions"] = {"KHR_texture_transform": {"scale": repeat}}
        return t

    def diffuse(name, base_texture=None, repeat=None, factor=(1, 1, 1)):
        pbr = {"baseColorFactor": list(factor) + [1], "metallicFactor": 0, "roughnessFactor": 1}
        if base_texture is not None:
            pbr["baseColorTexture"] = texture(base_texture, repeat)
        return {"name": name, "pbrMetallicRoughness": pbr}

    materials = [
        diffuse("floor-tiles", TILES, repeat=[2.5, 2.5]),
        diffuse("brick-wall", BRICKS, repeat=[5, 2]),
        dict(diffuse("plaster", factor=(0.72, 0.70, 0.66)), normalTexture=dict(texture(PLASTER_NORMAL, [2, 5]), scale=1.0)),
        diffuse("crate-planks", PLANKS),
        {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5}}},
    ]
    FLOOR, BRICK, PLASTER, CRATE, GLASS = range(5)
    mesh = MaterialMeshes(meshes, materials)

    nodes = []

    def node(name, **kw):
        nodes.append(dict(name=name, **kw))
        return len(nodes) - 1

    camera_position = [1.1, 1.3, 4.2]
    scene_nodes = [
        # A 5 × 5 m floor from z = −1.5 (the brick wall) toward the camera; walls 2 m high.
        node("floor", mesh=mesh(PLANE, FLOOR), translation=[0, 0, 1], scale=[5, 1, 5]),
        node("brick-wall", mesh=mesh(PLANE, BRICK), translation=[0, 1, -1.5], rotation=quat([1, 0, 0], 90), scale=[5, 1, 2]),
        node("plaster-wall", mesh=mesh(PLANE, PLASTER), translation=[-2.5, 1, 1], rotation=quat([0, 0, 1], -90), scale=[2, 1, 5]),
        node("crate", mesh=mesh(CUBE, CRATE), translation=[-0.8, 0.3, 0.1], rotation=quat([0, 1, 0], 30), scale=[0.6, 0.6, 0.6]),
        node("glass-ball", mesh=mesh(SPHERE, GLASS), translation=[0.45, 0.35, 0.2], scale=[0.35, 0.35, 0.35]),
        node("camera", camera=0, translation=camera_position, rotation=look_at(camera_position, [-0.3, 0.6, -0.5])),
    ]

    data_uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(buf.data)).decode()
    gltf = {
        "asset": {"version": "2.0", "generator": "photoncl scripts/make_courtyard_scene.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior", "KHR_texture_transform"],
        "scene": 0,
        "scenes": [{"name": "courtyard", "nodes": scene_nodes}],
        "nodes": nodes,
        "meshes": mesh.meshes,
        "materials": materials,
        "textures": textures,
        "images": images,
        "samplers": samplers,
        "cameras": [{"type": "perspective", "perspective": {"yfov": math.radians(45), "aspectRatio": 1.0, "znear": 0.01}}],
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data), "uri": data_uri}],
    }
    with open(os.path.join(out, "courtyard.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")

    scene = {
        "comment": ("A sunny courtyard, written by scripts/make_courtyard_scene.py: tiled floor, brick wall, "
                    "wooden crate, a normal-mapped plaster wall, a glass ball's caustic; lit only by sky.pfm "
                    f"(sun: one texel of {sun_radiance:.0f} W m^-2 sr^-1 over {sun_solid_angle:.3g} sr, "
                    f"{SUN_IRRADIANCE} W m^-2 at normal incidence)."),
        "environment": {"image": "sky.pfm"},
        "include": "courtyard.gltf",
    }
    with open(os.path.join(out, "courtyard.json"), "w") as f:
        json.dump(scene, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
