#!/usr/bin/env python3
"""Charts `photoncl sweep` CSVs: speed against accuracy.

    scripts/chart.py sweep-*.csv -o DIR [--budgets 10,30,60]

Per scene, DIR/<scene>-error.png: relMSE and RMSE against render seconds, log-log, one curve per
method (+ variant); per-seed rows at one budget are averaged. Where the CSV has bias/variance rows
(seed "all", from --seeds >= 2), DIR/<scene>-bias-variance.png: bias^2 and variance against seconds.
DIR/winners.md: per scene and budget, the curves with the lowest and second-lowest relMSE (and RMSE)
at that many seconds, read off each curve by log-log interpolation between its points (a curve
whose first point took longer, or that ended more than 15 % short of the budget, has none).
Needs matplotlib (Debian: python3-matplotlib); Agg backend, no display.
"""
import argparse
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {  # one colour per method, line style per variant
    "path": "black",
    "direct": "tab:green",
    "fg-estimate": "tab:red",
    "fg-precomputed": "tab:blue",
    "progressive": "tab:orange",
}


def colour(curve):
    for prefix in sorted(STYLE, key=len, reverse=True):
        if curve.startswith(prefix):
            return STYLE[prefix]
    return "tab:gray"


def load(paths):
    """scene -> curve -> {'points': [(seconds, relmse, rmse, passes)], 'split': [(s, bias2, var)], 'device': str}"""
    scenes = defaultdict(lambda: defaultdict(lambda: {"per": defaultdict(list), "split": [], "device": ""}))
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                c = scenes[row["scene"]][row["curve"]]
                c["device"] = row["device"]
                s = float(row["seconds"])
                if row["seed"] == "all":
                    c["split"].append((s, float(row["bias2"]), float(row["variance"])))
                else:
                    c["per"][int(row["passes"])].append((s, float(row["relmse"]), float(row["rmse"])))
    out = {}
    for scene, curves in scenes.items():
        out[scene] = {}
        for name, c in curves.items():
            pts = []
            for passes, vals in sorted(c["per"].items()):
                n = len(vals)
                pts.append((sum(v[0] for v in vals) / n, sum(v[1] for v in vals) / n,
                            sum(v[2] for v in vals) / n, passes))
            out[scene][name] = {"points": pts, "split": sorted(c["split"]), "device": c["device"]}
    return out


def positive(v):
    return v if v > 0 and math.isfinite(v) else float("nan")


def chart_errors(scene, curves, path):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4))
    variants = defaultdict(int)  # per colour: variants drawn so far (each its own dashes and marker)
    for name in sorted(curves):
        pts = curves[name]["points"]
        if not pts:
            continue
        if name in STYLE:
            style, marker = "-", "o"
        else:
            i = variants[colour(name)]
            variants[colour(name)] += 1
            style, marker = ("--", ":", "-.")[i % 3], ("s", "^", "v", "D")[i % 4]
        for ax, idx in ((axes[0], 1), (axes[1], 2)):
            ax.plot([p[0] for p in pts], [positive(p[idx]) for p in pts], marker=marker, markersize=3,
                    color=colour(name), linestyle=style, label=name)
    for ax, what in ((axes[0], "relMSE"), (axes[1], "RMSE")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("render seconds")
        ax.set_ylabel(what + " against the reference")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"{scene}: error against time")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def chart_split(scene, curves, path):
    fig, ax = plt.subplots(figsize=(6.5, 4.4))
    drawn = False
    for name in sorted(curves):
        sp = curves[name]["split"]
        if not sp:
            continue
        drawn = True
        ax.plot([p[0] for p in sp], [positive(p[1]) for p in sp], marker="o", markersize=3, color=colour(name),
                linestyle="-", label=name + " bias²")
        ax.plot([p[0] for p in sp], [positive(p[2]) for p in sp], marker="x", markersize=3, color=colour(name),
                linestyle=":", label=name + " variance")
    if not drawn:
        plt.close(fig)
        return False
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render seconds")
    ax.set_ylabel("MSE part")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    ax.set_title(f"{scene}: bias² (solid) and variance (dotted) over seeds")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return True


def at_budget(pts, budget, idx):
    """The curve's error at `budget` seconds: log-log interpolation between the points around it;
    the last point if the curve ended within 15 % short of it; None if it never got that far or
    its first point took longer."""
    if not pts or pts[0][0] > budget:
        return None
    for p, q in zip(pts, pts[1:]):
        if p[0] <= budget <= q[0]:
            if p[idx] <= 0 or q[idx] <= 0 or q[0] <= p[0]:
                return p[idx]
            t = (math.log(budget) - math.log(p[0])) / (math.log(q[0]) - math.log(p[0]))
            return math.exp(math.log(p[idx]) + t * (math.log(q[idx]) - math.log(p[idx])))
    return pts[-1][idx] if pts[-1][0] >= 0.85 * budget else None


def winners(data, budgets):
    lines = ["| scene | budget | best by relMSE | runner-up | its relMSE / best | best by RMSE | runner-up | "
             "its RMSE / best |", "|---|---|---|---|---|---|---|---|"]
    for scene in sorted(data):
        for b in budgets:
            cells = []
            for idx in (1, 2):
                ranked = sorted((v, n) for n, c in data[scene].items()
                                for v in [at_budget(c["points"], b, idx)] if v is not None)
                if not ranked:
                    cells = None
                    break
                v1, n1 = ranked[0]
                if len(ranked) > 1:
                    v2, n2 = ranked[1]
                    cells += [f"{n1} ({v1:.3g})", f"{n2} ({v2:.3g})", f"{v2 / v1:.2f}x" if v1 > 0 else "-"]
                else:
                    cells += [f"{n1} ({v1:.3g})", "-", "-"]
            if cells:
                lines.append(f"| {scene} | {b:g} s | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+")
    ap.add_argument("-o", "--output-dir", required=True)
    ap.add_argument("--budgets", default="10,30,60", help="seconds for winners.md")
    a = ap.parse_args()
    if not os.path.isdir(a.output_dir):
        sys.exit(f"chart.py: output folder {a.output_dir} does not exist")
    data = load(a.csv)
    if not data:
        sys.exit("chart.py: no rows in " + " ".join(a.csv))
    written = []
    for scene, curves in sorted(data.items()):
        p = os.path.join(a.output_dir, f"{scene}-error.png")
        chart_errors(scene, curves, p)
        written.append(p)
        p = os.path.join(a.output_dir, f"{scene}-bias-variance.png")
        if chart_split(scene, curves, p):
            written.append(p)
    table = winners(data, [float(b) for b in a.budgets.split(",") if b])
    p = os.path.join(a.output_dir, "winners.md")
    with open(p + ".tmp", "w") as f:
        f.write(table)
    os.replace(p + ".tmp", p)
    written.append(p)
    print("\n".join(written))


if __name__ == "__main__":
    main()
