#!/usr/bin/env python3
"""Independent references: every shipped scene that Mitsuba 3 expresses exactly
(scripts/mitsuba_scene.py) rendered by Mitsuba's path tracer at the size of the photoncl
reference (tests/data/ref-<scene>.exr) to tests/data/mitsuba-<scene>.exr, with the reference's
own noise beside the image, and a table in tests/data/references-mitsuba.md.

Each scene is rendered as CHUNKS independent renders (seeds 1..CHUNKS) of spp/CHUNKS samples.
The EXR (half float) holds their mean as R, G, B; the layer `sem` (channels sem.R/G/B) holds the
per-pixel, per-channel standard error of that mean (sample standard deviation over the chunks /
sqrt(CHUNKS)); the layer `semsum` holds the standard error of R+G+B (the value photoncl's
per-pixel Z-test compares) in all three channels. With 16 chunks the standard error is itself
estimated with 15 degrees of freedom. Half precision rounds at 2^-11 relative (5e-4), far below
the per-pixel standard errors (about 1e-2 relative) and unbiased in the image mean.

Mitsuba is a tool for making these files, not a dependency of photoncl: tests read the EXRs.
Needs `pip install mitsuba` (3.x; the scalar_rgb variant). Rendering uses one thread.

Usage: python3 scripts/make_mitsuba_references.py [--scale S] [--only NAME] [--out DIR]
"""
import argparse
import datetime
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from mitsuba_scene import Unexpressible, mitsuba_scene_dict  # noqa: E402

CHUNKS = 16
# Samples per pixel (all chunks together), chosen for a per-pixel standard error of about 1 %
# on the walls and a total under ~25 minutes on one core; the caustic scene is the noisiest.
SCENES = [
    ("cornell-box.json", 16384),
    ("cornell-spheres.json", 16384),
    ("cornell-spheres-point.json", 16384),
    ("furnace-0.5.json", 8192),
    ("furnace-0.8.json", 8192),
    ("cornell-glossy.json", 0),
    ("motion-dof.json", 0),
    ("gltf-room.gltf", 0),
    # Participating media (scenes/media/; integrator volpath). Fewer samples: a media path costs more.
    ("media/cornell-fog.json", 4096),
    ("media/hazy-room.json", 0),
    # No 64-px photoncl reference: its 256² one (tests/data/ref256-sky-spheres.exr) is held to this.
    ("sky-spheres.json", 16384),
]


def read_size(path, mi):
    b = mi.Bitmap(path)
    return b.width(), b.height()


def render(mi, dr, scene_path, width, height, spp):
    scene = mi.load_dict(mitsuba_scene_dict(scene_path, width, height))
    per_chunk = spp // CHUNKS
    n = width * height * 3
    s1 = [0.0] * n  # per value: sum over chunks, and sum of squares
    s2 = [0.0] * n
    sum1 = [0.0] * (width * height)  # R+G+B per pixel
    sum2 = [0.0] * (width * height)
    dr.set_thread_count(1)
    start = time.time()
    for chunk in range(CHUNKS):
        img = list(mi.render(scene, spp=per_chunk, seed=chunk + 1).array)
        for i, v in enumerate(img):
            s1[i] += v
            s2[i] += v * v
        for p in range(width * height):
            v = img[3 * p] + img[3 * p + 1] + img[3 * p + 2]
            sum1[p] += v
            sum2[p] += v * v
    seconds = time.time() - start
    dr.set_thread_count(2)  # Mitsuba's EXR I/O deadlocks on a one-thread pool

    def sem(a, b):
        var = max(0.0, (b - a * a / CHUNKS) / (CHUNKS - 1))  # unbiased sample variance over chunks
        return math.sqrt(var / CHUNKS)

    mean = [a / CHUNKS for a in s1]
    sem_rgb = [sem(a, b) for a, b in zip(s1, s2)]
    sem_sum = [sem(a, b) for a, b in zip(sum1, sum2)]
    return mean, sem_rgb, sem_sum, seconds


