#!/usr/bin/env python3
"""Records MikkTSpace's own tangents for test meshes: tests/data/mikktspace-tangents.json.

The reference is Morten Mikkelsen's mikktspace.c (the implementation Blender, Godot and glTF's
sample viewer use; zlib licence). No Debian package ships it, so this script takes it from the
PyPI sdist pymikktspace 0.3.0 (checked by its SHA-256), compiles it with a small driver (gcc,
-ffp-contract=off) and runs genTangSpaceDefault on each mesh below. photoncl's own implementation
(host/scene/mesh_tangents.cpp) is held to the file by tests/unit/mesh_tangents_test.cpp; CI reads
the JSON and never runs this script.

    scripts/make_mikktspace_references.py [--mikktspace-dir DIR] [-o tests/data/mikktspace-tangents.json]

Without --mikktspace-dir (a folder holding mikktspace.c and mikktspace.h) the sdist is fetched
with `pip download` (its metadata step needs `pip install "cython<3" setuptools_scm`).

The tangents are per triangle corner, as MikkTSpace gives them: x, y, z and MikkTSpace's sign
(+1 where the UV triangle keeps its orientation). glTF's w is the opposite sign (its v runs down
the image); the test converts.
"""
import argparse
import hashlib
import json
import math
import os
import struct
import subprocess
import sys
import tarfile
import tempfile

SDIST = "pymikktspace-0.3.0.tar.gz"
SDIST_SHA256 = "26e88815c1ec5cd02481be6055d61a5a45f65e1cd04f95cf0917aa63dfc1115c"
MIKKTSPACE_C_SHA256 = "de87e74107df766ce68108801262bd8d53899414236b59810509a8fc2a51e288"

DRIVER = r"""
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include "mikktspace.h"
/* stdin: nv nt hasNormals, then nv lines "px py pz nx ny nz u v", then nt lines "i j k".
   stdout: per corner "tx ty tz sign". Without normals, each corner gets its face's normal. */
static int nv, nt, hasNormals;
static float *P, *N, *UV, *T;
static int *I;
static int numFaces(const SMikkTSpaceContext* c) { (void)c; return nt; }
static int numVerts(const SMikkTSpaceContext* c, int f) { (void)c; (void)f; return 3; }
static void pos(const SMikkTSpaceContext* c, float o[], int f, int k) {
    (void)c; for (int a = 0; a < 3; ++a) o[a] = P[3 * I[3 * f + k] + a]; }
static void nrm(const SMikkTSpaceContext* c, float o[], int f, int k) {
    (void)c;
    if (hasNormals) { for (int a = 0; a < 3; ++a) o[a] = N[3 * I[3 * f + k] + a]; return; }
    const float* p0 = &P[3 * I[3 * f]]; const float* p1 = &P[3 * I[3 * f + 1]]; const float* p2 = &P[3 * I[3 * f + 2]];
    float e1[3], e2[3];
    for (int a = 0; a < 3; ++a) { e1[a] = p1[a] - p0[a]; e2[a] = p2[a] - p0[a]; }
    float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 3; ++a) o[a] = n[a] * (1.0f / l);
}
static void tex(const SMikkTSpaceContext* c, float o[], int f, int k) {
    (void)c; o[0] = UV[2 * I[3 * f + k]]; o[1] = UV[2 * I[3 * f + k] + 1]; }
static void setBasic(const SMikkTSpaceContext* c, const float t[], float sign, int f, int k) {
    (void)c; for (int a = 0; a < 3; ++a) T[4 * (3 * f + k) + a] = t[a]; T[4 * (3 * f + k) + 3] = sign; }
int main(void) {
    if (scanf("%d %d %d", &nv, &nt, &hasNormals) != 3) return 1;
    P = malloc(sizeof(float) * 3 * nv); N = malloc(sizeof(float) * 3 * nv); UV = malloc(sizeof(float) * 2 * nv);
    I = malloc(sizeof(int) * 3 * nt); T = malloc(sizeof(float) * 12 * nt);
    for (int v = 0; v < nv; ++v)
        if (scanf("%f %f %f %f %f %f %f %f", &P[3*v], &P[3*v+1], &P[3*v+2], &N[3*v], &N[3*v+1], &N[3*v+2],
                  &UV[2*v], &UV[2*v+1]) != 8) return 1;
    for (int t = 0; t < 3 * nt; ++t) if (scanf("%d", &I[t]) != 1) return 1;
    SMikkTSpaceInterface iface = {0};
    iface.m_getNumFaces = numFaces; iface.m_getNumVerticesOfFace = numVerts; iface.m_getPosition = pos;
    iface.m_getNormal = nrm; iface.m_getTexCoord = tex; iface.m_setTSpaceBasic = setBasic;
    SMikkTSpaceContext ctx = {&iface, 0};
    if (!genTangSpaceDefault(&ctx)) return 2;
    for (int c = 0; c < 3 * nt; ++c) printf("%.9g %.9g %.9g %.9g\n", T[4*c], T[4*c+1], T[4*c+2], T[4*c+3]);
    return 0;
}
"""


