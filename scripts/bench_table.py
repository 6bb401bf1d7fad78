#!/usr/bin/env python3
"""Turns Google Benchmark JSON files from scripts/bench.sh into one Markdown table of ratios.

Pairs, by scene: traversal kernel vs Embree rtcIntersect1 and vs the host traversal (rays per
CPU second of the process), photon pass on the device vs the CPU twin (paths per wall second,
both on all cores), and the BVH build figures of the 1M-triangle mesh.
"""
import json
import sys


def load(paths):
    rows = {}
    context = {}
    for p in paths:
        with open(p) as f:
            data = json.load(f)
        context = data.get("context", context)
        for b in data["benchmarks"]:
            rows[b["name"].split("/process_time")[0].split("/iterations")[0].split("/min_time")[0]] = b
    return rows, context


def main():
    rows, context = load(sys.argv[1:])
    print(f"Benchmarks on {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs, "
          f"{context.get('date', '')}\n")
    print("| comparison | scene | photoncl | peer | ratio |")
    print("|---|---|---:|---:|---:|")
    scenes = sorted({n.split("/", 1)[1] for n in rows if "/" in n})
    for s in scenes:
        k = rows.get(f"KernelClosest/{s}")
        e = rows.get(f"EmbreeClosest/{s}")
        h = rows.get(f"HostClosest/{s}")
        if k and e:
            print(f"| traversal kernel (PoCL) vs Embree rtcIntersect1, rays/CPU-s | {s} | "
                  f"{k['rays_per_s']:.3g} | {e['rays_per_s']:.3g} | {k['rays_per_s'] / e['rays_per_s']:.2f}x |")
        if k and h:
            print(f"| traversal kernel (PoCL) vs host BVH traversal, rays/CPU-s | {s} | "
                  f"{k['rays_per_s']:.3g} | {h['rays_per_s']:.3g} | {k['rays_per_s'] / h['rays_per_s']:.2f}x |")
        d = rows.get(f"Device/{s}")
        t = rows.get(f"Twin/{s}")
        if d and t:
            print(f"| photon pass on the device (PoCL) vs CPU twin, paths/wall-s | {s} | "
                  f"{d['paths_per_wall_s']:.3g} | {t['paths_per_wall_s']:.3g} | "
                  f"{d['paths_per_wall_s'] / t['paths_per_wall_s']:.2f}x |")
    b = rows.get("Build/mesh1M")
    if b:
        print(f"\nBVH of the 1M-triangle mesh: build {b['build_s']:.2f} s, SAH cost {b['sah']:.1f}, "
              f"{b['bytes_per_tri']:.1f} bytes/triangle (nodes + packets), depth {b['depth']:.0f}")


if __name__ == "__main__":
    main()
