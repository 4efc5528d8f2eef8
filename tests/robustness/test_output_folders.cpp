// Issue 31, "nothing lost, nothing mixed": the geartopo program interrupted at every step of its write phase (a test
// hook, GEARTOPO_TEST_SIGNAL_AT="SIG:K", sends the signal at the K-th staged file or commit rename), under a file-size
// limit and on a full tmpfs, and with two writers on one folder: the folder holds the earlier run's files or the new
// run's, byte for byte, never a mix; a second writer is refused. Inputs and files geartopo did not write are never
// replaced. The expected states are the two runs' own results, produced without interruption.
#include "robustness_support.hpp"

#include "geartopo/files/output_folder.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <sstream>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace geartopo;
using namespace geartopo::robustness;
namespace fs = std::filesystem;

namespace output_folder_tests {

struct Result {
  int code; ///< exit code of `timeout`: 128 + signal when the program was killed
  std::string err;
};

Result run_geartopo(const std::string& args, const std::string& shell_prefix = "") {
  static int calls = 0;
  const auto err = temp_path("folders_err_" + std::to_string(calls++));
  const std::string cmd = shell_prefix + "timeout " + std::to_string(120 * GEARTOPO_TEST_TIMEOUT_FACTOR) + " " +
                          GEARTOPO_BINARY + " " + args + " >/dev/null 2>" + err.string();
  const int status = std::system(cmd.c_str());
  std::ifstream in(err);
  std::stringstream s;
  s << in.rdbuf();
  fs::remove(err);
  // A program killed by a signal: `timeout` may re-raise it, and sh may report it as 128 + signal; both are that.
  return {WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1, s.str()};
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

using Snapshot = std::map<std::string, std::string>; // relative path → content, every regular file, hidden ones too

Snapshot snapshot(const fs::path& dir) {
  Snapshot out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[e.path().lexically_relative(dir).generic_string()] = slurp(e.path());
  return out;
}

// Without what only geartopo itself looks at: the lock file and staging or commit folders.
Snapshot visible(const Snapshot& s) {
  Snapshot out;
  for (const auto& [name, text] : s)
    if (name != output::kLockName && name.rfind(".gt-", 0) != 0) out[name] = text;
  return out;
}

bool has_commit_folder(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind(".gt-commit-", 0) == 0) return true;
  return false;
}

void copy_folder(const fs::path& from, const fs::path& to) {
  fs::remove_all(to);
  fs::copy(from, to, fs::copy_options::recursive);
}

const std::string kScene = kDefaultScene.string();
// The earlier run: teeth 1 and 2 with a dense grid (linear); the new one: teeth 1 and 3 (exact). The new run replaces
// topology.csv, traces.csv and tooth 1's meshes, adds tooth 3's and removes dense.csv and tooth 2's.
const std::string kOldRun = "simulate " + kScene + " --teeth 1,2 --dense 4x4 --method linear --out ";
const std::string kNewRun = "simulate " + kScene + " --teeth 1,3 --out ";

// compensate as the issue found it mixing: the earlier result by the paper method, the new one by the flank method
// (no Monte Carlo: the write phase is the same, the run shorter).
const std::string kOldCompensation = "compensate " + kScene + " --samples 0 --method paper --out ";
const std::string kNewCompensation = "compensate " + kScene + " --samples 0 --method flank --out ";

struct Runs {
  fs::path old_dir;
  Snapshot old_files, new_files;
};

// The two runs' own results, each run once per test program: `old_run` into a fresh folder, then `new_run` into a
// copy of it.
const Runs& reference_runs(const std::string& old_run = kOldRun, const std::string& new_run = kNewRun) {
  static std::map<std::string, Runs> cache;
  const auto found = cache.find(old_run + new_run);
  if (found != cache.end()) return found->second;
  Runs r;
  r.old_dir = temp_path("folders_old_" + std::to_string(cache.size()));
  fs::remove_all(r.old_dir);
  EXPECT_EQ(run_geartopo(old_run + r.old_dir.string()).code, 0);
  r.old_files = snapshot(r.old_dir);
  const auto new_dir = temp_path("folders_new");
  copy_folder(r.old_dir, new_dir);
  EXPECT_EQ(run_geartopo(new_run + new_dir.string()).code, 0);
  r.new_files = snapshot(new_dir);
  fs::remove_all(new_dir);
  EXPECT_NE(r.old_files, r.new_files);
  return cache.emplace(old_run + new_run, std::move(r)).first->second;
}

// Interrupts `new_run` (into a copy of `old_run`'s folder) with `sig` at every `step_stride`-th step of its write
// phase, and once beyond the last step; the folder must then hold exactly one of the two runs. Returns how often
// each was found (old, new).
std::pair<int, int> interrupt_at_every_step(int sig, int step_stride, const std::string& old_run = kOldRun,
                                            const std::string& new_run = kNewRun) {
  const Runs& r = reference_runs(old_run, new_run);
  // Staged files (the new run's files and its manifest), then as many renames.
  const int steps = 2 * static_cast<int>(r.new_files.size()) + 1;
  int olds = 0, news = 0;
  const auto dir = temp_path("folders_signal_" + std::to_string(sig));
  for (int k = 1; k <= steps; k = k + step_stride > steps && k < steps ? steps : k + step_stride) {
    copy_folder(r.old_dir, dir);
    const auto result = run_geartopo(new_run + dir.string(), "GEARTOPO_TEST_SIGNAL_AT=" + std::to_string(sig) + ":" +
                                                                 std::to_string(k) + " ");
    const Snapshot now = snapshot(dir);
    const std::string where = "signal " + std::to_string(sig) + " at step " + std::to_string(k) + ", exit " +
                              std::to_string(result.code) + ": " + result.err;
    if (sig == SIGKILL) {
      // Nothing can run at a SIGKILL: the staging folder, the lock file or an unfinished commit stay, and the next
      // opening of the folder removes or completes them.
      const bool in_commit = has_commit_folder(dir);
      if (!in_commit) {
        EXPECT_TRUE(visible(now) == r.old_files || visible(now) == r.new_files) << where;
      }
      { output::OutputFolder next(dir); }
      const Snapshot after = snapshot(dir);
      EXPECT_TRUE(after == r.old_files || after == r.new_files) << where;
      if (in_commit) {
        EXPECT_EQ(after, r.new_files) << where;
      }
      olds += after == r.old_files;
      news += after == r.new_files;
    } else {
      EXPECT_TRUE(now == r.old_files || now == r.new_files) << where << " (leftovers or a mix)";
      // The handler re-raises: the status says what ended the run (beyond the last step, nothing did).
      EXPECT_EQ(result.code, k < steps ? 128 + sig : 0) << where;
      olds += now == r.old_files;
      news += now == r.new_files;
    }
  }
  fs::remove_all(dir);
  return {olds, news};
}

} // namespace output_folder_tests

