#!/usr/bin/env python3
"""The media scenes against their references: default renders of several seeds, each timed, averaged
down 4x4 (256² → the 64² references, tests/data/references.md) and compared.

Per scene and contender it prints and writes (CSV):
  seconds      wall time of each render (the machine's load is printed beside it)
  mean ratio   image mean (RGB average) / the reference's, per seed and over the seeds, with the
               standard error of the seeds' mean ratio
  relMSE       of each seed's averaged-down image (eps 0.01, as `photoncl compare`)
  Z-test       per pixel and channel z = (mean over seeds − reference) / (the seeds' standard error):
               the RMS of z (1 when the seeds' scatter explains the difference; the reference's own
               noise and any bias raise it) and the fractions with |z| > 2 and > 3 (4.6 % and
               0.27 % for a normal z); and the same with the reference's own noise added to the
               denominator, modelled per pixel as relMSE_ref × (ref² + 0.01) from the relMSE its
               table gives (tests/data/references.md): the references are noisy at the level of
               these renders' error, so the first z mostly measures the reference's noise

Usage:
  scripts/media_accuracy.py [--seeds 3] [--scene media/cornell-fog.json ...]
      [--contender NAME='--volume-radii photon' ...] [-o media-accuracy.csv]
Without --contender: the defaults. Contenders of one seed run one after the other (interleaved).
Needs oiiotool (its --dumpdata reads the EXRs).
"""
import argparse
import csv
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PIXEL = re.compile(r"\s*Pixel \((\d+), (\d+)\): (.*)")
SCENES = {"media/cornell-fog.json": "ref-cornell-fog.exr", "media/hazy-room.json": "ref-hazy-room.exr"}
REF_RELMSE = {"media/cornell-fog.json": 0.0012, "media/hazy-room.json": 0.0044}  # tests/data/references.md


def read_image(path):
    """(width, height, [r, g, b, ...]) from oiiotool's text dump of the first three channels."""
    out = subprocess.run(["oiiotool", "--dumpdata", "--info", "-v", path], check=True, stdout=subprocess.PIPE,
                         text=True).stdout
    m = re.search(r":\s+(\d+) x\s+(\d+),", out)
    if not m:
        sys.exit("%s: no size in oiiotool's dump" % path)
    w, h = int(m.group(1)), int(m.group(2))
    d = [0.0] * (w * h * 3)
    for line in out.splitlines():
        p = PIXEL.match(line)
        if p:
            i = (int(p.group(2)) * w + int(p.group(1))) * 3
            d[i:i + 3] = [float(v) for v in p.group(3).split()[:3]]
    return w, h, d


def downsample(img, f):
    w, h, d = img
    if w % f or h % f:
        sys.exit("image %dx%d is not a multiple of %d" % (w, h, f))
    W, H = w // f, h // f
    out = [0.0] * (W * H * 3)
    for y in range(h):
        for x in range(w):
            o = ((y // f) * W + x // f) * 3
            i = (y * w + x) * 3
            out[o] += d[i]
            out[o + 1] += d[i + 1]
            out[o + 2] += d[i + 2]
    n = f * f
    return W, H, [v / n for v in out]


def mean(v):
    return sum(v) / len(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--photoncl", default=os.path.join(ROOT, "build", "photoncl"))
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--scene", action="append", help="relative to scenes/ (default: both media scenes)")
    ap.add_argument("--contender", action="append", default=[], help="NAME='render options'")
    ap.add_argument("-o", "--output", default="media-accuracy.csv")
    ap.add_argument("--keep", metavar="DIR", help="keep the renders in DIR (default: a temporary directory)")
    a = ap.parse_args()
    scenes = a.scene or list(SCENES)
    contenders = [c.split("=", 1) for c in a.contender] or [["default", ""]]
    rows = []
    if a.keep:
        os.makedirs(a.keep, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            ref = read_image(os.path.join(ROOT, "tests", "data", SCENES[scene]))
            rw, rh, rd = ref
            ref_mean = mean(rd)
            images = {name: [] for name, _ in contenders}
            for s in range(a.first_seed, a.first_seed + a.seeds):
                for name, opts in contenders:
                    out = os.path.join(a.keep or tmp, "%s-%s-%d.exr" % (os.path.basename(scene)[:-5], name, s))
                    load = os.getloadavg()[0]
                    t = time.time()
                    subprocess.run([a.photoncl, "render", os.path.join(ROOT, "scenes", scene), "-o", out, "--seed",
                                    str(s), "--no-png"] + shlex.split(opts), check=True, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL)
                    secs = time.time() - t
                    img = read_image(out)
                    f = img[0] // rw
                    w, h, d = downsample(img, f)
                    if (w, h) != (rw, rh):
                        sys.exit("%s: %dx%d averages down to %dx%d, the reference is %dx%d" %
                                 (scene, img[0], img[1], w, h, rw, rh))
                    rel = mean([(x - r) ** 2 / (r * r + 0.01) for x, r in zip(d, rd)])
                    ratio = mean(d) / ref_mean
                    images[name].append(d)
                    print("%s %s seed %d: %.1f s (load %.1f), mean ratio %.4f, relMSE %.5f" %
                          (scene, name, s, secs, load, ratio, rel), flush=True)
                    rows.append({"scene": scene, "contender": name, "seed": s, "seconds": "%.2f" % secs,
                                 "load": "%.2f" % load, "mean_ratio": "%.5f" % ratio, "relmse": "%.6f" % rel})
            for name, _ in contenders:
                imgs = images[name]
                n = len(imgs)
                ratios = [mean(d) / ref_mean for d in imgs]
                mr = mean(ratios)
                se = math.sqrt(sum((r - mr) ** 2 for r in ratios) / (n - 1) / n) if n > 1 else float("nan")
                row = {"scene": scene, "contender": name, "seed": "all", "mean_ratio": "%.5f" % mr,
                       "mean_ratio_se": "%.5f" % se}
                text = "%s %s over %d seeds: mean ratio %.4f ± %.4f" % (scene, name, n, mr, se)
                for tag, ref_var in (("", 0.0), ("_with_ref", REF_RELMSE[scene])):
                    z2, big2, big3, count = 0.0, 0, 0, 0
                    for i in range(len(rd) if n > 1 else 0):
                        v = [d[i] for d in imgs]
                        m = mean(v)
                        var = sum((x - m) ** 2 for x in v) / (n - 1) / n + ref_var * (rd[i] * rd[i] + 0.01)
                        if var <= 0.0:
                            continue
                        z = (m - rd[i]) / math.sqrt(var)
                        z2 += z * z
                        big2 += abs(z) > 2
                        big3 += abs(z) > 3
                        count += 1
                    zrms = math.sqrt(z2 / count) if count else float("nan")
                    text += "; Z-test%s RMS z %.2f, |z|>2 %.1f %%, |z|>3 %.2f %%" % (
                        " with the reference's noise" if tag else " (seeds' stderr)", zrms,
                        100.0 * big2 / max(count, 1), 100.0 * big3 / max(count, 1))
                    row.update({"z_rms" + tag: "%.3f" % zrms, "z_over2" + tag: "%.4f" % (big2 / max(count, 1)),
                                "z_over3" + tag: "%.4f" % (big3 / max(count, 1))})
                print(text + " (%d pixel channels)" % count, flush=True)
                rows.append(row)
    keys = ["scene", "contender", "seed", "seconds", "load", "mean_ratio", "relmse", "mean_ratio_se", "z_rms",
            "z_over2", "z_over3", "z_rms_with_ref", "z_over2_with_ref", "z_over3_with_ref"]
    with open(a.output, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
