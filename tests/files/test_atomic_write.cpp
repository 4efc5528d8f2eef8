// Issue 18, "nothing lost": output files are written to a temporary beside them and renamed only when complete. A
// write error (a full disk, simulated with a file-size limit, which works for root too, unlike a read-only folder)
// gives OutputError naming the file and leaves nothing partial under the final name.
#include "geartopo/files/atomic_write.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/resource.h>
#include <unistd.h>

using namespace geartopo;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("geartopo_atomic_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Files in `dir` other than `keep`: leftovers (temporaries) after a failed write.
std::vector<std::string> others(const fs::path& dir, const std::string& keep) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename() != keep) out.push_back(e.path().filename().string());
  return out;
}

} // namespace

TEST(AtomicFile, WritesTheWholeFileAndLeavesNoTemporary) {
  const auto dir = fresh_dir("ok");
  output::write_text_atomically(dir / "a.json", "{}\n");
  EXPECT_EQ(slurp(dir / "a.json"), "{}\n");
  output::write_atomically(dir / "a.json", [](std::ostream& out) { out << "second\n"; }); // replaces
  EXPECT_EQ(slurp(dir / "a.json"), "second\n");
  EXPECT_TRUE(others(dir, "a.json").empty());
  fs::remove_all(dir);
}

TEST(AtomicFile, AWriterThatThrowsLeavesTheOldFileAndNoTemporary) {
  const auto dir = fresh_dir("throw");
  output::write_text_atomically(dir / "t.csv", "old\n");
  EXPECT_THROW(output::write_atomically(dir / "t.csv",
                                        [](std::ostream& out) {
                                          out << "half";
                                          throw std::runtime_error("stop");
                                        }),
               std::runtime_error);
  EXPECT_EQ(slurp(dir / "t.csv"), "old\n");
  EXPECT_TRUE(others(dir, "t.csv").empty());
  fs::remove_all(dir);
}

TEST(AtomicFile, AFailedStreamIsAnErrorNamingTheFile) {
  const auto dir = fresh_dir("badbit");
  try {
    output::write_atomically(dir / "b.csv", [](std::ostream& out) { out.setstate(std::ios::badbit); });
    FAIL() << "a failed stream was taken as written";
  } catch (const output::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "b.csv").string() + ": cannot write"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "b.csv"));
  EXPECT_TRUE(others(dir, "").empty());
  fs::remove_all(dir);
}

// A full disk: the file-size limit makes write() fail with EFBIG once 4 KiB are written (SIGXFSZ ignored, as a
// full disk gives ENOSPC without a signal). The limit is this test's process only (ctest runs each test alone).
TEST(AtomicFile, AFullDiskIsAnErrorAndLeavesNoPartialFile) {
  const auto dir = fresh_dir("full");
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string error;
  try {
    output::write_atomically(dir / "big.csv", [](std::ostream& out) {
      for (int i = 0; i < 100000; ++i) out << "1,left,1,1,560.000,10.000,0.0000\n";
    });
  } catch (const output::OutputError& e) {
    error = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
  EXPECT_NE(error.find((dir / "big.csv").string() + ": cannot write"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(dir / "big.csv"));
  EXPECT_TRUE(others(dir, "").empty());
  fs::remove_all(dir);
}

TEST(AtomicFile, WhatMustNotBeReplacedIsRefused) {
  EXPECT_THROW(output::write_text_atomically("", "x"), output::OutputError);
  if (fs::exists("/dev/full")) {
    try {
      output::write_text_atomically("/dev/full", "x");
      FAIL() << "/dev/full accepted as an output file";
    } catch (const output::OutputError& e) {
      EXPECT_NE(std::string(e.what()).find("/dev/full: cannot write: it is not a regular file"), std::string::npos) << e.what();
    }
  }
  const auto dir = fresh_dir("dir");
  EXPECT_THROW(output::write_text_atomically(dir, "x"), output::OutputError);
  EXPECT_THROW(output::write_text_atomically(dir / "no_such_folder" / "f.json", "x"), output::OutputError);
  fs::remove_all(dir);
}

TEST(AtomicFile, APathWriterMustLeaveAFileWithTheSameExtension) {
  const auto dir = fresh_dir("path");
  fs::path seen;
  output::write_atomically_via_path(dir / "m.ply", [&](const fs::path& tmp) {
    seen = tmp;
    std::ofstream(tmp) << "ply\n";
  });
  EXPECT_EQ(seen.extension(), ".ply"); // writers that choose the format by extension choose the same one
  EXPECT_EQ(seen.parent_path(), dir);   // same folder: the rename cannot cross file systems
  EXPECT_EQ(slurp(dir / "m.ply"), "ply\n");
  EXPECT_THROW(output::write_atomically_via_path(dir / "n.png", [](const fs::path&) {}), output::OutputError);
  EXPECT_FALSE(fs::exists(dir / "n.png"));
  fs::remove_all(dir);
}
