#!/usr/bin/env python3
"""Writes scenes/gltf-room.gltf: a closed room with a ceiling lamp (emissive material with
KHR_materials_emissive_strength), a table built as a node hierarchy (translation, rotation, scale
at several levels), a brushed-metal box (glossy), a polished cube (mirror), a glass cube
(KHR_materials_transmission + KHR_materials_ior), a KHR_lights_punctual point light and a
perspective camera. One buffer, embedded as a base64 data URI, so the file stands alone.

    python3 scripts/make_gltf_scene.py [OUT.gltf]      (default: scenes/gltf-room.gltf)
"""
import base64
import json
import math
import os
import struct
import sys


class Buffer:
    """Accumulates binary data and the bufferViews/accessors that describe it."""

    def __init__(self):
        self.data = bytearray()
        self.views, self.accessors = [], []

    def add(self, fmt, values, count, acc_type, component, target, minmax=None):
        while len(self.data) % 4:
            self.data.append(0)
        offset = len(self.data)
        self.data += struct.pack("<" + fmt * len(values), *values)
        self.views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(self.data) - offset, "target": target})
        acc = {"bufferView": len(self.views) - 1, "componentType": component, "count": count, "type": acc_type}
        if minmax:
            acc["min"], acc["max"] = minmax
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def vec3(self, points):
        flat = [c for p in points for c in p]
        lo = [min(p[i] for p in points) for i in range(3)]
        hi = [max(p[i] for p in points) for i in range(3)]
        return self.add("f", flat, len(points), "VEC3", 5126, 34962, (lo, hi))

    def indices(self, idx):
        return self.add("H", idx, len(idx), "SCALAR", 5123, 34963)


class MaterialMeshes:
    """glTF binds materials to primitives, not nodes: one copy of a bare mesh per (shape, material),
    made on first use. Calling it gives the copy's index in `meshes`, the list to write (the bare
    meshes themselves are not written)."""

    def __init__(self, bare, materials):
        self.bare, self.materials, self.meshes, self.index = bare, materials, [], {}

    def __call__(self, shape, material):
        key = (shape, material)
        if key not in self.index:
            m = json.loads(json.dumps(self.bare[shape]))
            m["name"] = f'{m["name"]}-{self.materials[material]["name"]}'
            m["primitives"][0]["material"] = material
            self.meshes.append(m)
            self.index[key] = len(self.meshes) - 1
        return self.index[key]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def plane():
    """Unit square in the XZ plane, normal +Y, counter-clockwise seen from +Y."""
    p = [[-0.5, 0, -0.5], [-0.5, 0, 0.5], [0.5, 0, 0.5], [0.5, 0, -0.5]]
    return p, [[0, 1, 0]] * 4, [0, 1, 2, 0, 2, 3]


