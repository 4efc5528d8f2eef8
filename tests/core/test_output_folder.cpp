// Issue 18, "a run writes into its folder only what it produced", and "no temporary is left after a kill": the output
// folder's manifest and the clean-up of dead processes' temporaries, and the signal-time removal of temporaries in
// progress. Expected states are written out by hand: which names must exist after each step.
#include "geartopo/core/atomic_file.hpp"
#include "geartopo/core/output_folder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

using namespace geartopo;
namespace fs = std::filesystem;

namespace {

fs::path fresh_output_dir(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("geartopo_outfolder_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  return dir;
}

// Every file below `dir` (relative, generic form), the manifest included.
std::set<std::string> files_below(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out.insert(e.path().lexically_relative(dir).generic_string());
  return out;
}

// A pid that is certainly not running: a child that has exited and been reaped.
long dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return static_cast<long>(child);
}

} // namespace

TEST(OutputFolder, ASecondRunRemovesWhatOnlyTheFirstWroteAndNothingElse) {
  const auto dir = fresh_output_dir("stale");
  {
    output::OutputFolder folder(dir);
    fs::create_directories(dir / "meshes");
    output::write_text_atomically(dir / "topology.csv", "a\n");
    output::write_text_atomically(dir / "dense.csv", "b\n");
    output::write_text_atomically(dir / "meshes" / "tooth01_left.ply", "c\n");
    EXPECT_TRUE(folder.finish().empty());
  }
  std::ofstream(dir / "notes.txt") << "the user's own file\n"; // never written by geartopo
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "topology.csv", "a2\n");
    const auto removed = folder.finish();
    std::set<std::string> names;
    for (const auto& r : removed) names.insert(r.generic_string());
    EXPECT_EQ(names, (std::set<std::string>{"dense.csv", "meshes/tooth01_left.ply"}));
  }
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "notes.txt", "topology.csv"}));
  fs::remove_all(dir);
}

TEST(OutputFolder, AFailedRunRemovesNothingAndTheNextRunStillKnowsItsFiles) {
  const auto dir = fresh_output_dir("failed");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "old.csv", "old\n");
    folder.finish();
  }
  {
    output::OutputFolder folder(dir); // fails after one file: no finish()
    output::write_text_atomically(dir / "partial_run.csv", "x\n");
  }
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "old.csv", "partial_run.csv"}));
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "new.csv", "n\n");
    folder.finish();
  }
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "new.csv"}));
  fs::remove_all(dir);
}

TEST(OutputFolder, AManifestNamingFilesOutsideTheFolderIsIgnored) {
  const auto dir = fresh_output_dir("escape");
  const auto outside = dir.parent_path() / ("geartopo_outfolder_victim_" + std::to_string(::getpid()));
  std::ofstream(outside) << "must survive\n";
  fs::create_directories(dir);
  std::ofstream(dir / output::kManifestName) << "../" << outside.filename().string() << "\n" << outside.string() << "\n";
  {
    output::OutputFolder folder(dir);
    EXPECT_TRUE(folder.finish().empty());
  }
  EXPECT_TRUE(fs::exists(outside));
  fs::remove(outside);
  fs::remove_all(dir);
}

TEST(OutputFolder, TemporariesOfDeadProcessesAreRemovedThoseOfLiveOnesKept) {
  const auto dir = fresh_output_dir("temps");
  fs::create_directories(dir / "meshes");
  const std::string dead = ".topology.tmp-" + std::to_string(dead_pid()) + "-0.csv";
  const std::string dead_mesh = ".tooth01_left.tmp-" + std::to_string(dead_pid()) + "-3.ply";
  const std::string live = ".traces.tmp-" + std::to_string(::getppid()) + "-1.csv"; // our parent runs
  const std::string lookalike = ".tmp-notes.txt";
  for (const auto& name : {dead, live, lookalike}) std::ofstream(dir / name) << "x";
  std::ofstream(dir / "meshes" / dead_mesh) << "x";
  output::OutputFolder folder(dir);
  EXPECT_EQ(folder.removed_temporaries().size(), 2u);
  EXPECT_EQ(files_below(dir), (std::set<std::string>{live, lookalike}));
  fs::remove_all(dir);
}

TEST(OutputFolder, TemporaryNamesAreRecognisedExactly) {
  long pid = 0;
  EXPECT_TRUE(output::is_geartopo_temporary(".topology.tmp-1234-0.csv", pid));
  EXPECT_EQ(pid, 1234);
  EXPECT_TRUE(output::is_geartopo_temporary(".iso1328.tmp-7-12.json", pid));
  EXPECT_TRUE(output::is_geartopo_temporary(".README.tmp-99-0", pid)); // no extension
  EXPECT_FALSE(output::is_geartopo_temporary("topology.tmp-1234-0.csv", pid)); // not hidden
  EXPECT_FALSE(output::is_geartopo_temporary(".topology.tmp-12a4-0.csv", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".topology.tmp-1234.csv", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".topology.tmp-1234-x.csv", pid));
}

// What the SIGINT/SIGTERM handler calls: the temporary being written at that moment disappears, and the write then
// fails instead of renaming a file that is gone.
TEST(OutputFolder, TemporariesInProgressAreRemovedOnRequest) {
  const auto dir = fresh_output_dir("signal");
  fs::create_directories(dir);
  std::vector<std::string> during;
  EXPECT_THROW(output::write_atomically(dir / "big.csv",
                                        [&](std::ostream& out) {
                                          out << "partial" << std::flush;
                                          output::remove_temporaries_in_progress();
                                          for (const auto& e : fs::directory_iterator(dir))
                                            during.push_back(e.path().filename().string());
                                        }),
               output::OutputError);
  EXPECT_TRUE(during.empty());
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

// The same through a real signal in a child process: SIGTERM while the temporary is open.
TEST(OutputFolder, ASigtermWhileWritingLeavesNoTemporary) {
  const auto dir = fresh_output_dir("sigterm");
  fs::create_directories(dir);
  const pid_t child = ::fork();
  if (child == 0) {
    output::remove_temporaries_on_termination_signals();
    output::write_atomically(dir / "big.csv", [](std::ostream& out) {
      out << "partial" << std::flush;
      ::raise(SIGTERM);
    });
    ::_exit(0); // not reached: the handler re-raises with the default action
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}
