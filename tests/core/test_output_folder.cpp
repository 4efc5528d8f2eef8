// Issue 31: a folder changes all at once (staging, commit, recovery), one writer at a time, never a user's file or an
// input replaced, a file-size limit reported like a full disk.
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
#include <sstream>
#include <string>
#include <sys/resource.h>
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

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
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

TEST(OutputFolder, AFailedRunLeavesTheFolderAsItWas) {
  const auto dir = fresh_output_dir("failed");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "old.csv", "old\n");
    folder.finish();
  }
  {
    output::OutputFolder folder(dir); // fails after one file: no finish()
    output::write_text_atomically(dir / "old.csv", "replaced\n");
    output::write_text_atomically(dir / "partial_run.csv", "x\n");
    EXPECT_FALSE(fs::exists(dir / "partial_run.csv")); // staged, not in the folder yet
  }
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "old.csv"}));
  EXPECT_EQ(read_text(dir / "old.csv"), "old\n");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "new.csv", "n\n");
    folder.finish();
  }
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "new.csv"}));
  fs::remove_all(dir);
}

// Staging: nothing of the run is in the folder before finish(), everything after it; what the run wrote can be read
// back through current_location meanwhile (a figure's panels).
TEST(OutputFolder, FilesAppearOnlyWhenTheRunFinishes) {
  const auto dir = fresh_output_dir("staged");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "a.csv", "first\n");
    folder.finish();
  }
  output::OutputFolder folder(dir);
  output::write_text_atomically(dir / "a.csv", "second\n");
  EXPECT_EQ(read_text(dir / "a.csv"), "first\n");
  EXPECT_EQ(read_text(output::current_location(dir / "a.csv")), "second\n");
  EXPECT_TRUE(fs::exists(dir / output::kLockName));
  folder.finish();
  EXPECT_EQ(read_text(dir / "a.csv"), "second\n");
  EXPECT_EQ(output::current_location(dir / "a.csv"), dir / "a.csv");
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "a.csv"})); // no lock, no staging folder
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
  fs::remove_all(dir);
}

TEST(OutputFolder, AFileGeartopoDidNotWriteIsNeverReplaced) {
  const auto dir = fresh_output_dir("foreign");
  fs::create_directories(dir);
  std::ofstream(dir / "prediction.txt") << "the user's notes\n";
  {
    output::OutputFolder folder(dir);
    try {
      output::write_text_atomically(dir / "prediction.txt", "x\n");
      ADD_FAILURE() << "replaced a file not in the manifest";
    } catch (const output::OutputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("prediction.txt"), std::string::npos) << m;
      EXPECT_NE(m.find(output::kManifestName), std::string::npos) << m;
    }
  }
  // Declared before any work, the same refusal.
  EXPECT_THROW(output::check_run_files(dir, {{}, {"prediction.txt"}}), output::OutputError);
  EXPECT_THROW(output::OutputFolder(dir, {{}, {"prediction.txt"}}), output::OutputError);
  EXPECT_EQ(read_text(dir / "prediction.txt"), "the user's notes\n");
  EXPECT_EQ(files_below(dir), (std::set<std::string>{"prediction.txt"}));
  fs::remove_all(dir);
}

TEST(OutputFolder, AnInputOfTheRunIsNeverReplacedEvenIfGeartopoWroteIt) {
  const auto dir = fresh_output_dir("input");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "residuals.csv", "earlier\n");
    folder.finish();
  }
  const output::RunFiles files{{dir / "residuals.csv"}, {"residuals.csv"}};
  try {
    output::check_run_files(dir, files);
    ADD_FAILURE() << "an input would be replaced";
  } catch (const output::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("an input of this run"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text(dir / "residuals.csv"), "earlier\n");
  fs::remove_all(dir);
}

TEST(OutputFolder, ASecondWriterIsRefusedNamingTheFolderAndThePid) {
  const auto dir = fresh_output_dir("lock");
  output::OutputFolder first(dir);
  try {
    output::OutputFolder second(dir);
    ADD_FAILURE() << "two writers on one folder";
  } catch (const output::OutputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(dir.filename().string()), std::string::npos) << m;
    EXPECT_NE(m.find("pid " + std::to_string(::getpid())), std::string::npos) << m;
  }
  first.finish();
  output::OutputFolder third(dir); // free again
  third.finish();
  fs::remove_all(dir);
}

