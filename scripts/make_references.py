#!/usr/bin/env python3
"""Converged references of the shipped scenes, made with the reference path
tracer (`photoncl render --method path`) and kept in tests/data/ as small half-float EXRs. Where a
point, spot or directional light shines through mirrors or glass (cornell-spheres-point,
motion-dof, gltf-room) the render adds the light tracer by itself (host/reference/light_tracer.h):
it finds the light paths the path tracer cannot.

Each reference is the average of two independent half renders (seeds 1 and 2, N/2 samples per
pixel each). The two halves also measure the reference's own error: with per-pixel variance s2
for one half, E[(A - B)^2] = 2 s2 and the average has variance s2 / 2, so the reference's
expected relMSE is relMSE(A, B) / 4 (the denominator uses B, close enough at these noise
levels). That figure goes into tests/data/references.md beside the samples and the time.

Usage: scripts/make_references.py [--photoncl build/photoncl] [--spp 16384] [--threads 1]
                                  [--only NAME ...] [--out tests/data]
Needs oiiotool (openimageio-tools) to average the halves. Run under `nice` on a shared machine.
"""
import argparse
import datetime
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Every shipped scene, at the width the accuracy tests render (height keeps the aspect ratio).
# The samples differ by how hard a scene is for a path tracer: caustics seen through glass
# from a small lamp need the most.
SCENES = [
    # (scene file, width, samples per pixel for the whole reference)
    ("cornell-box.json", 64, 16384),
    ("cornell-spheres.json", 64, 32768),
    ("cornell-spheres-point.json", 64, 16384),
    ("cornell-glossy.json", 64, 16384),
    ("motion-dof.json", 64, 16384),
    ("gltf-room.gltf", 64, 16384),
    # Closed-form answers (L = rho / (1 - rho) everywhere): the references double as a check.
    ("furnace-0.5.json", 32, 4096),
    ("furnace-0.8.json", 32, 4096),
    # Participating media (scenes/media/): only the path tracer renders them for now.
    ("media/cornell-fog.json", 64, 8192),
    ("media/hazy-room.json", 64, 16384),
    # Textured and lit by an image sky (scripts/make_courtyard_scene.py): the sun's caustic under
    # the glass ball is found only by paths that leave the glass toward the sun's one texel.
    ("courtyard/courtyard.json", 64, 65536),
]


# What the references hold and what they lack (reference/light_tracer.h has the path classes).
LIMITATION = """\
Light from point, spot and directional lights through mirrors and glass: a path tracer cannot find
it (a sampled direction never hits a point light, nor a parallel light's exact direction), so where
a scene has such a light and a mirror or dielectric (cornell-spheres-point, motion-dof, gltf-room)
`render --method path` adds a light tracer (host/reference/light_tracer.h): light paths from the
delta lights whose first bounce is specular, connected to the camera at every later non-delta
vertex. The two count disjoint paths and their sum is unbiased for every path but one class:
L S ... S E, light from a delta light through a specular surface that the camera sees only through
a specular surface again (the caustic under the glass ball seen in the mirror ball or through the
glass, the light reflected by the mirror ball seen through the glass ball). No estimator that
connects non-delta vertices finds those (bidirectional path tracing included); they lie only in
the pixels whose camera ray first hits a mirror or glass, which the references hold without them.
Its size on cornell-spheres-point, by progressive photon mapping (64 passes, 64 wide): +5.2 % on
the 503 pixels that see a ball, −0.2 % elsewhere, so about 0.5 % of the image mean.
The light tracer's share of the mean: cornell-spheres-point +3.8 %, motion-dof +0.2 %, gltf-room
+0.2 %. Before it (references made before 2026-12-02) these scenes' references lacked it: photon
mapping then read +4.5 % above cornell-spheres-point's.

"""


def run(cmd):
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (result.returncode, " ".join(cmd), result.stdout))
    return result.stdout


