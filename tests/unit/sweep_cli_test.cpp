// `photoncl sweep --quick` on cornell-box against its reference: the CSV's
// columns and rows, every method present with finite numbers, the path tracer's error falling
// with its budget, the bias²/variance rows of --seeds, the errors, and scripts/chart.py's charts.
#include <gtest/gtest.h>
#include "common/optional_feature.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "unit/run_photoncl.h"

namespace fs = std::filesystem;
using photoncl_cli::Result;
using photoncl_cli::run;

namespace {

std::string source(const std::string& rel) { return (fs::path(PHOTONCL_SOURCE_DIR) / rel).string(); }

struct Csv {
    std::vector<std::string> header;
    std::vector<std::map<std::string, std::string>> rows;  // column name -> text; "#fields": the field count
};

// Splits one CSV line (quoted fields may hold commas and doubled quotes).
std::vector<std::string> splitCsvLine(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cur += '"', ++i;
            else if (c == '"') quoted = false;
            else cur += c;
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            out.push_back(cur), cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

Csv readCsv(const fs::path& path) {
    std::ifstream in(path);
    Csv csv;
    std::string line;
    if (!std::getline(in, line)) return csv;
    csv.header = splitCsvLine(line);
    while (std::getline(in, line)) {
        std::vector<std::string> f = splitCsvLine(line);
        std::map<std::string, std::string> row;
        for (size_t i = 0; i < csv.header.size() && i < f.size(); ++i) row[csv.header[i]] = f[i];
        row["#fields"] = std::to_string(f.size());
        csv.rows.push_back(row);
    }
    return csv;
}

class SweepCliTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() / ("photoncl-sweep-cli-" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    fs::path dir;
};

}  // namespace

TEST_F(SweepCliTest, QuickSweepWritesEveryMethodsCurveAndCharts) {
    // Two seeds: the bias²/variance rows too. --quick: 16x16, curves of about 2 s each here (at
    // 1 s a heavily loaded machine's first pass can reach the budget, leaving a one-point curve).
    // The output folder does not exist yet: sweep makes it, parents too.
    const fs::path out = dir / "made" / "by-sweep";
    Result r = run("sweep " + source("scenes/cornell-box.json") + " --reference " +
                   source("tests/data/ref-cornell-box.exr") + " --quick --seeds 2 --max-seconds 2 -o " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const fs::path csv = out / "sweep-cornell-box.csv";
    ASSERT_TRUE(fs::exists(csv)) << r.output;
    Csv table = readCsv(csv);
    ASSERT_FALSE(table.rows.empty());
    // clang-format off
    const std::vector<std::string> expected = {
        "scene",          "curve",           "method",          "variant_settings",  "device",
        "seed",           "passes",          "samples_per_pixel", "seconds",         "seconds_photons",
        "seconds_maps",   "seconds_camera",  "seconds_eye_paths", "seconds_direct",  "seconds_caustic",
        "seconds_indirect", "seconds_volume", "seconds_accumulate", "rmse",        "relmse",          "mean_ratio",
        "max_error",      "mse",             "bias2",           "variance"};
    // clang-format on
    EXPECT_EQ(table.header, expected);

    std::map<std::string, std::vector<std::map<std::string, std::string>>> perCurve;  // seed 0 rows
    std::map<std::string, int> splitRows;
    for (size_t i = 0; i < table.rows.size(); ++i) {
        auto& row = table.rows[i];
        ASSERT_EQ(row["#fields"], std::to_string(expected.size())) << "row " << i;
        EXPECT_EQ(row["scene"], "cornell-box");
        for (const char* col : {"seconds", "rmse", "relmse", "mean_ratio", "max_error", "mse"}) {
            double v = std::strtod(row[col].c_str(), nullptr);
            EXPECT_TRUE(std::isfinite(v) && v >= 0) << col << " = " << row[col] << " in row " << i;
        }
        if (row["seed"] == "all") {
            ++splitRows[row["curve"]];
            double b = std::strtod(row["bias2"].c_str(), nullptr), v = std::strtod(row["variance"].c_str(), nullptr);
            EXPECT_TRUE(std::isfinite(b) && std::isfinite(v) && v >= 0) << row["bias2"] << " " << row["variance"];
            // bias² + variance is the mean of the seeds' MSEs (sweep.h), up to the CSV's 6 digits.
            EXPECT_NEAR(b + v, std::strtod(row["mse"].c_str(), nullptr), 1e-4 * std::abs(b + v) + 1e-12);
        } else if (row["seed"] == "0") {
            EXPECT_TRUE(row["bias2"].empty() && row["variance"].empty());
            perCurve[row["curve"]].push_back(row);
        }
    }
    for (const char* curve : {"path", "direct", "fg-estimate", "fg-precomputed", "progressive"}) {
        ASSERT_GE(perCurve[curve].size(), 2u) << curve << ": at least two budgets\n" << r.output;
        EXPECT_EQ(splitRows[curve], int(perCurve[curve].size())) << curve;
        auto first = perCurve[curve].front();
        auto last = perCurve[curve].back();
        double mr = std::strtod(last["mean_ratio"].c_str(), nullptr);
        std::printf("[figure] quick sweep cornell-box %s: %s -> %s passes, relMSE %s -> %s, %s s, mean ratio %s\n",
                    curve, first["passes"].c_str(), last["passes"].c_str(), first["relmse"].c_str(),
                    last["relmse"].c_str(), last["seconds"].c_str(), last["mean_ratio"].c_str());
        // Energy: the path tracer's last point (over a thousand spp here) within 5 %; the photon
        // methods' last point (8-32 passes at 16x16) within 10 %: measured within 1.6 %, and
        // renders of 8 passes over 6 seeds stay within 3.5 % (partly covered lamp pixels and
        // direct visualisation's ~2 % bias), so a tenth of the energy lost or gained fails.
        EXPECT_NEAR(mr, 1.0, std::string(curve) == "path" ? 0.05 : 0.10) << curve;
    }
    // The path tracer is unbiased: its MSE falls as 1/spp. Its budgets span at least 2^4 spp here,
    // so the last point's relMSE must be below a quarter of the first's (expected ~1/16 or less).
    auto path = perCurve["path"];
    double spp0 = std::strtod(path.front()["passes"].c_str(), nullptr);
    double spp1 = std::strtod(path.back()["passes"].c_str(), nullptr);
    ASSERT_GE(spp1 / spp0, 16.0) << r.output;
    EXPECT_LT(std::strtod(path.back()["relmse"].c_str(), nullptr),
              0.25 * std::strtod(path.front()["relmse"].c_str(), nullptr));

    // The charts: made whenever a python3 with matplotlib is found (CI installs Debian's
    // python3-matplotlib: no skip there). A pyenv python3 first on PATH may lack it: try Debian's too.
    std::string python;
    for (const char* candidate : {"python3", "/usr/bin/python3"})
        if (python.empty() &&
            std::system((std::string(candidate) + " -c 'import matplotlib' >/dev/null 2>&1").c_str()) == 0)
            python = candidate;
    PCL_REQUIRE_FEATURE(!python.empty(), "python3-matplotlib");
    std::string cmd = python + " " + source("scripts/chart.py") + " " + csv.string() + " -o " + dir.string() + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    for (const char* png : {"cornell-box-error.png", "cornell-box-bias-variance.png"}) {
        ASSERT_TRUE(fs::exists(dir / png)) << png;
        std::ifstream f(dir / png, std::ios::binary);
        char magic[4] = {};
        f.read(magic, 4);
        EXPECT_EQ(std::string(magic + 1, 3), "PNG") << png;
        EXPECT_GT(fs::file_size(dir / png), 5000u) << png;
    }
    EXPECT_TRUE(fs::exists(dir / "winners.md"));
}

// A scene with media: the fg curves are left out (said on stderr) and refused when named; the
// path tracer and progressive run, progressive's volume stage timed.
TEST_F(SweepCliTest, MediaSweepLeavesFgOut) {
    const std::string scene = source("scenes/media/cornell-fog.json"), ref = source("tests/data/ref-cornell-fog.exr");
    Result fg = run("sweep " + scene + " --reference " + ref + " --quick --curves fg-precomputed -o " + dir.string());
    EXPECT_EQ(fg.status, 2) << fg.output;
    EXPECT_NE(fg.output.find("sweep curve fg-precomputed (fg's gather rays do not carry media yet)"), std::string::npos)
        << fg.output;
    Result r = run("sweep " + scene + " --reference " + ref +
                   " --quick --curves path,progressive,fg-precomputed --max-seconds 1 -o " + dir.string());
    EXPECT_EQ(r.status, 2) << r.output;  // named: refused
    r = run("sweep " + scene + " --reference " + ref + " --quick --max-seconds 1 -o " + dir.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("fg curve(s) left out"), std::string::npos) << r.output;
    Csv table = readCsv(dir / "sweep-cornell-fog.csv");
    std::map<std::string, int> rows;
    double volumeSeconds = 0.0;
    for (const auto& row : table.rows) {
        ++rows[row.at("curve")];
        if (row.at("curve") == "progressive") volumeSeconds += std::stod(row.at("seconds_volume"));
        // direct renders its budgets in increments: their volume seconds add up too.
        if (row.at("curve") == "direct" && row.at("seed") != "all") {
            EXPECT_GT(std::stod(row.at("seconds_volume")), 0.0) << row.at("passes");
        }
    }
    EXPECT_GT(rows["path"], 0);
    EXPECT_GT(rows["progressive"], 0);
    EXPECT_GT(rows["direct"], 0);
    for (const auto& [curve, n] : rows) EXPECT_EQ(curve.rfind("fg", 0), std::string::npos) << curve;
    EXPECT_GT(volumeSeconds, 0.0);
}

TEST_F(SweepCliTest, ClearErrors) {
    const std::string scene = source("scenes/cornell-box.json");
    Result missing = run("sweep " + scene + " --reference " + (dir / "nope.exr").string() + " -o " + dir.string());
    EXPECT_EQ(missing.status, 2) << missing.output;
    EXPECT_NE(missing.output.find("nope.exr: no such file"), std::string::npos) << missing.output;
    // motion-dof's camera is 4:3, the furnace's reference square.
    Result aspect = run("sweep " + source("scenes/motion-dof.json") + " --reference " +
                        source("tests/data/ref-furnace-0.5.exr") + " -o " + dir.string());
    EXPECT_EQ(aspect.status, 2) << aspect.output;
    EXPECT_NE(aspect.output.find("expected a reference at the camera's aspect ratio"), std::string::npos)
        << aspect.output;
    Result bad = run("sweep " + scene + " --reference " + source("tests/data/ref-cornell-box.exr") +
                     " --curves sparkle -o " + dir.string());
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("unknown curve 'sparkle'"), std::string::npos) << bad.output;
    // -o names a file: refused (a missing folder is made: the quick sweep test writes into one).
    std::ofstream(dir / "a-file") << "x";
    Result noDir = run("sweep " + scene + " --reference " + source("tests/data/ref-cornell-box.exr") + " -o " +
                       (dir / "a-file").string());
    EXPECT_EQ(noDir.status, 2) << noDir.output;
    EXPECT_NE(noDir.output.find("exists and is not a folder"), std::string::npos) << noDir.output;
}

// The auto curve: `render --method auto --time T` per point (here one point of 5 s at 64 wide),
// the pilot's pick named in the method column, the whole time (pilot included) in seconds.
TEST_F(SweepCliTest, AutoCurveRendersTimedPointsWithThePilotsChoice) {
    Result r = run("sweep " + source("scenes/cornell-box.json") + " --reference " +
                   source("tests/data/ref-cornell-box.exr") + " --curves auto --max-seconds 5 -o " + dir.string());
    ASSERT_EQ(r.status, 0) << r.output;
    Csv table = readCsv(dir / "sweep-cornell-box.csv");
    ASSERT_EQ(table.rows.size(), 1u) << r.output;
    auto& row = table.rows[0];
    std::printf("[figure] sweep auto cornell-box 64 wide, 5 s: %s, %s s, %s passes, relMSE %s, mean ratio %s\n",
                row["method"].c_str(), row["seconds"].c_str(), row["passes"].c_str(), row["relmse"].c_str(),
                row["mean_ratio"].c_str());
    const std::set<std::string> picks = {"auto: fg", "auto: fg 6x6x2", "auto: path"};
    EXPECT_EQ(picks.count(row["method"]), 1u) << row["method"];
    EXPECT_NE(row["variant_settings"].find("render --method auto --time 5; method auto: "), std::string::npos)
        << row["variant_settings"];
    // The budget is spent, not skipped: --time stops within half a pass of T, and the pilot is
    // paid from T (no upper bound: a loaded machine stretches the last pass).
    EXPECT_GT(std::stod(row["seconds"]), 2.5);
    EXPECT_GT(std::stoull(row["passes"]), 0u);
    EXPECT_NEAR(std::stod(row["mean_ratio"]), 1.0, 0.05);
}
