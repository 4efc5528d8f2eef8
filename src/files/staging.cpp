// The staging of the open OutputFolder as the writers see it (staging.hpp), and what writers ask of it
// (atomic_write.hpp: current_location, create_folders_for).
#include "staging.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_registry.hpp"
#include "geartopo/files/output_folder.hpp"

#include <map>
#include <mutex>
#include <sys/stat.h>
#include <system_error>
#include <utility>

namespace geartopo::output {

namespace fs = std::filesystem;

namespace {

// The folder being staged: writes below `dir` go to `stage`.
struct Staging {
  bool active = false;
  fs::path dir, stage;
  std::set<fs::path> replaceable;
  std::map<fs::path, fs::path> staged; // final (absolute, normal) → staged copy
};
std::mutex staging_mutex;
Staging& staging_state() {
  static Staging s;
  return s;
}

fs::path absolute_normal(const fs::path& file) {
  std::error_code ec;
  fs::path p = fs::absolute(file, ec);
  if (ec) p = file;
  return p.lexically_normal();
}

} // namespace

namespace detail {

void begin_staging(const fs::path& dir, const fs::path& stage, std::set<fs::path> replaceable) {
  const std::lock_guard lock(staging_mutex);
  Staging& s = staging_state();
  // One folder per command: a second would take the first one's writes.
  if (s.active) throw OutputError(dir, "another output folder (" + s.dir.string() + ") is open in this process");
  s.active = true;
  s.dir = dir;
  s.stage = stage;
  s.replaceable = std::move(replaceable);
  s.staged.clear();
}

std::set<fs::path> end_staging() {
  std::set<fs::path> out;
  const std::lock_guard lock(staging_mutex);
  Staging& s = staging_state();
  for (const auto& [file, staged] : s.staged) out.insert(file.lexically_relative(s.dir));
  s = Staging{};
  return out;
}

// (Without an open folder, in a library or a test, "this run" is not defined: a file read earlier may be written
// again, as before.)
fs::path destination_for(const fs::path& file) {
  const std::lock_guard lock(staging_mutex);
  Staging& s = staging_state();
  if (!s.active) return file;
  check_not_an_input(file);
  const fs::path abs = absolute_normal(file);
  const fs::path rel = abs.lexically_relative(s.dir);
  if (rel.empty() || *rel.begin() == ".." || rel == ".") return file;
  if (*rel.begin() == s.stage.filename()) return file; // the staging folder itself (the manifest written by finish)
  struct stat st {};
  if (s.replaceable.count(rel) == 0 && ::lstat(abs.c_str(), &st) == 0) throw OutputError(file, foreign_file_reason(s.dir));
  const fs::path staged = s.stage / rel;
  std::error_code ec;
  fs::create_directories(staged.parent_path(), ec);
  if (ec) throw OutputError(file, "cannot create its staging folder: " + ec.message());
  return staged;
}

void record_staged(const fs::path& file, const fs::path& staged) {
  if (staged == file) return;
  const std::lock_guard lock(staging_mutex);
  staging_state().staged[absolute_normal(file)] = staged;
}

std::string foreign_file_reason(const fs::path& dir) {
  std::string reason = "a file geartopo did not write is there (it is not listed in ";
  reason += (dir / kManifestName).string();
  reason += "): geartopo never replaces it; move it away or choose another --out";
  return reason;
}

} // namespace detail

fs::path current_location(const fs::path& file) {
  const std::lock_guard lock(staging_mutex);
  const auto& staged = staging_state().staged;
  const auto it = staged.find(absolute_normal(file));
  return it != staged.end() ? it->second : file;
}

void create_folders_for(const fs::path& dir) {
  {
    const std::lock_guard lock(staging_mutex);
    const Staging& s = staging_state();
    if (s.active) {
      const fs::path rel = absolute_normal(dir).lexically_relative(s.dir);
      if (!rel.empty() && *rel.begin() != "..") return; // staged writes make their folders in the staging folder
    }
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw OutputError(dir, "cannot create the folder: " + ec.message());
}

} // namespace geartopo::output
