// Issue 31: a folder changes all at once (staging, commit, recovery), one writer at a time, never a user's file or an
// input replaced, a file-size limit reported like a full disk.
// Issue 18, "a run writes into its folder only what it produced", and "no temporary is left after a kill": the output
// folder's manifest and the clean-up of dead processes' temporaries, and the signal-time removal of temporaries in
// progress. Expected states are written out by hand: which names must exist after each step.
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/termination.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/files/output_folder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <grp.h>
#include <csignal>
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
    output::create_folders_for(dir / "meshes");
    EXPECT_FALSE(fs::exists(dir / "meshes")); // made in the staging folder, moved in by the commit
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
  EXPECT_FALSE(fs::exists(dir / "meshes")); // it held only geartopo's files: removed with them
  fs::remove_all(dir);
}

// Review of issue 31, item 3: a subfolder that held the earlier run's files and something of the user's stays.
TEST(OutputFolder, ASubfolderHoldingAUsersFileStays) {
  const auto dir = fresh_output_dir("subfolder");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "meshes" / "t.ply", "t\n");
    folder.finish();
  }
  std::ofstream(dir / "meshes" / "mine.txt") << "user\n";
  {
    output::OutputFolder folder(dir);
    folder.finish();
  }
  EXPECT_EQ(files_below(dir), (std::set<std::string>{".geartopo-outputs", "meshes/mine.txt"}));
  fs::remove_all(dir);
}