def f32(x):
    """x rounded to float32, so the C driver and the C++ test read the same value."""
    return struct.unpack("f", struct.pack("f", x))[0]


class Lcg:
    def __init__(self, seed):
        self.s = seed

    def next(self):  # in [0, 1)
        self.s = (self.s * 1103515245 + 12345) % (1 << 31)
        return self.s / float(1 << 31)


def normalize(v):
    l = math.sqrt(sum(c * c for c in v))
    return [c / l for c in v]


def uv_sphere(segments=12, rings=6):
    """Seam duplicated, each pole one vertex per segment (as exporters write it)."""
    P, N, UV, I = [], [], [], []
    for r in range(rings + 1):
        th = math.pi * r / rings
        for k in range(segments + 1):
            ph = 2 * math.pi * k / segments
            p = [math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)]
            u = (k + 0.5) / segments if r in (0, rings) else k / segments
            P.append(p); N.append(normalize(p)); UV.append([u, r / rings])
    row = segments + 1
    for r in range(rings):
        for k in range(segments):
            a, b = r * row + k, r * row + k + 1
            c, d = a + row, b + row
            if r > 0: I.append([a, b, c])
            if r < rings - 1: I.append([b, d, c])
    return P, N, UV, I


def mirrored_grid(n=5):
    """A plane facing +y whose u is mirrored at x = 0: the middle column's vertices belong to
    triangles of both orientations."""
    P, N, UV, I = [], [], [], []
    for j in range(n):
        for i in range(n):
            x, z = -1 + 2 * i / (n - 1), -1 + 2 * j / (n - 1)
            P.append([x, 0, z]); N.append([0, 1, 0]); UV.append([abs(x), (z + 1) / 2])
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            I += [[a, a + n, a + 1], [a + 1, a + n, a + n + 1]]
    return P, N, UV, I