// A commit folder left by a process killed within its renames is completed by the next opening: the new files in
// place, the earlier run's files the new manifest does not list removed, the user's file kept.
TEST(OutputFolder, AnInterruptedCommitIsCompletedOnTheNextOpening) {
  const auto dir = fresh_output_dir("recover");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "a.csv", "old a\n");
    output::write_text_atomically(dir / "stale.csv", "old\n");
    folder.finish();
  }
  std::ofstream(dir / "notes.txt") << "user\n";
  const auto commit = dir / (".gt-commit-" + std::to_string(dead_pid()));
  fs::create_directories(commit / "meshes");
  std::ofstream(commit / "meshes" / "t.ply") << "new t\n";
  std::ofstream(commit / output::kManifestName) << "a.csv\nmeshes/t.ply\n";
  std::ofstream(dir / "a.csv") << "new a\n"; // already moved in before the kill
  const auto stage = dir / (".gt-stage-" + std::to_string(dead_pid()));
  fs::create_directories(stage);
  std::ofstream(stage / "a.csv") << "never committed\n";
  { output::OutputFolder folder(dir); }
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "a.csv", "meshes/t.ply", "notes.txt"}));
  EXPECT_EQ(read_text(dir / "a.csv"), "new a\n");
  EXPECT_FALSE(fs::exists(commit));
  EXPECT_FALSE(fs::exists(stage));
  fs::remove_all(dir);
}

// NAME_MAX is 255: a final name of 250 bytes needs a temporary name shorter than itself.
TEST(OutputFolder, ALongLegalFileNameCanBeWritten) {
  const auto dir = fresh_output_dir("long");
  const std::string name = std::string(246, 'n') + ".csv";
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / name, "x\n");
    folder.finish();
  }
  EXPECT_EQ(read_text(dir / name), "x\n");
  try {
    output::write_text_atomically(dir / (std::string(300, 'n') + ".csv"), "x\n");
    ADD_FAILURE() << "a 304-byte name was accepted";
  } catch (const output::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("more than the 255"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// A file-size limit (RLIMIT_FSIZE, `ulimit -f`) in a child: SIGXFSZ is ignored, the write fails with EFBIG, the error
// names the file and the folder keeps the earlier run's files, with no temporary and no staging folder.
TEST(OutputFolder, AFileSizeLimitFailsTheRunAndLeavesTheFolderAsItWas) {
  const auto dir = fresh_output_dir("fsize");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "small.csv", "old\n");
    output::write_text_atomically(dir / "big.csv", "old\n");
    folder.finish();
  }
  const pid_t child = ::fork();
  if (child == 0) {
    output::remove_temporaries_on_termination_signals();
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      output::OutputFolder folder(dir);
      output::write_text_atomically(dir / "small.csv", "new\n");
      output::write_text_atomically(dir / "big.csv", std::string(100000, 'x'));
      folder.finish();
    } catch (const output::OutputError& e) {
      const std::string m = e.what();
      ::_exit(m.find("big.csv") != std::string::npos && m.find("File too large") != std::string::npos ? 3 : 4);
    }
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 3);
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "big.csv", "small.csv"}));
  EXPECT_EQ(read_text(dir / "small.csv"), "old\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
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
  const std::string dead_now = ".gt-" + std::to_string(dead_pid()) + "-4.csv"; // the name of today's temporaries
  std::ofstream(dir / dead_now) << "x";
  output::OutputFolder folder(dir);
  EXPECT_EQ(folder.removed_temporaries().size(), 3u);
  EXPECT_EQ(files_below(dir), (std::set<std::string>{live, lookalike, output::kLockName}));
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
  EXPECT_TRUE(output::is_geartopo_temporary(".gt-4321-0.csv", pid));
  EXPECT_EQ(pid, 4321);
  EXPECT_TRUE(output::is_geartopo_temporary(".gt-5-17", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".gt-stage-5", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".gt-5.csv", pid));
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

// One output folder per command: a second one open in the same process would take the first one's writes.
TEST(OutputFolder, ASecondFolderInTheSameProcessIsRefused) {
  const auto a = fresh_output_dir("first"), b = fresh_output_dir("second");
  output::OutputFolder first(a);
  EXPECT_THROW(output::OutputFolder(b, {}), output::OutputError);
  EXPECT_FALSE(fs::exists(b / output::kLockName)); // released by the refused one
  output::write_text_atomically(a / "x.csv", "x\n");
  first.finish();
  EXPECT_EQ(read_text(a / "x.csv"), "x\n");
  fs::remove_all(a);
  fs::remove_all(b);
}
