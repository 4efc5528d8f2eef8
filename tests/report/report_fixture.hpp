// The report of the default scene, written once by `geartopo report` (no display, the header date fixed by
// SOURCE_DATE_EPOCH = 1700000000 s, i.e. 2023-11-14), for the tests of test_report.cpp and test_report_page.cpp.
// Under ctest the report is written once for the whole program: ctest runs every test in a process of its own, so the
// fixture test ReportFixture.Write (tests/CMakeLists.txt) writes it before them into the folder named by
// GEARTOPO_REPORT_DIR, and each process reads it from there (geometry-central's shared fixtures in spirit). Run
// directly, the program writes it itself, once (SetUpTestSuite), into a temporary folder it removes afterwards. Tests
// may add files of their own to the folder (screenshots, browser profiles) under names no other test uses.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

class ReportTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    const char* shared = std::getenv("GEARTOPO_REPORT_DIR");
    owned_ = shared == nullptr || *shared == '\0';
    if (owned_) {
      dir_ = new fs::path(fs::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_report"));
      const std::string scene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";
      // No display: unset DISPLAY for the child, as on a headless server.
      const std::string cmd = "env -u DISPLAY SOURCE_DATE_EPOCH=1700000000 " + std::string(GEARTOPO_BINARY) + " report " +
                              scene + " --out " + dir_->string() + " > " + (dir_->string() + ".log") + " 2>&1";
      code_ = std::system(cmd.c_str());
    } else {
      // Written by ReportFixture.Write with the command above; its exit status is that test's (ctest runs no test
      // that needs a failed fixture), so here the report is there or this is a failure.
      dir_ = new fs::path(shared);
      code_ = fs::exists(*dir_ / "index.html") && fs::exists(*dir_ / "figures.json") ? 0 : 1;
    }
    std::ifstream man(*dir_ / "figures.json");
    if (man) manifest_ = new nlohmann::json(nlohmann::json::parse(man));
  }
  static void TearDownTestSuite() {
    if (owned_) {
      fs::remove_all(*dir_);
      fs::remove(dir_->string() + ".log");
    }
    delete manifest_;
    delete dir_;
  }
  static inline fs::path* dir_ = nullptr;
  static inline nlohmann::json* manifest_ = nullptr;
  static inline int code_ = -1;
  static inline bool owned_ = true;
};

} // namespace