def reference_name(scene):
    return "ref-" + os.path.splitext(os.path.basename(scene))[0] + ".exr"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--photoncl", default=os.path.join(ROOT, "build", "photoncl"))
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "data"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--spp-scale", type=float, default=1.0, help="multiply every scene's samples (quick trial: 0.01)")
    ap.add_argument("--only", nargs="*", help="scene file names to (re)make; default all")
    args = ap.parse_args()
    if not shutil.which("oiiotool"):
        sys.exit("oiiotool not found (apt-get install openimageio-tools)")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    table = os.path.join(args.out, "references.md")
    previous = {}
    if os.path.exists(table):  # keep rows of scenes not remade this time
        for line in open(table):
            m = re.match(r"\| `(ref-[^`]+)` \|", line)
            if m:
                previous[m.group(1)] = line.rstrip("\n")
    with tempfile.TemporaryDirectory() as tmp:
        for scene, width, spp in SCENES:
            name = reference_name(scene)
            if args.only and scene not in args.only:
                if name in previous:
                    rows.append(previous[name])
                continue
            spp = max(2, int(spp * args.spp_scale) // 2 * 2)
            halves = []
            start = time.time()
            for seed in (1, 2):
                out = os.path.join(tmp, "half%d.exr" % seed)
                run([args.photoncl, "render", os.path.join(ROOT, "scenes", scene), "--method", "path",
                     "--device", "ref", "--width", str(width), "--passes", str(spp // 2), "--seed", str(seed),
                     "--threads", str(args.threads), "--no-png", "-q", "-o", out])
                halves.append(out)
            seconds = time.time() - start
            compare = run([args.photoncl, "compare", halves[0], halves[1]])
            m = re.search(r"relMSE (\S+)\s+mean ratio (\S+)", compare)
            halves_relmse = float(m.group(1))
            ref_relmse = halves_relmse / 4.0
            target = os.path.join(args.out, name)
            run(["oiiotool", halves[0], halves[1], "--add", "--mulc", "0.5",
                 "--attrib", "photoncl:scene", "scenes/" + scene,
                 "--attrib", "photoncl:method", "path",
                 "--attrib", "photoncl:device", "ref",
                 "--attrib", "photoncl:samples", str(spp),
                 "--attrib", "photoncl:seed", "1+2",
                 "--attrib", "photoncl:reference_relmse", "%.3g" % ref_relmse,
                 "--attrib", "photoncl:seconds", "%.1f" % seconds,
                 "-d", "half", "--compression", "zip", "-o", target])
            stats = run(["oiiotool", target, "--printstats"])
            avg = re.search(r"Stats Avg: (\S+) (\S+) (\S+)", stats)
            mean = sum(float(v) for v in avg.groups()) / 3.0
            row = "| `%s` | %s | %d | %.4g | %.2g | %.1f |" % (name, scene, spp, mean, ref_relmse, seconds)
            print(row, flush=True)
            rows.append(row)
    with open(table + ".tmp", "w") as f:
        f.write("# Path-traced references (made by scripts/make_references.py)\n\n")
        f.write("Each EXR (half float) averages two independent half renders (seeds 1 and 2) of\n"
                "`photoncl render --method path`. *relMSE of the reference* is relMSE(half 1, half 2) / 4: the\n"
                "expected error of the average itself. Accuracy tests hold renders to bounds far above it.\n\n")
        f.write(LIMITATION)
        f.write("Made %s with %s thread(s).\n\n" % (datetime.date.today().isoformat(), args.threads))
        f.write("| file | scene | samples/pixel | mean (RGB average) | relMSE of the reference | seconds |\n")
        f.write("|---|---|---|---|---|---|\n")
        for row in rows:
            f.write(row + "\n")
        if os.path.exists(os.path.join(args.out, "references-256.md")):  # made apart, kept apart
            f.write("\n256×256 references for equal-time comparisons: [references-256.md](references-256.md).\n")
    os.replace(table + ".tmp", table)


if __name__ == "__main__":
    main()
