// A test fixture with a fresh folder per test (pid and test name in its name, removed after) to
// write scene files and their images into, load them, and check that a bad one is refused with
// the usual message: an InputError naming the file and every expected fragment (field, what was
// found, what was expected).
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "core/error.h"
#include "scene/load_scene.h"

namespace pcl::test {

class SceneFolderTest : public ::testing::Test {
protected:
    // Call first in SetUp (after any feature check).
    void makeFolder(const std::string& prefix) {
        dir_ = std::filesystem::temp_directory_path() /
               (prefix + "-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override {
        if (!dir_.empty()) std::filesystem::remove_all(dir_);
    }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::string write(const std::string& name, const std::string& text) {
        std::ofstream(path(name), std::ios::binary) << text;
        return path(name);
    }
    Scene load(const nlohmann::json& s) { return loadScene(write("scene.json", s.dump())); }
    // `doc` written as `name` (its extension picks the loader) must be refused.
    void expectError(const std::string& name, const nlohmann::json& doc, std::initializer_list<std::string> fragments) {
        const std::string file = write(name, doc.dump());
        try {
            loadScene(file);
            ADD_FAILURE() << "expected InputError, loaded fine";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(file), std::string::npos) << msg;
            for (const auto& f : fragments)
                EXPECT_NE(msg.find(f), std::string::npos) << "lacks \"" << f << "\": " << msg;
        }
    }
    void expectError(const nlohmann::json& s, std::initializer_list<std::string> fragments) {
        expectError("bad.json", s, fragments);
    }

    std::filesystem::path dir_;
};

}  // namespace pcl::test