def cube():
    """Unit cube centred at the origin: 24 vertices (flat normals), 12 outward-facing triangles."""
    positions, normals, indices = [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [0, 0, 0]
            u[(axis + 1) % 3] = 1
            v = cross(n, u)
            base = len(positions)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                positions.append([0.5 * n[i] + 0.5 * a * u[i] + 0.5 * b * v[i] for i in range(3)])
                normals.append(n)
            # u x v = n, so (0,1,2) is counter-clockwise seen from outside.
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, indices


def quat(axis, degrees):
    s = math.sin(math.radians(degrees) / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(math.radians(degrees) / 2)]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "scenes", "gltf-room.gltf")
    buf = Buffer()
    meshes = []
    for name, (p, n, idx) in (("plane", plane()), ("cube", cube())):
        meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": buf.vec3(p), "NORMAL": buf.vec3(n)}, "indices": buf.indices(idx)}]})
    PLANE, CUBE = 0, 1

    materials = [
        {"name": "plaster", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.68, 1], "metallicFactor": 0, "roughnessFactor": 1}},
        {"name": "terracotta", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.32, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.95}},
        {"name": "wood", "pbrMetallicRoughness": {"baseColorFactor": [0.45, 0.3, 0.18, 1], "metallicFactor": 0, "roughnessFactor": 0.9}},
        {"name": "brushed-metal", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.78, 0.75, 1], "metallicFactor": 1, "roughnessFactor": 0.35}},
        {"name": "polished", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 1, "roughnessFactor": 0.02}},
        {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5}}},
        {"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 1},
         "emissiveFactor": [1.0, 0.9, 0.8], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 30}}},
    ]
    PLASTER, TERRACOTTA, WOOD, METAL, POLISHED, GLASS, LAMP = range(7)
    mesh = MaterialMeshes(meshes, materials)

    nodes = []

    def node(name, children=(), **kw):
        nodes.append(dict(name=name, **kw))
        if children:
            nodes[-1]["children"] = list(children)
        return len(nodes) - 1

    # Room 4 x 2.5 x 4 m, every surface facing inwards.
    room = [
        node("floor", mesh=mesh(PLANE, TERRACOTTA), scale=[4, 1, 4]),
        node("ceiling", mesh=mesh(PLANE, PLASTER), translation=[0, 2.5, 0], rotation=[1, 0, 0, 0], scale=[4, 1, 4]),
        node("back-wall", mesh=mesh(PLANE, PLASTER), translation=[0, 1.25, -2], rotation=quat([1, 0, 0], 90), scale=[4, 1, 2.5]),
        node("front-wall", mesh=mesh(PLANE, PLASTER), translation=[0, 1.25, 2], rotation=quat([1, 0, 0], -90), scale=[4, 1, 2.5]),
        node("left-wall", mesh=mesh(PLANE, PLASTER), translation=[-2, 1.25, 0], rotation=quat([0, 0, 1], -90), scale=[2.5, 1, 4]),
        node("right-wall", mesh=mesh(PLANE, PLASTER), translation=[2, 1.25, 0], rotation=quat([0, 0, 1], 90), scale=[2.5, 1, 4]),
        node("lamp", mesh=mesh(PLANE, LAMP), translation=[0, 2.49, -0.3], rotation=[1, 0, 0, 0], scale=[0.8, 1, 0.8]),
    ]
    # The table: a parent with translation + rotation; legs, top and objects placed relative to it.
    legs = [node(f"leg-{i}", mesh=mesh(CUBE, WOOD), translation=[x, 0.35, z], scale=[0.06, 0.7, 0.06])
            for i, (x, z) in enumerate(((-0.55, -0.3), (0.55, -0.3), (0.55, 0.3), (-0.55, 0.3)))]
    top = node("table-top", mesh=mesh(CUBE, WOOD), translation=[0, 0.73, 0], scale=[1.2, 0.06, 0.7])
    metal = node("metal-box", mesh=mesh(CUBE, METAL), translation=[-0.3, 0.86, 0], rotation=quat([0, 1, 0], 20), scale=[0.2, 0.2, 0.2])
    glass = node("glass-cube", mesh=mesh(CUBE, GLASS), translation=[0.3, 0.86, 0.05], scale=[0.2, 0.2, 0.2])
    table = node("table", legs + [top, metal, glass], translation=[0.3, 0, -0.6], rotation=quat([0, 1, 0], 30))
    mirror = node("mirror-cube", mesh=mesh(CUBE, POLISHED), translation=[-1.2, 0.3, -1.0], rotation=quat([0, 1, 0], -35), scale=[0.6, 0.6, 0.6])
    bulb = node("bulb", translation=[-1.2, 2.0, 0.8], extensions={"KHR_lights_punctual": {"light": 0}})
    camera = node("camera", camera=0, translation=[0, 1.3, 1.7], rotation=quat([1, 0, 0], -12))

    data_uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(buf.data)).decode()
    gltf = {
        "asset": {"version": "2.0", "generator": "photoncl scripts/make_gltf_scene.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior", "KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "bulb", "type": "point", "color": [1.0, 0.85, 0.6], "intensity": 700}]}},
        "scene": 0,
        "scenes": [{"name": "room", "nodes": room + [table, mirror, bulb, camera]}],
        "nodes": nodes,
        "meshes": mesh.meshes,
        "materials": materials,
        "cameras": [{"type": "perspective", "perspective": {"yfov": math.radians(60), "aspectRatio": 4 / 3, "znear": 0.01}}],
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data), "uri": data_uri}],
    }
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
