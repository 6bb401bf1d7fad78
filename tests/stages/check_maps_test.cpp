// check/maps (photoncl check --stage sort|build): passes on a shipped scene, prints a
// row per input, and fails when the comparison is handed a wrong answer.
#include <gtest/gtest.h>

#include <filesystem>

#include "check/maps.h"
#include "device_fixture.h"
#include "reference/kdtree.h"
#include "scene/load_scene.h"

namespace pcl {
namespace {

MapCheckOptions small() {
    MapCheckOptions o;
    o.photons = 5000;
    o.syntheticKeys = 20000;
    return o;
}

Scene cornell() {
    return loadScene((std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes" / "cornell-spheres.json").string());
}

TEST(CheckMaps, SortPassesOnShippedScene) {
    MapCheckReport r = checkSort(test::testDevice(), cornell(), small());
    std::printf("%s", r.table().c_str());
    EXPECT_TRUE(r.passed());
    EXPECT_GE(r.rows.size(), 14u);  // 4 global-map rows + 10 synthetic (+ 4 caustic when present)
    for (const MapCheckRow& row : r.rows) EXPECT_GT(row.items, 0u) << row.input;
}

TEST(CheckMaps, BuildPassesOnShippedScene) {
    MapCheckReport r = checkKdTreeBuild(test::testDevice(), cornell(), small());
    std::printf("%s", r.table().c_str());
    EXPECT_TRUE(r.passed());
    ASSERT_EQ(r.rows.size(), 2u);
    EXPECT_GT(r.rows[0].items, 1000u);
    EXPECT_NE(r.table().find("PASSED"), std::string::npos);
}

TEST(CheckMaps, ComparisonsFailOnWrongAnswers) {
    MapCheckRow sortRow;
    compareSorted({1, 2, 2}, {0, 1, 2}, {1, 2, 2}, {0, 2, 1}, sortRow);  // unstable
    EXPECT_EQ(sortRow.valueMismatches, 2u);
    MapCheckReport sortReport;
    sortReport.stage = "sort";
    sortReport.rows.push_back(sortRow);
    EXPECT_FALSE(sortReport.passed());

    std::vector<PclPhoton> map;
    for (uint32_t i = 0; i < 100; ++i)
        map.push_back(PclPhoton{float(i % 10), float(i / 10), 0.5f * float(i % 3), i, i, 0u});
    ReferenceKdTree t = referenceBuildKdTree(map);
    MapCheckRow same;
    compareKdTrees(map, t.photons, t.index, t.photons, t.index, same);
    EXPECT_EQ(same.defect, "");
    EXPECT_EQ(same.byteMismatches + same.indexMismatches, 0u);
    ReferenceKdTree broken = t;
    std::swap(broken.photons[3], broken.photons[4]);
    std::swap(broken.index[3], broken.index[4]);
    MapCheckRow row;
    compareKdTrees(map, t.photons, t.index, broken.photons, broken.index, row);
    EXPECT_EQ(row.byteMismatches, 2u);
    EXPECT_NE(row.defect, "");
    MapCheckReport buildReport;
    buildReport.stage = "build";
    buildReport.rows.push_back(row);
    EXPECT_FALSE(buildReport.passed());
    EXPECT_NE(buildReport.table().find("FAILED"), std::string::npos);
}

}  // namespace
}  // namespace pcl
