#!/usr/bin/env python3
"""Equal-time comparison: `photoncl render --time T` with several contenders (methods or
settings) against one converged reference, interleaved, at the size users render.

Every (budget, contender) pair is one render of T seconds of wall time; the contenders of a
budget run one after the other in an order that rotates with the repeat, so a change in the
machine's load falls on all of them alike. Each image is compared with the reference by
`photoncl compare` (RMSE, relMSE with eps = 0.01, mean ratio). With --reference-halves A B the
reference's own MSE (MSE(A, B) / 4 for the average of two independent halves) is measured and
written beside the rows: errors near it are the reference's noise, not the contender's. With
--skip-specular-pixels each image is also compared without the pixels that see mirrors or glass
first (`photoncl compare --skip-specular-pixels`: there references made by path and light tracing
lack the L S...S E light of delta lights), in the *_masked columns.

Seeds: the contenders render with --seed 1001 (+ repeat) by default. The references were path
traced with seeds 1-12 (tests/data/references-256.md), and the path tracer's sample i of seed s is
the same in every render, so a path-traced contender with one of those seeds shares its samples
with the reference and reads far too good (cornell-glossy, 512 spp: RMSE 0.0143 with seed 1 against
0.0205 with seed 1001). Seeds 1-12 are refused.

Usage:
  scripts/equal_time.py SCENE --reference REF.exr [--width 256] [--budgets 10 30]
      [--contender NAME='--method path' ...] [--repeats 1] [--seed 1001] [-o equal-time.csv]
Without --contender: path, fg (defaults) and fg with 4x4 eye samples of 4 gather rays.
"""
import argparse
import csv
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

DEFAULT_CONTENDERS = [
    ("path", "--method path"),
    ("fg", "--method fg"),
    ("fg-4x4x4", "--method fg --strata 4 --gather-rays 4"),
]


def compare(photoncl, image, reference, extra=()):
    out = subprocess.run([photoncl, "compare", image, reference] + list(extra), stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    m = re.search(r"RMSE (\S+)\s+relMSE (\S+)\s+mean ratio (\S+)\s+max diff (\S+)", out.stdout)
    if out.returncode not in (0, 1) or not m:
        sys.exit("compare failed (%d): %s" % (out.returncode, out.stdout))
    return [float(x) for x in m.groups()]


def samples_of(log):
    m = re.search(r"(\d+) passes × (\d+) samples/pixel", log)
    if m:
        return int(m.group(1)), int(m.group(1)) * int(m.group(2))
    m = re.search(r"(\d+) samples/pixel", log)
    return (int(m.group(1)), int(m.group(1))) if m else (0, 0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--reference", required=True)
    ap.add_argument("--reference-halves", nargs=2, metavar=("A", "B"))
    ap.add_argument("--photoncl", default=os.path.join(ROOT, "build", "photoncl"))
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--budgets", type=float, nargs="+", default=[10.0, 30.0])
    ap.add_argument("--contender", action="append", default=[], help="NAME='render options'")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1001,
                    help="first seed (+ repeat); not 1-12, the references' own seeds")
    ap.add_argument("--skip-specular-pixels", action="store_true",
                    help="also compare without the pixels that see mirrors or glass first (*_masked columns)")
    ap.add_argument("-o", "--output", default="equal-time.csv")
    args = ap.parse_args()

    if any(1 <= args.seed + rep <= 12 for rep in range(args.repeats)):
        sys.exit("--seed %d: seeds 1-12 made the references (tests/data/references-256.md); a path-traced "
                 "contender would share their samples" % args.seed)
    contenders = DEFAULT_CONTENDERS
    if args.contender:
        contenders = []
        for c in args.contender:
            name, sep, opts = c.partition("=")
            if not sep or not name:
                sys.exit("--contender %r: expected NAME='render options'" % c)
            contenders.append((name, opts))
    refMse = ""
    if args.reference_halves:
        rmse = compare(args.photoncl, args.reference_halves[0], args.reference_halves[1])[0]
        refMse = "%.6g" % (rmse * rmse / 4.0)
        print("reference's own MSE (halves): %s" % refMse, file=sys.stderr)

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for rep in range(args.repeats):
            for budget in args.budgets:
                k = int(rep + budget) % len(contenders)
                for name, opts in contenders[k:] + contenders[:k]:
                    image = os.path.join(tmp, "%s.exr" % name)
                    cmd = [args.photoncl, "render", args.scene, "--width", str(args.width), "--time", str(budget),
                           "--seed", str(args.seed + rep), "--no-png", "-o", image] + shlex.split(opts)
                    t0 = time.monotonic()
                    run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
                    wall = time.monotonic() - t0
                    if run.returncode != 0:
                        sys.exit("render failed (%d): %s\n%s" % (run.returncode, " ".join(cmd), run.stdout[-2000:]))
                    passes, spp = samples_of(run.stdout)
                    # What `render` ran: the method auto's pilot chose, with the emitter samples' log line.
                    picked = re.search(r"method auto: (.+?) \(pilot", run.stdout)
                    emitter = re.search(r"emitter samples: (\S+) a pass in (\d+) pixels", run.stdout)
                    ran = (picked.group(1) if picked else "") + (
                        " + emitter %s in %s px" % emitter.groups() if emitter else "")
                    rmse, relmse, ratio, maxdiff = compare(args.photoncl, image, args.reference)
                    row = {"scene": os.path.basename(args.scene), "contender": name, "options": opts,
                           "budget_s": budget, "wall_s": round(wall, 2), "passes": passes, "samples_per_pixel": spp,
                           "rmse": rmse, "relmse": relmse, "mean_ratio": ratio, "max_diff": maxdiff,
                           "reference_mse": refMse, "repeat": rep, "ran": ran.strip()}
                    masked = ""
                    if args.skip_specular_pixels:
                        m = compare(args.photoncl, image, args.reference, ["--skip-specular-pixels", args.scene])
                        row.update({"rmse_masked": m[0], "relmse_masked": m[1], "mean_ratio_masked": m[2]})
                        masked = "  masked: RMSE %.5f  relMSE %.6f  mean %.4f" % tuple(m[:3])
                    rows.append(row)
                    print("%-14s %5.0f s  wall %6.1f s  spp %5d  RMSE %.5f  relMSE %.6f  mean %.4f%s%s" %
                          (name, budget, wall, spp, rmse, relmse, ratio, masked, "  [%s]" % ran if ran else ""),
                          file=sys.stderr)
    tmpOut = args.output + ".tmp"
    with open(tmpOut, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    os.replace(tmpOut, args.output)


if __name__ == "__main__":
    main()
