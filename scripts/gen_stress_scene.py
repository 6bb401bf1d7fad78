#!/usr/bin/env python3
"""Generates a >= 1M-triangle stress scene: a tessellated, displaced 4 x 4 m terrain written as
stress.gltf + stress.bin (one buffer, float positions, uint32 indices), and stress.json, a
JSON scene that includes it and adds a camera, a diffuse sphere and lights.

    python3 scripts/gen_stress_scene.py OUT_DIR [--grid N]

N vertices per side (default 709: 2 * 708^2 = 1,002,528 triangles). The output is large
(~18 MB) and is not committed.
"""
import argparse
import array
import json
import math
import os


def height(x, z):
    # Rolling hills plus fine ripples, so the BVH sees both large and small scales.
    return (0.25 * math.sin(1.7 * x) * math.cos(1.3 * z) + 0.04 * math.sin(9.0 * x + 7.0 * z)
            + 0.01 * math.sin(41.0 * x) * math.sin(37.0 * z))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out_dir")
    ap.add_argument("--grid", type=int, default=709, help="vertices per side (>= 2)")
    args = ap.parse_args()
    n = max(2, args.grid)
    os.makedirs(args.out_dir, exist_ok=True)

    size = 4.0
    positions = array.array("f")
    for j in range(n):
        z = -size / 2 + size * j / (n - 1)
        for i in range(n):
            x = -size / 2 + size * i / (n - 1)
            positions.extend((x, height(x, z), z))
    indices = array.array("I")
    for j in range(n - 1):
        row, nxt = j * n, (j + 1) * n
        for i in range(n - 1):
            a, b, c, d = row + i, row + i + 1, nxt + i + 1, nxt + i
            # Counter-clockwise seen from +Y: (a, d, c) and (a, c, b).
            indices.extend((a, d, c, a, c, b))
    pos_bytes, idx_bytes = positions.tobytes(), indices.tobytes()
    with open(os.path.join(args.out_dir, "stress.bin"), "wb") as f:
        f.write(pos_bytes)
        f.write(idx_bytes)

    ys = positions[1::3]
    gltf = {
        "asset": {"version": "2.0", "generator": "photoncl scripts/gen_stress_scene.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "terrain", "mesh": 0}],
        "meshes": [{"name": "terrain", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"name": "ground", "pbrMetallicRoughness": {
            "baseColorFactor": [0.55, 0.5, 0.42, 1], "metallicFactor": 0, "roughnessFactor": 1}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3",
             "min": [-size / 2, min(ys), -size / 2], "max": [size / 2, max(ys), size / 2]},
            {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos_bytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos_bytes), "byteLength": len(idx_bytes), "target": 34963},
        ],
        "buffers": [{"byteLength": len(pos_bytes) + len(idx_bytes), "uri": "stress.bin"}],
    }
    with open(os.path.join(args.out_dir, "stress.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)

    scene = {
        "comment": f"Stress scene: {len(indices) // 3} terrain triangles from stress.gltf.",
        "include": "stress.gltf",
        "camera": {"position": [0, 2.2, 4.2], "look_at": [0, 0, 0], "fov": 45, "resolution": [256, 256]},
        "materials": [{"name": "white", "rho_d": [0.7, 0.7, 0.7]}],
        "shapes": [{"type": "sphere", "material": "white", "centre": [0.5, 0.6, 0.5], "radius": 0.3}],
        "lights": [
            {"type": "area", "name": "sky-panel", "shape": "quad", "corner": [-1, 3, -1], "edge_u": [2, 0, 0],
             "edge_v": [0, 0, 2], "power": [120, 120, 115]},
            {"type": "directional", "name": "sun", "direction": [-0.5, -1, -0.3], "irradiance": [2.0, 1.9, 1.7]},
        ],
    }
    with open(os.path.join(args.out_dir, "stress.json"), "w") as f:
        json.dump(scene, f, indent=2)
    print(f"{len(indices) // 3} triangles, {n * n} vertices -> {args.out_dir}/stress.json")


if __name__ == "__main__":
    main()
