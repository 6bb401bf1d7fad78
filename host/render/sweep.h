// Speed against accuracy (README.md, "Speed against accuracy"): one scene rendered at increasing budgets with every
// method and a small grid of settings, each point's error against a reference image and the
// seconds it took, as CSV rows for scripts/chart.py.
//
// A curve is one method with one setting variant. Its budgets double (passes for the photon
// methods, samples per pixel for the path tracer) until a point takes at least maxSeconds.
// fg, direct and path render the increments only: the passes [n, 2n) come from one render with
// a seed of their own (the passes of a photon render are independent and averaged, so the
// merged film is a 2n-pass render) and the seconds add up. Progressive renders each budget from
// scratch (its radius shrinks with the pass index). Before its first point each curve renders
// one untimed pass, so kernel builds are not charged to the first point.
//
// Seeds ≥ 2: every curve repeats with independent seeds at the same budgets (set by the first
// seed), and one more row per budget ("all") splits the error: with m the mean image over the
// S seeds, r the reference and v the per-value variance across seeds (unbiased, averaged over
// pixels and channels), bias² = MSE(m, r) − v/S (an unbiased estimate: MSE(m, r) holds v/S of
// noise; it can come out slightly below 0) and variance = v, so that bias² + variance is exactly
// the mean over seeds of each seed's MSE. The reference's own noise (tests/data/references.md)
// is part of bias².
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "image/image.h"
#include "image/metrics.h"
#include "render/photon_renderer.h"

namespace pcl {

struct SweepOptions {
    std::string scenePath;
    std::string referencePath;
    std::string device = "cpu";       // OpenCL device of the photon methods (the path tracer runs on the CPU)
    bool quick = false;               // CI form: a 16-wide image (the reference box-downsampled), fewer photons,
                                      // short curves; well under 2 minutes on 2 cores
    double maxSeconds = 60.0;         // a curve stops after its first point at or past this
    uint32_t seeds = 1;               // independent repeats per curve (≥ 2: bias² and variance rows)
    uint64_t seed = 0;                // the first seed; the others are seed + 1000, + 2000 ...
    std::vector<std::string> curves;  // curve names to run (empty: all of the form); see sweepCurveNames
    int threads = 0;                  // path tracer threads (0: all cores)
    std::function<void(const std::string&)> progress;  // one line per point (stderr in the CLI)
};

// One CSV row. seed is the seed's number, or "all" on a bias²/variance row.
struct SweepRow {
    std::string scene, curve, method, settings, device, seed;
    uint64_t passes = 0;  // photon passes, or samples per pixel for path
    uint64_t samplesPerPixel = 0;
    StageTimes times;  // seconds by stage (total: the point's render seconds)
    double rmse = 0, relMse = 0, meanRatio = 0, maxError = 0, mse = 0;
    bool split = false;  // an "all" row: bias2 and variance hold the split
    double bias2 = 0, variance = 0;
};

// The curves a sweep runs: quick → the five methods; full → those and the variants.
std::vector<std::string> sweepCurveNames(bool quick);

// The header line and one line per row (no trailing newline after the header's "\n" only).
std::string sweepCsvHeader();
std::string sweepCsvLine(const SweepRow& row);

// Runs the sweep. InputError: missing or unreadable scene/reference, a reference whose aspect
// ratio differs from the camera's, an unknown curve name. Each row is also passed to `onRow` as
// soon as it is measured (the CLI rewrites its CSV after every point).
std::vector<SweepRow> runSweep(const SweepOptions& options,
                               const std::function<void(const std::vector<SweepRow>&)>& onRow = {});

}  // namespace pcl
