#!/usr/bin/env python3
"""Turns Google Benchmark JSON files from scripts/bench.sh into one Markdown table of ratios.

Each row pairs a photoncl benchmark with its peer measured in the same run, with the same
suffix (scene, size, k): traversal kernel vs Embree rtcIntersect1 and vs the host BVH (rays per
CPU second), photon pass on the device vs the CPU twin (paths per wall second, both on all
cores), device radix sort vs __gnu_parallel::sort, kd-tree build device vs twin, kNN on the
device kd-tree and hash grid vs nanoflann on all cores, the radiance estimate vs its twin,
the precomputed irradiance lookup vs the full estimate.
"""
import json
import re
import sys

# (photoncl prefix, peer prefix(es), counter, what is compared); with several peer prefixes the
# fastest peer is the one compared against.
PAIRS = [
    ("KernelClosest/", "EmbreeClosest/", "rays_per_s", "traversal kernel vs Embree rtcIntersect1, rays/CPU-s"),
    ("KernelClosest/", "HostClosest/", "rays_per_s", "traversal kernel vs host BVH traversal, rays/CPU-s"),
    ("Device/", "Twin/", "paths_per_wall_s", "photon pass, device vs CPU twin, paths/s"),
    ("Sort/Device/", "Sort/StdPar/", "keys_per_s", "radix sort vs __gnu_parallel::sort, keys/s"),
    ("KdTree/Device/", "KdTree/Twin/", "photons_per_s", "kd-tree build, device vs twin, photons/s"),
    ("KdTree/", ("Nanoflann/", "NanoflannRmax/"), "queries_per_s",
     "kNN, device kd-tree vs the faster of nanoflann plain / r_max-bounded, queries/s"),
    ("HashGrid/", ("Nanoflann/", "NanoflannRmax/"), "queries_per_s",
     "kNN, device hash grid vs the faster of nanoflann plain / r_max-bounded, queries/s"),
    ("EstimateKdTree/", "EstimateTwin/", "queries_per_cpu_s", "radiance estimate, device kd-tree vs CPU twin, queries/CPU-s"),
    ("EstimateHashGrid/", "EstimateTwin/", "queries_per_cpu_s", "radiance estimate, device hash grid vs CPU twin, queries/CPU-s"),
    ("IrradianceLookup/", "FullEstimate/", "queries_per_s", "precomputed irradiance lookup vs the full estimate, queries/s"),
    ("IrradianceLookup/", "NanoflannNearest/", "queries_per_s",
     "precomputed irradiance lookup (queries as given) vs nanoflann k = 1 on the same points, all cores, queries/s"),
    ("IrradianceLookupOrdered/", "NanoflannNearest/", "queries_per_s",
     "precomputed irradiance lookup in query order, sort included (as render) vs nanoflann k = 1, queries/s"),
]


def name_of(bench):
    # Drop Google Benchmark's decorations: /iterations:3, /manual_time, /process_time, /min_time:2.
    return re.sub(r"/(iterations:\d+|manual_time|process_time|real_time|min_time:[\d.]+)", "", bench["name"])


def main():
    rows, context = {}, {}
    for path in sys.argv[1:]:
        with open(path) as f:
            data = json.load(f)
        context = data.get("context", context)
        for b in data["benchmarks"]:
            if b.get("run_type", "iteration") == "iteration":
                rows[name_of(b)] = b
    print(f"Benchmarks on {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs, "
          f"{context.get('date', '')}\n")
    print("| comparison | case | photoncl | peer | ratio |")
    print("|---|---|---:|---:|---:|")
    for ours, peers, counter, what in PAIRS:
        peers = (peers,) if isinstance(peers, str) else peers
        for name in sorted(rows):
            if not name.startswith(ours) or any(name.startswith(p) for p in peers):
                continue
            suffix = name[len(ours):]
            mine = rows[name]
            candidates = [rows[p + suffix] for p in peers if p + suffix in rows and rows[p + suffix].get(counter)]
            if counter not in mine or not candidates:
                continue
            other = max(candidates, key=lambda b: b[counter])
            print(f"| {what} | {suffix} | {mine[counter]:.3g} | {other[counter]:.3g} | "
                  f"{mine[counter] / other[counter]:.2f}x |")
    # The photon pass against its bound: the traversal kernel's rays per CPU-second over the mean
    # rays a photon path traces (both in this run): 1.0 would be a pass that only traverses.
    for name in sorted(rows):
        if not name.startswith("Device/"):
            continue
        scene = name[len("Device/"):]
        mine, kernel = rows[name], rows.get("KernelClosest/" + scene)
        if not kernel or not mine.get("rays_per_path") or not mine.get("paths_per_s"):
            continue
        bound = kernel["rays_per_s"] / mine["rays_per_path"]
        print(f"| photon pass vs the traversal bound (kernel rays/CPU-s ÷ {mine['rays_per_path']:.2f} rays per path), "
              f"paths/CPU-s | {scene} | {mine['paths_per_s']:.3g} | {bound:.3g} | {mine['paths_per_s'] / bound:.2f}x |")
    # The hash grid's build against the kd-tree's of the same 1M photons (knn_bench Build/*: wall
    # milliseconds per build): how much cheaper the grid is to make.
    for name in sorted(rows):
        if not name.startswith("Build/grid/"):
            continue
        case = name[len("Build/grid/"):]
        grid, tree = rows[name], rows.get("Build/kdtree/" + case)
        if tree and grid.get("real_time") and tree.get("real_time"):
            print(f"| hash-grid build vs kd-tree build of the same 1M photons, ms (lower is faster) | {case} | "
                  f"{grid['real_time']:.3g} | {tree['real_time']:.3g} | {tree['real_time'] / grid['real_time']:.2f}x |")
    build = rows.get("Build/mesh1M")
    if build:
        print(f"\nBVH of the 1M-triangle mesh: build {build['build_s']:.2f} s, SAH cost {build['sah']:.1f}, "
              f"{build['bytes_per_tri']:.1f} bytes/triangle (nodes + packets), depth {build['depth']:.0f}")


if __name__ == "__main__":
    main()
