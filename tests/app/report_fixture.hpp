// The report of the default scene, written once per test program by `geartopo report` (no display, the header date
// fixed by SOURCE_DATE_EPOCH = 1700000000 s, i.e. 2023-11-14), for the tests of test_report.cpp and
// test_report_page.cpp.
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
    dir_ = new fs::path(fs::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_report"));
    const std::string scene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";
    // No display: unset DISPLAY for the child, as on a headless server.
    const std::string cmd = "env -u DISPLAY SOURCE_DATE_EPOCH=1700000000 " + std::string(GEARTOPO_BINARY) + " report " + scene + " --out " + dir_->string() +
                            " > " + (dir_->string() + ".log") + " 2>&1";
    code_ = std::system(cmd.c_str());
    std::ifstream man(*dir_ / "figures.json");
    if (man) manifest_ = new nlohmann::json(nlohmann::json::parse(man));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    fs::remove(dir_->string() + ".log");
    delete manifest_;
    delete dir_;
  }
  static inline fs::path* dir_ = nullptr;
  static inline nlohmann::json* manifest_ = nullptr;
  static inline int code_ = -1;
};

} // namespace