def flat_cube():
    """Eight shared vertices and no normals: every corner takes its face's normal."""
    P = [[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    UV = [[0.3 * (x + 1) + 0.1 * (z + 1), 0.35 * (y + 1) + 0.05 * (x + 1)] for x, y, z in P]
    idx = lambda x, y, z: 4 * (x > 0) + 2 * (y > 0) + (z > 0)
    quads = [  # outward, counter-clockwise
        [(1, -1, -1), (1, 1, -1), (1, 1, 1), (1, -1, 1)], [(-1, -1, -1), (-1, -1, 1), (-1, 1, 1), (-1, 1, -1)],
        [(-1, 1, -1), (-1, 1, 1), (1, 1, 1), (1, 1, -1)], [(-1, -1, -1), (1, -1, -1), (1, -1, 1), (-1, -1, 1)],
        [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)], [(-1, -1, -1), (-1, 1, -1), (1, 1, -1), (1, -1, -1)]]
    I = []
    for q in quads:
        v = [idx(*c) for c in q]
        I += [[v[0], v[1], v[2]], [v[0], v[2], v[3]]]
    return P, None, UV, I


def bumpy_grid(n=7):
    """A height field with jittered coordinates and rounded normals, plus the cases MikkTSpace
    handles apart: a triangle of zero UV area (joins its neighbours' group), a degenerate
    triangle (two corners at one position: copies a good corner's tangent) and three triangles
    on one edge (a butterfly)."""
    rng = Lcg(20261203)
    P, N, UV, I = [], [], [], []
    h = lambda x, z: 0.25 * math.sin(2.1 * x + 0.3) * math.cos(1.7 * z - 0.2)
    for j in range(n):
        for i in range(n):
            x, z = -1 + 2 * i / (n - 1), -1 + 2 * j / (n - 1)
            e = 1e-3
            dx = (h(x + e, z) - h(x - e, z)) / (2 * e)
            dz = (h(x, z + e) - h(x, z - e)) / (2 * e)
            P.append([x, h(x, z), z])
            N.append(normalize([-dx, 1, -dz]))
            UV.append([0.5 + 0.45 * x + 0.04 * (rng.next() - 0.5), 0.5 - 0.45 * z + 0.04 * (rng.next() - 0.5)])
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            I += [[a, a + n, a + 1], [a + 1, a + n, a + n + 1]]
    # Zero UV area: the corners of triangle 7 given collinear coordinates (new vertices).
    t = I[7]
    base = len(P)
    for k, v in enumerate(t):
        P.append(P[v][:]); N.append(N[v][:]); UV.append([0.2 + 0.1 * k, 0.3 + 0.1 * k])
    I[7] = [base, base + 1, base + 2]
    # Degenerate: corners 0 and 1 at one position with different coordinates.
    v0, v1 = I[20][0], I[20][2]
    P.append(P[v0][:]); N.append(N[v0][:]); UV.append([UV[v0][0] + 0.01, UV[v0][1]])
    I.append([v0, len(P) - 1, v1])
    # Butterfly: a fin standing on the edge of triangle 30.
    a, b = I[30][0], I[30][1]
    top = [(P[a][0] + P[b][0]) / 2, 0.8, (P[a][2] + P[b][2]) / 2]
    P.append(top); N.append([0, 0, 1]); UV.append([0.9, 0.1])
    I.append([b, a, len(P) - 1])
    return P, N, UV, I


CASES = [("uv-sphere", uv_sphere), ("mirrored-grid", mirrored_grid), ("flat-cube", flat_cube),
         ("bumpy-grid", bumpy_grid)]


def fetch_sources(work):
    subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "--no-binary", ":all:",
                    "--no-build-isolation", "pymikktspace==0.3.0", "-d", work], check=True)
    path = os.path.join(work, SDIST)
    digest = hashlib.sha256(open(path, "rb").read()).hexdigest()
    if digest != SDIST_SHA256:
        sys.exit(f"{path}: SHA-256 {digest}, expected {SDIST_SHA256}")
    with tarfile.open(path) as tar:
        for name in ("mikktspace.c", "mikktspace.h"):
            member = tar.getmember(f"pymikktspace-0.3.0/_external/MikkTSpace/{name}")
            with open(os.path.join(work, name), "wb") as out:
                out.write(tar.extractfile(member).read())
    return work


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mikktspace-dir", help="a folder with mikktspace.c and mikktspace.h")
    ap.add_argument("-o", "--output", default=os.path.join(os.path.dirname(__file__), "..", "tests", "data",
                                                           "mikktspace-tangents.json"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as work:
        src = args.mikktspace_dir or fetch_sources(work)
        c = os.path.join(src, "mikktspace.c")
        digest = hashlib.sha256(open(c, "rb").read()).hexdigest()
        if digest != MIKKTSPACE_C_SHA256:
            print(f"note: {c} has SHA-256 {digest}, not the recorded {MIKKTSPACE_C_SHA256}", file=sys.stderr)
        driver = os.path.join(work, "driver.c")
        open(driver, "w").write(DRIVER)
        exe = os.path.join(work, "mikk")
        subprocess.run(["gcc", "-O2", "-ffp-contract=off", "-std=gnu99", "-I", src, driver, c, "-o", exe, "-lm"],
                       check=True)
        cases = []
        for name, make in CASES:
            P, N, UV, I = make()
            P = [[f32(x) for x in p] for p in P]
            N = [[f32(x) for x in n] for n in N] if N else None
            UV = [[f32(x) for x in t] for t in UV]
            lines = [f"{len(P)} {len(I)} {1 if N else 0}"]
            for v in range(len(P)):
                n = N[v] if N else [0, 0, 0]
                lines.append(" ".join(repr(x) for x in P[v] + n + UV[v]))
            lines += [" ".join(str(i) for i in t) for t in I]
            out = subprocess.run([exe], input="\n".join(lines) + "\n", capture_output=True, text=True, check=True)
            tangents = [float(x) for x in out.stdout.split()]
            assert len(tangents) == 12 * len(I), name
            cases.append({"name": name, "positions": sum(P, []), "normals": sum(N, []) if N else [],
                          "uv": sum(UV, []), "indices": sum(I, []), "corner_tangents": tangents})
            print(f"{name}: {len(P)} vertices, {len(I)} triangles")
    doc = {"source": "mikktspace.c (genTangSpaceDefault) from the PyPI sdist " + SDIST + ", SHA-256 " +
                     MIKKTSPACE_C_SHA256 + " of mikktspace.c; made by scripts/make_mikktspace_references.py",
           "corner_tangents": "x, y, z, MikkTSpace's sign per triangle corner (glTF's w is its negative)",
           "cases": cases}
    tmp = args.output + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, separators=(",", ":"))
        f.write("\n")
    os.replace(tmp, args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