// Review of issue 31, item 4: a failed run removes the folder and the parent folders it created (deepest first),
// after an error (the destructor) and after a signal (the handler); a parent that holds something stays.
TEST(OutputFolder, AFailedRunRemovesTheFoldersItCreated) {
  const auto top = fresh_output_dir("created");
  {
    output::OutputFolder folder(top / "new" / "D");
    output::write_text_atomically(top / "new" / "D" / "x.csv", "x\n");
    EXPECT_TRUE(fs::is_directory(top / "new" / "D"));
  } // no finish(): failed
  EXPECT_FALSE(fs::exists(top)) << "the failed run left the folders it created";
  const pid_t child = ::fork();
  if (child == 0) {
    output::remove_temporaries_on_termination_signals();
    output::OutputFolder folder(top / "new" / "D");
    output::write_text_atomically(top / "new" / "D" / "meshes" / "t.ply", "t\n");
    ::raise(SIGTERM);
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  EXPECT_FALSE(fs::exists(top)) << "the interrupted run left the folders it created";
  fs::create_directories(top);
  std::ofstream(top / "other.txt") << "x";
  { output::OutputFolder folder(top / "new" / "D"); }
  EXPECT_EQ(files_below(top), (std::set<std::string>{"other.txt"}));
  EXPECT_FALSE(fs::exists(top / "new"));
  {
    output::OutputFolder folder(top / "new" / "D"); // a run that succeeds keeps its folders
    folder.finish();
  }
  EXPECT_TRUE(fs::exists(top / "new" / "D" / output::kManifestName));
  fs::remove_all(top);
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

// Only ".gt-PID-N" temporaries, in the folder and in the subfolders its manifest names files in. Review of issue 31,
// item 1: users' files named like the ".name.tmp-PID-N" temporaries of earlier versions (".notes.tmp-2024-11.md")
// were removed, and so was such a file two levels down.
TEST(OutputFolder, TemporariesOfDeadProcessesAreRemovedThoseOfLiveOnesAndUsersFilesKept) {
  const auto dir = fresh_output_dir("temps");
  fs::create_directories(dir / "meshes");
  fs::create_directories(dir / "a" / "b");
  std::ofstream(dir / "meshes" / "tooth01_left.ply") << "x";
  std::ofstream(dir / output::kManifestName) << "meshes/tooth01_left.ply\n";
  const std::string dead = ".gt-" + std::to_string(dead_pid()) + "-0.csv";
  const std::string dead_mesh = ".gt-" + std::to_string(dead_pid()) + "-3.ply";
  const std::string live = ".gt-" + std::to_string(::getppid()) + "-1.csv"; // our parent runs
  const std::vector<std::string> users = {".notes.tmp-2024-11.md", ".tmp-notes.txt", "a/b/.draft.tmp-1999-12",
                                          "a/" + dead, // not a folder geartopo writes into
                                          ".topology.tmp-" + std::to_string(dead_pid()) + "-0.csv"};
  for (const auto& name : {dead, live}) std::ofstream(dir / name) << "x";
  for (const auto& name : users) std::ofstream(dir / name) << "x";
  std::ofstream(dir / "meshes" / dead_mesh) << "x";
  output::OutputFolder folder(dir);
  EXPECT_EQ(folder.removed_temporaries().size(), 2u);
  std::set<std::string> kept{live, output::kLockName, output::kManifestName, "meshes/tooth01_left.ply"};
  kept.insert(users.begin(), users.end());
  EXPECT_EQ(files_below(dir), kept);
  fs::remove_all(dir);
}

TEST(OutputFolder, TemporaryNamesAreRecognisedExactly) {
  long pid = 0;
  EXPECT_TRUE(output::is_geartopo_temporary(".gt-4321-0.csv", pid));
  EXPECT_EQ(pid, 4321);
  EXPECT_TRUE(output::is_geartopo_temporary(".gt-5-17", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".gt-stage-5", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".gt-5.csv", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".gt-5-x.csv", pid));
  EXPECT_FALSE(output::is_geartopo_temporary("gt-5-1.csv", pid)); // not hidden
  // The names of earlier versions match users' files too: never taken for temporaries.
  EXPECT_FALSE(output::is_geartopo_temporary(".topology.tmp-1234-0.csv", pid));
  EXPECT_FALSE(output::is_geartopo_temporary(".notes.tmp-2024-11.md", pid));
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

// Review of issue 31, items 5 and 7: a commit that fails midway (here a rename onto a folder; on a full disk a rename
// that must grow the folder fails with ENOSPC) says that the next run completes it; until then readers refuse the
// folder, whose files are a mix of two runs; the next run completes it and the files read again.
TEST(OutputFolder, AnUnfinishedCommitIsNamedAndReadersRefuseTheFolderUntilItIsCompleted) {
  const auto dir = fresh_output_dir("unfinished");
  {
    output::OutputFolder folder(dir);
    output::write_text_atomically(dir / "a.csv", "old a\n");
    output::write_text_atomically(dir / "b.csv", "old b\n");
    folder.finish();
  }
  const auto commit = dir / (".gt-commit-" + std::to_string(dead_pid()));
  fs::create_directories(commit);
  std::ofstream(commit / "a.csv") << "new a\n";
  std::ofstream(commit / "b.csv") << "new b\n";
  std::ofstream(commit / output::kManifestName) << "a.csv\nb.csv\n";
  fs::remove(dir / "b.csv");
  fs::create_directories(dir / "b.csv" / "blocker"); // b.csv cannot be moved in
  try {
    output::OutputFolder folder(dir);
    ADD_FAILURE() << "a commit that cannot be completed was not reported";
  } catch (const output::OutputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("b.csv"), std::string::npos) << m;
    EXPECT_NE(m.find("the next geartopo run with --out " + dir.string() + " completes this commit"), std::string::npos) << m;
  }
  EXPECT_EQ(read_text(dir / "a.csv"), "new a\n"); // moved in: the folder is a mix now
  EXPECT_EQ(output::unfinished_commit(dir), commit.filename().string());
  try {
    input::read_input_file(dir / "a.csv", input::kMaxSceneBytes, "traces CSV");
    ADD_FAILURE() << "a mixed folder was read";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("unfinished geartopo commit"), std::string::npos) << m;
    EXPECT_NE(m.find("--out " + dir.string()), std::string::npos) << m;
  }
  fs::remove_all(dir / "b.csv");
  { output::OutputFolder folder(dir); } // completes the commit, even though this run fails
  EXPECT_EQ(output::unfinished_commit(dir), "");
  EXPECT_EQ(input::read_input_file(dir / "b.csv", input::kMaxSceneBytes, "traces CSV"), "new b\n");
  fs::remove_all(dir);
}

// Review of issue 31, item 6: a signal the parent set to be ignored stays ignored (`nohup`: SIGHUP; a shell's
// background job: SIGINT); one that is not is handled (the process ends by it).
TEST(OutputFolder, AnIgnoredSighupOrSigintStaysIgnored) {
  const auto run_child = [](bool ignore) {
    const pid_t child = ::fork();
    if (child == 0) {
      if (ignore) std::signal(SIGHUP, SIG_IGN), std::signal(SIGINT, SIG_IGN);
      output::remove_temporaries_on_termination_signals();
      ::raise(SIGHUP);
      ::raise(SIGINT);
      ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    return status;
  };
  const int ignored = run_child(true);
  EXPECT_TRUE(WIFEXITED(ignored) && WEXITSTATUS(ignored) == 0) << ignored;
  const int handled = run_child(false);
  EXPECT_TRUE(WIFSIGNALED(handled) && WTERMSIG(handled) == SIGHUP) << handled;
}

namespace {

// Runs `body` in a child process as the user nobody (uid and gid 65534); its return value is the child's exit code.
int as_nobody(const std::function<int()>& body) {
  const pid_t child = ::fork();
  if (child == 0) {
    if (::setgroups(0, nullptr) != 0 || ::setresgid(65534, 65534, 65534) != 0 || ::setresuid(65534, 65534, 65534) != 0)
      ::_exit(99);
    int code = 98;
    try {
      code = body();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "as nobody: %s\n", e.what());
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

} // namespace

// Review of issue 31, item 2: the lock file left by another user's killed run (mode 0644) does not block a later run
// of anyone: it is locked read-only and replaced; in a sticky folder, where it cannot be replaced, it is locked as it
// is, and a second writer's refusal does not name the dead run's pid written in it.
TEST(OutputFolder, ADeadRunsLockFileOfAnotherUserBlocksNobody) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs a second user: run as root (id -u = 0), which switches to nobody in a child";
  const auto dir = fresh_output_dir("lock_user");
  fs::create_directories(dir);
  fs::permissions(dir, fs::perms::all);
  const long dead = dead_pid();
  std::ofstream(dir / output::kLockName) << dead << "\n"; // root's, 0644
  fs::permissions(dir / output::kLockName, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                                               fs::perms::others_read);
  ASSERT_EQ(as_nobody([&] {
              output::OutputFolder folder(dir);
              output::write_text_atomically(dir / "x.csv", "x\n");
              folder.finish();
              return 0;
            }),
            0);
  EXPECT_EQ(read_text(dir / "x.csv"), "x\n");
  EXPECT_FALSE(fs::exists(dir / output::kLockName));

  fs::permissions(dir, fs::perms::all | fs::perms::sticky_bit);
  std::ofstream(dir / output::kLockName) << dead << "\n";
  int held[2], go[2];
  ASSERT_EQ(::pipe(held), 0);
  ASSERT_EQ(::pipe(go), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    ::_exit(as_nobody([&] {
      output::OutputFolder folder(dir);
      char c = 'h';
      if (::write(held[1], &c, 1) != 1 || ::read(go[0], &c, 1) != 1) return 2;
      output::write_text_atomically(dir / "y.csv", "y\n");
      folder.finish();
      return 0;
    }));
  }
  char c = 0;
  ASSERT_EQ(::read(held[0], &c, 1), 1);
  try {
    output::OutputFolder second(dir);
    ADD_FAILURE() << "two writers on one folder";
  } catch (const output::OutputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("another geartopo run (its pid is unknown"), std::string::npos) << m;
    EXPECT_EQ(m.find(std::to_string(dead)), std::string::npos) << m;
  }
  ASSERT_EQ(::write(go[1], &c, 1), 1);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_EQ(read_text(dir / "y.csv"), "y\n");
  for (const int fd : {held[0], held[1], go[0], go[1]}) ::close(fd);
  fs::remove_all(dir);
}