using namespace output_folder_tests;

TEST(OutputFolders, ASigkillAtAnyStepLeavesTheOldOrTheNewRun) {
  const auto [olds, news] = interrupt_at_every_step(SIGKILL, 1);
  EXPECT_GT(olds, 0);
  EXPECT_GT(news, 0); // killed within the commit, completed by the next opening
}

TEST(OutputFolders, ASigtermOrSigintAtAnyStepLeavesTheOldOrTheNewRunAndNoLeftovers) {
  for (const int sig : {SIGTERM, SIGINT}) {
    const auto [olds, news] = interrupt_at_every_step(sig, 1);
    EXPECT_GT(olds, 0) << sig;
    EXPECT_GT(news, 0) << sig; // within the commit: the signal waits for its end
  }
}

// The case the issue measured: compensate into a folder that holds an earlier result, killed at every fourth step
// (two in the staging, two in the commit; SIGTERM and SIGINT are covered step by step with simulate above).
TEST(OutputFolders, CompensateKilledLeavesTheOldOrTheNewResult) {
  const auto [olds, news] = interrupt_at_every_step(SIGKILL, 4, kOldCompensation, kNewCompensation);
  EXPECT_GT(olds, 0);
  EXPECT_GT(news, 0);
}

TEST(OutputFolders, ASecondWriterIsRefusedWhileTheFirstRuns) {
  const auto dir = temp_path("folders_two_writers");
  fs::remove_all(dir);
  const pid_t first = ::fork();
  if (first == 0) {
    ::setenv("GEARTOPO_TEST_SIGNAL_AT", (std::to_string(SIGSTOP) + ":2").c_str(), 1); // stops in its write phase
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execl(GEARTOPO_BINARY, GEARTOPO_BINARY, "simulate", kScene.c_str(), "--teeth", "1", "--out", dir.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(first, &status, WUNTRACED), first);
  ASSERT_TRUE(WIFSTOPPED(status));
  const auto second = run_geartopo("simulate " + kScene + " --teeth 2 --out " + dir.string());
  EXPECT_EQ(second.code, 1) << second.err;
  EXPECT_NE(second.err.find(dir.string()), std::string::npos) << second.err;
  EXPECT_NE(second.err.find("pid " + std::to_string(first)), std::string::npos) << second.err;
  ::kill(first, SIGCONT);
  ASSERT_EQ(::waitpid(first, &status, 0), first);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const Snapshot s = snapshot(dir);
  EXPECT_EQ(s.count("meshes/tooth01_left.ply"), 1u);
  EXPECT_EQ(s.count("meshes/tooth02_left.ply"), 0u);
  EXPECT_EQ(s.count(output::kLockName), 0u);
  // The lock of a killed writer is free by itself.
  EXPECT_EQ(run_geartopo("simulate " + kScene + " --teeth 2 --out " + dir.string(), "GEARTOPO_TEST_SIGNAL_AT=9:1 ").code, 137);
  EXPECT_EQ(run_geartopo("simulate " + kScene + " --teeth 2 --out " + dir.string()).code, 0);
  fs::remove_all(dir);
}

TEST(OutputFolders, AFileSizeLimitFailsCleanlyNamingTheFile) {
  const Runs& r = reference_runs();
  const auto dir = temp_path("folders_fsize");
  copy_folder(r.old_dir, dir);
  // dense.csv of 4 flanks at 100×100 is far beyond 64 blocks (32 or 64 KiB); the meshes and the other files may be too.
  const auto result = run_geartopo("simulate " + kScene + " --teeth 1,2 --dense 100x100 --out " + dir.string(), "ulimit -f 64; ");
  EXPECT_EQ(result.code, 1) << result.err;
  EXPECT_NE(result.err.find(dir.string() + "/"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("File too large"), std::string::npos) << result.err;
  EXPECT_EQ(snapshot(dir), r.old_files); // no temporary, no staging folder, no lock; the earlier files intact
  fs::remove_all(dir);
}

TEST(OutputFolders, AFullDiskFailsCleanlyNamingTheFile) {
  if (::geteuid() != 0) GTEST_SKIP() << "a full disk needs a small tmpfs, and mounting one needs root (id -u = 0)";
  const auto mnt = temp_path("folders_tmpfs");
  fs::create_directories(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=1m") != 0) {
    fs::remove_all(mnt);
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << "), e.g. in a container without CAP_SYS_ADMIN";
  }
  const Runs& r = reference_runs();
  const auto dir = mnt / "out";
  fs::copy(r.old_dir, dir, fs::copy_options::recursive);
  const auto result = run_geartopo("simulate " + kScene + " --teeth 1,2 --dense 100x100 --out " + dir.string());
  EXPECT_EQ(result.code, 1) << result.err;
  EXPECT_NE(result.err.find(dir.string() + "/"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("No space left on device"), std::string::npos) << result.err;
  EXPECT_EQ(snapshot(dir), r.old_files);
  ::umount(mnt.c_str());
  fs::remove_all(mnt);
}

TEST(OutputFolders, AnInputIsNeverReplaced) {
  const auto dir = temp_path("folders_inputs");
  fs::remove_all(dir);
  fs::create_directories(dir);
  // compare S --measured D/residuals.csv --out D: refused before any work, both paths named.
  ASSERT_EQ(run_geartopo("synth " + kScene + " --teeth 1 --out " + (dir / "m.csv").string()).code, 0);
  ASSERT_EQ(run_geartopo("compare " + kScene + " --measured " + (dir / "m.csv").string() + " --out " + (dir / "D").string()).code, 0);
  const auto residuals = dir / "D" / "residuals.csv";
  const std::string before = slurp(residuals);
  const auto r = run_geartopo("compare " + kScene + " --measured " + residuals.string() + " --out " + (dir / "D").string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("an input of this run"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(residuals.string() + ": cannot write: it is " + residuals.string()), std::string::npos) << r.err;
  EXPECT_EQ(slurp(residuals), before);
  // synth s.yaml --out s.yaml
  const auto scene = dir / "s.yaml";
  fs::copy_file(kDefaultScene, scene);
  fs::copy(kDefaultScene.parent_path() / "machine", dir / "machine", fs::copy_options::recursive); // its error tables
  const auto s = run_geartopo("synth " + scene.string() + " --out " + scene.string());
  EXPECT_EQ(s.code, 1) << s.err;
  EXPECT_NE(s.err.find("an input of this run"), std::string::npos) << s.err;
  EXPECT_EQ(slurp(scene), slurp(kDefaultScene));
  fs::remove_all(dir);
}

TEST(OutputFolders, AFileGeartopoDidNotWriteIsNeverReplaced) {
  const auto dir = temp_path("folders_user_file");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "prediction.txt") << "my own notes\n";
  const auto r = run_geartopo("compensate " + kScene + " --out " + dir.string()); // refused before any work
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find((dir / "prediction.txt").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((dir / output::kManifestName).string()), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir / "prediction.txt"), "my own notes\n");
  EXPECT_EQ(snapshot(dir).size(), 1u);
  fs::remove_all(dir);
}

TEST(OutputFolders, LongNamesAndAFileNamedAsAFolderGetAClearMessage) {
  const auto dir = temp_path("folders_names");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto legal = dir / (std::string(246, 'm') + ".csv"); // 250 bytes: NAME_MAX is 255
  EXPECT_EQ(run_geartopo("synth " + kScene + " --teeth 1 --out " + legal.string()).code, 0);
  EXPECT_TRUE(fs::is_regular_file(legal));
  const auto too_long = run_geartopo("synth " + kScene + " --teeth 1 --out " + (dir / (std::string(300, 'm') + ".csv")).string());
  EXPECT_EQ(too_long.code, 1) << too_long.err;
  EXPECT_NE(too_long.err.find("more than the 255"), std::string::npos) << too_long.err;
  const auto too_long_folder = run_geartopo("compare " + kScene + " --measured " + legal.string() + " --out " +
                                        (dir / std::string(300, 'f')).string());
  EXPECT_EQ(too_long_folder.code, 1) << too_long_folder.err;
  EXPECT_NE(too_long_folder.err.find("more than the 255"), std::string::npos) << too_long_folder.err;
  std::ofstream(dir / "FILE") << "x\n";
  const auto file_as_folder = run_geartopo("synth " + kScene + " --teeth 1 --out " + (dir / "FILE").string() + "/");
  EXPECT_EQ(file_as_folder.code, 1) << file_as_folder.err;
  EXPECT_NE(file_as_folder.err.find("is a file, not a folder"), std::string::npos) << file_as_folder.err;
  for (const auto* r : {&too_long, &too_long_folder, &file_as_folder})
    EXPECT_EQ(r->err.find("filesystem error"), std::string::npos) << r->err;
  fs::remove_all(dir);
}

// The folder is opened (created, locked) before the computation; a run that then fails removes the folder it created,
// and the parent folders it created with it. Review of issue 31, item 4: after a bad scene the parent "new/" stayed;
// after a SIGTERM "new/D" stayed, with "meshes/" in it (item 3: made outside the staging folder).
TEST(OutputFolders, AFailedRunLeavesNoFolderItCreated) {
  const auto dir = temp_path("folders_failed_new");
  fs::remove_all(dir);
  const auto r = run_geartopo("simulate " + (kCorpus / "scenes" / "module_0.yaml").string() + " --out " + dir.string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_FALSE(fs::exists(dir));
  const auto nested = run_geartopo("simulate " + (kCorpus / "scenes" / "module_0.yaml").string() + " --out " +
                                   (dir / "new" / "D").string());
  EXPECT_EQ(nested.code, 1) << nested.err;
  EXPECT_FALSE(fs::exists(dir)) << "a failed run left the parent folders it created";
  const auto term = run_geartopo("simulate " + kScene + " --teeth 1 --method linear --out " + (dir / "new" / "D").string(),
                                 "GEARTOPO_TEST_SIGNAL_AT=" + std::to_string(SIGTERM) + ":3 ");
  EXPECT_EQ(term.code, 128 + SIGTERM) << term.err;
  EXPECT_FALSE(fs::exists(dir)) << "an interrupted run left the folders it created";
}

// Review of issue 31, item 3: a folder a commit leaves empty goes (meshes/ after a run into the folder that writes no
// meshes); the run's files appear only with its commit.
TEST(OutputFolders, ARunThatWritesNoMeshesLeavesNoEmptyMeshesFolder) {
  const auto dir = temp_path("folders_no_meshes");
  fs::remove_all(dir);
  ASSERT_EQ(run_geartopo("simulate " + kScene + " --teeth 1 --method linear --out " + dir.string()).code, 0);
  ASSERT_TRUE(fs::is_directory(dir / "meshes"));
  const auto r = run_geartopo("evaluate " + kScene + " --traces " + (dir / "traces.csv").string() + " --out " + dir.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "meshes"));
  EXPECT_TRUE(fs::exists(dir / "traces.csv")); // read by the run: kept
  EXPECT_TRUE(fs::exists(dir / "iso1328.json"));
  fs::remove_all(dir);
}

// Review of issue 31, item 5: a writer killed within its commit leaves a mix; a reader then refuses the folder and
// says how to complete it, and that advice works.
TEST(OutputFolders, AReaderRefusesAFolderWhoseCommitWasInterrupted) {
  const auto dir = temp_path("folders_reader"), other = temp_path("folders_reader_out");
  fs::remove_all(dir);
  fs::remove_all(other);
  // simulate --teeth 1 stages 5 files (4 and the manifest); its 7th step is the 2nd rename of the commit.
  const auto killed = run_geartopo("simulate " + kScene + " --teeth 1 --method linear --out " + dir.string(),
                                   "GEARTOPO_TEST_SIGNAL_AT=" + std::to_string(SIGKILL) + ":7 ");
  ASSERT_EQ(killed.code, 128 + SIGKILL) << killed.err;
  ASSERT_TRUE(has_commit_folder(dir));
  const std::string evaluate = "evaluate " + kScene + " --traces " + (dir / "traces.csv").string() + " --out ";
  const auto refused = run_geartopo(evaluate + other.string());
  EXPECT_EQ(refused.code, 1) << refused.err;
  EXPECT_NE(refused.err.find("unfinished geartopo commit"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--out " + dir.string()), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(other));
  const auto completed = run_geartopo(evaluate + dir.string()); // the advice: a run into the folder completes it
  EXPECT_EQ(completed.code, 0) << completed.err;
  EXPECT_FALSE(has_commit_folder(dir));
  EXPECT_EQ(run_geartopo(evaluate + other.string()).code, 0);
  fs::remove_all(dir);
  fs::remove_all(other);
}

// Review of issue 31, item 6: a run started with SIGHUP ignored (nohup, `trap '' HUP`) is not ended by a SIGHUP.
TEST(OutputFolders, AnIgnoredSighupDoesNotEndTheRun) {
  const auto dir = temp_path("folders_nohup");
  fs::remove_all(dir);
  const pid_t child = ::fork();
  if (child == 0) {
    std::signal(SIGHUP, SIG_IGN);
    ::setenv("GEARTOPO_TEST_SIGNAL_AT", (std::to_string(SIGHUP) + ":1").c_str(), 1);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execl(GEARTOPO_BINARY, GEARTOPO_BINARY, "simulate", kScene.c_str(), "--teeth", "1", "--method", "linear", "--out",
            dir.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_TRUE(fs::exists(dir / "meshes" / "tooth01_left.ply"));
  fs::remove_all(dir);
}