def write_exr(mi, dr, path, width, height, mean, sem_rgb, sem_sum):
    values = []
    for p in range(width * height):
        values += mean[3 * p:3 * p + 3] + sem_rgb[3 * p:3 * p + 3] + [sem_sum[p]] * 3
    # Half float straight from a half tensor (Bitmap.convert loses the channel names).
    tensor = dr.scalar.TensorXf16(values, shape=(height, width, 9))
    bmp = mi.Bitmap(tensor, mi.Bitmap.PixelFormat.MultiChannel,
                    ["R", "G", "B", "sem.R", "sem.G", "sem.B", "semsum.R", "semsum.G", "semsum.B"])
    tmp = path + ".tmp.exr"
    bmp.write(tmp)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scale", type=float, default=1.0, help="multiply every spp (a quick trial: 0.01)")
    ap.add_argument("--only", help="one scene file name")
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "data"), help="output folder")
    ap.add_argument("--no-table", action="store_true", help="do not rewrite references-mitsuba.md")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    rows, refused = [], []
    for name, spp in SCENES:
        if args.only and name != args.only:
            continue
        scene_path = os.path.join(ROOT, "scenes", name)
        stem = os.path.splitext(os.path.basename(name))[0]
        try:
            mitsuba_scene_dict(scene_path)
        except Unexpressible as e:
            refused.append((name, e.field, e.why))
            print(f"refused: {e}", flush=True)
            continue
        spp = max(CHUNKS, int(spp * args.scale) // CHUNKS * CHUNKS)
        small = os.path.join(ROOT, "tests", "data", f"ref-{stem}.exr")
        if os.path.exists(small):
            width, height = read_size(small, mi)
        else:  # 64 wide at the scene camera's aspect
            import json
            res = json.load(open(scene_path))["camera"]["resolution"]
            width, height = 64, round(64 * res[1] / res[0])
        mean, sem_rgb, sem_sum, seconds = render(mi, dr, scene_path, width, height, spp)
        out = os.path.join(args.out, f"mitsuba-{stem}.exr")
        write_exr(mi, dr, out, width, height, mean, sem_rgb, sem_sum)
        img_mean = sum(mean) / len(mean)
        # Standard error of the image mean: the pixels' errors are independent.
        mean_sem = math.sqrt(sum(s * s for s in sem_rgb)) / len(sem_rgb)
        rel = [s / max(m, 1e-3) for s, m in zip(sem_sum, (mean[3 * p] + mean[3 * p + 1] + mean[3 * p + 2]
                                                         for p in range(width * height)))]
        rel.sort()
        rows.append((name, stem, width, height, spp, img_mean, mean_sem, rel[len(rel) // 2], rel[int(0.99 * len(rel))],
                     seconds))
        print(f"{out}: {width}x{height}, {spp} spp, mean {img_mean:.5g} +- {mean_sem:.2g}, "
              f"median per-pixel relative SEM {rel[len(rel) // 2]:.3g}, {seconds:.1f} s", flush=True)

    if args.no_table or args.only:
        return 0
    lines = [
        "# Independent references: Mitsuba 3 (made by scripts/make_mitsuba_references.py)",
        "",
        f"Mitsuba {mi.__version__} (variant scalar_rgb), Dr.Jit {dr.__version__}; made "
        f"{datetime.date.today().isoformat()} on one thread. Integrator `path` (`volpath` for scenes with media), "
        "max_depth 65 (photoncl's 64 bounces after the camera ray), Russian roulette from depth 5 (Mitsuba's default; unbiased), `independent` "
        "sampler, box pixel filter, scenes converted by scripts/mitsuba_scene.py.",
        "",
        f"Each EXR (half float) is the mean of {CHUNKS} independent renders (seeds 1..{CHUNKS}); layer `sem` holds "
        "the per-pixel, per-channel standard error of that mean, layer `semsum` the standard error of R+G+B.",
        "*mean ± SE* is the RGB average over the image with its standard error; *pixel rel. SE* is the standard "
        "error of R+G+B relative to R+G+B (median and 99th percentile over the pixels).",
        "",
        "| file | scene | size | samples/pixel | mean ± SE | pixel rel. SE median / p99 | seconds |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, stem, w, h, spp, m, se, med, p99, sec in rows:
        lines.append(f"| `mitsuba-{stem}.exr` | {name} | {w}×{h} | {spp} | {m:.5f} ± {se:.1g} | {med:.3g} / {p99:.3g} "
                     f"| {sec:.0f} |")
    lines += ["", "Refused (not expressible exactly in Mitsuba; no file):", ""]
    for name, field, why in refused:
        lines.append(f"- {name}: `{field}`: {why}")
    lines.append("")
    with open(os.path.join(args.out, "references-mitsuba.md"), "w") as f:
        f.write("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
