#!/usr/bin/env python3
"""Seconds per pass of `photoncl render` for two binaries, run interleaved (issue 14, target 5).

    scripts/pass_speed.py OLD_BINARY NEW_BINARY [--runs 3] [--passes 2] [--scenes a.json,b.gltf]
                                                [--methods fg,direct,progressive] [--out table.md]

Every scene and method is rendered with `render`'s defaults (the shipped camera size, 256x256
for the Cornell boxes; --fg-options adds options to fg, so two versions whose fg defaults differ
can be timed on the same work; --new-options adds options to one method of the new binary only)
and the same seed by both binaries, old then new, `--runs` times, so load
on the machine falls on both alike. Per run it reads the render's "time by stage" table and
divides by the passes. Prints (and with --out writes) a Markdown table: the median seconds per
pass of each binary, their ratio, the median CPU seconds per pass (user + system of the render
process, all its threads: steadier than wall time when other jobs share the cores) and their
ratio, and the median seconds per pass of each stage.
Exit status 0, or 2 on bad arguments or a render that fails (its log is printed).
"""
import argparse
import os
import resource
import re
import shlex
import statistics
import subprocess
import sys
import tempfile

STAGES = ["photon pass", "maps", "camera", "eye paths", "direct light", "caustics", "indirect", "accumulate",
          "total"]
ROW = re.compile(r"^\s+(photon pass|maps|camera|eye paths|direct light|caustics|indirect|accumulate|total)\s+"
                 r"([0-9.]+) s")


def render(binary, scene, method, passes, out, extra=()):
    cmd = [binary, "render", scene, "--method", method, "--passes", str(passes), "--seed", "1", "--no-png", "-o", out]
    cmd += list(extra)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if p.returncode != 0:
        sys.stderr.write(f"pass_speed: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}\n")
        sys.exit(2)
    times = {}
    for line in p.stderr.splitlines():
        m = ROW.match(line)
        if m:
            times[m.group(1)] = float(m.group(2)) / passes
    times["cpu"] = cpu / passes
    missing = [s for s in STAGES if s not in times]
    if missing:
        sys.stderr.write(f"pass_speed: no time for {missing} in the log of {' '.join(cmd)}:\n{p.stderr}\n")
        sys.exit(2)
    return times


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    a = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    a.add_argument("old")
    a.add_argument("new")
    a.add_argument("--runs", type=int, default=3)
    a.add_argument("--passes", type=int, default=2)
    a.add_argument("--scenes", default="cornell-box.json,cornell-spheres.json,gltf-room.gltf")
    a.add_argument("--methods", default="fg,direct,progressive")
    a.add_argument("--out")
    a.add_argument("--fg-options", default="",
                   help="extra render options for fg (e.g. the same eye samples and gather rays for both binaries "
                        "when their defaults differ)")
    a.add_argument("--new-options", action="append", default=[], metavar="METHOD:OPTIONS",
                   help="extra render options for one method of the new binary only, after --fg-options "
                        "(repeatable; options the old binary does not know, or defaults that changed, e.g. "
                        "'fg:--emitter-strata 0' or 'progressive:--strata 1')")
    o = a.parse_args()
    for b in (o.old, o.new):
        if not os.access(b, os.X_OK):
            sys.stderr.write(f"pass_speed: {b} is not an executable\n")
            return 2
    if o.runs < 1 or o.passes < 1:
        sys.stderr.write("pass_speed: --runs and --passes must be at least 1\n")
        return 2
    newOptions = {}
    for spec in o.new_options:
        method, sep, options = spec.partition(":")
        if not sep or method not in ("fg", "direct", "progressive"):
            sys.stderr.write(f"pass_speed: --new-options {spec!r}: expected METHOD:OPTIONS with METHOD fg, direct "
                             "or progressive\n")
            return 2
        newOptions.setdefault(method, []).extend(shlex.split(options))
    scenes = [os.path.join(root, "scenes", s) for s in o.scenes.split(",")]
    methods = o.methods.split(",")
    lines = ["| scene | method | old s/pass | new s/pass | old / new | old CPU s/pass | new CPU s/pass | old / new CPU | "
             "stage (old → new, s/pass) |",
             "|---|---|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "pass.exr")
        for scene in scenes:
            for method in methods:
                runs = {"old": [], "new": []}
                for r in range(o.runs):
                    for which, binary in (("old", o.old), ("new", o.new)):
                        extra = shlex.split(o.fg_options) if method == "fg" else []
                        if which == "new":
                            extra += newOptions.get(method, [])
                        runs[which].append(render(binary, scene, method, o.passes, out, extra))
                        sys.stderr.write(f"pass_speed: {os.path.basename(scene)} {method} run {r + 1} {which}: "
                                         f"{runs[which][-1]['total']:.3f} s/pass, "
                                         f"{runs[which][-1]['cpu']:.3f} CPU s/pass\n")
                med = {w: {s: statistics.median(t[s] for t in runs[w]) for s in STAGES + ["cpu"]} for w in runs}
                stages = ", ".join(f"{s} {med['old'][s]:.3f} → {med['new'][s]:.3f}" for s in STAGES[:-1]
                                   if med["old"][s] >= 0.0005 or med["new"][s] >= 0.0005)
                ratio = med["old"]["total"] / med["new"]["total"] if med["new"]["total"] > 0 else float("inf")
                cpuRatio = med["old"]["cpu"] / med["new"]["cpu"] if med["new"]["cpu"] > 0 else float("inf")
                lines.append(f"| {os.path.basename(scene)} | {method} | {med['old']['total']:.3f} | "
                             f"{med['new']['total']:.3f} | {ratio:.2f} | {med['old']['cpu']:.3f} | "
                             f"{med['new']['cpu']:.3f} | {cpuRatio:.2f} | {stages} |")
    text = "\n".join(lines) + f"\n\n{o.runs} runs each, interleaved, {o.passes} passes, seed 1, median per pass.\n"
    print(text)
    if o.out:
        with open(o.out + ".tmp", "w") as f:
            f.write(text)
        os.replace(o.out + ".tmp", o.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
