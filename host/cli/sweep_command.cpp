// `photoncl sweep`: speed against accuracy for one scene (render/sweep.h). Every method and a
// small grid of settings at doubling budgets, each point's error against a reference, one CSV
// (rewritten whole, through a temporary, after every point) for scripts/chart.py.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "cli/command.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "render/sweep.h"

namespace pcl::cli {
namespace {

struct SweepCliOptions {
    SweepOptions sweep;
    std::string outDir = ".", curves;
    double maxSeconds = 0;  // 0: 60, or 2 with --quick
    bool quiet = false;
};

int runSweepCommand(SweepCliOptions& o) {
    namespace fs = std::filesystem;
    // A missing output folder is made (with its parents), as a user running a new sweep expects;
    // a path that exists and is not a folder, or one that cannot be made, is refused.
    std::error_code ec;
    if (!fs::is_directory(o.outDir)) fs::create_directories(o.outDir, ec);
    if (!fs::is_directory(o.outDir))
        throw InputError(
            "sweep: output folder " + o.outDir + ": " +
            (fs::exists(o.outDir) ? "exists and is not a folder" : "cannot be created (" + ec.message() + ")"));
    SweepOptions s = o.sweep;
    s.maxSeconds = o.maxSeconds > 0 ? o.maxSeconds : (s.quick ? 2.0 : 60.0);
    std::stringstream list(o.curves);
    for (std::string item; std::getline(list, item, ',');)
        if (!item.empty()) s.curves.push_back(item);
    if (!o.quiet) s.progress = [](const std::string& line) { std::fprintf(stderr, "sweep: %s\n", line.c_str()); };
    const std::string csv = (fs::path(o.outDir) / ("sweep-" + fs::path(s.scenePath).stem().string() + ".csv")).string();
    auto write = [&](const std::vector<SweepRow>& rows) {
        std::string text = sweepCsvHeader();
        for (const SweepRow& r : rows) text += sweepCsvLine(r);
        writeFileAtomically(csv, text);
    };
    std::vector<SweepRow> rows = runSweep(s, write);
    write(rows);
    std::fprintf(stderr, "wrote %s: %zu rows\n", csv.c_str(), rows.size());
    return kExitOk;
}

}  // namespace

Run addSweepCommand(CLI::App& app) {
    auto o = std::make_shared<SweepCliOptions>();
    CLI::App* sub = app.add_subcommand(
        "sweep",
        "Speed against accuracy: render a scene at doubling budgets with every method (path, direct, fg with the "
        "full estimate, fg with precomputed irradiance, progressive) and a few setting variants, and write each "
        "point's seconds (total and by stage) and error against a reference to OUT_DIR/sweep-<scene>.csv "
        "(scripts/chart.py charts it).");
    sub->add_option("SCENE", o->sweep.scenePath, "Scene file (.json, .gltf, .glb)")->required();
    sub->add_option("--reference", o->sweep.referencePath,
                    "Reference EXR (tests/data/ref-<scene>.exr); the renders take its size, which must have the "
                    "camera's aspect ratio")
        ->required();
    sub->add_flag("--quick", o->sweep.quick,
                  "CI form: the image at a quarter of the reference's width (the reference box-averaged), 1/8 of the "
                  "photons, 1/4 of the gather rays, curves of about 2 s, the five methods only");
    sub->add_option("-o,--output-dir", o->outDir, "Folder for sweep-<scene>.csv (made if missing)")
        ->capture_default_str();
    sub->add_option("--device", o->sweep.device,
                    "OpenCL device of the photon methods: cpu, gpu, auto, <index> or <name substring> (the path "
                    "tracer always runs on the CPU)")
        ->capture_default_str();
    sub->add_option("--seeds", o->sweep.seeds,
                    "Independent repeats of every curve; 2 or more add rows (seed \"all\") splitting the MSE into "
                    "bias² and variance")
        ->check(CLI::Range(1u, 64u))
        ->capture_default_str();
    sub->add_option(
           "--seed", o->sweep.seed,
           "The first seed (the others: + 1000, + 2000 ...; not 1 or 2 with a path curve: those made the references)")
        ->capture_default_str();
    sub->add_option("--max-seconds", o->maxSeconds,
                    "A curve ends with its first point at or past this many render seconds (default 60; --quick 2)")
        ->check(CLI::PositiveNumber);
    std::string names;
    for (const std::string& n : sweepCurveNames(false)) names += (names.empty() ? "" : ", ") + n;
    sub->add_option("--curves", o->curves, "Comma-separated curves to run instead of the form's: " + names);
    sub->add_option("--threads", o->sweep.threads, "CPU threads of the path tracer (default: all cores)");
    sub->add_flag("-q,--quiet", o->quiet, "No line per point on stderr");
    return [o] { return runSweepCommand(*o); };
}

}  // namespace pcl::cli
