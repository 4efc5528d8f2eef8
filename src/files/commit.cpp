// An output folder's manifest and the completion of its commit (commit.hpp).
#include "commit.hpp"

#include "signal_cleanup.hpp"

#include "geartopo/files/output_folder.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace geartopo::output {

namespace fs = std::filesystem;

namespace detail {

namespace {

/// The regular files of `commit` but its manifest (relative paths); `ec` set when the folder cannot be read.
std::vector<fs::path> files_to_move_in(const fs::path& commit, std::error_code& ec) {
  std::vector<fs::path> files;
  for (auto it = fs::recursive_directory_iterator(commit, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const fs::path rel = it->path().lexically_relative(commit);
    if (it->is_regular_file(ec) && rel != kManifestName) files.push_back(rel);
  }
  return files;
}

/// Removes the files `before` lists and `after` does not (regular files only), and the subfolders that leaves
/// empty; returns what was removed.
std::vector<fs::path> remove_earlier_files(const fs::path& dir, const std::set<fs::path>& before,
                                           const std::set<fs::path>& after) {
  std::vector<fs::path> removed;
  for (const auto& old : before) {
    if (after.count(old) != 0) continue;
    std::error_code rm;
    const fs::path p = dir / old;
    if (!fs::is_regular_file(fs::symlink_status(p, rm)) || !fs::remove(p, rm)) continue;
    removed.push_back(old);
    // A subfolder that held only geartopo's files goes with them (meshes/ of a run that wrote no meshes this time);
    // rmdir removes only an empty folder, so one holding anything else, the user's files, stays.
    for (fs::path sub = old.parent_path(); !sub.empty(); sub = sub.parent_path())
      if (::rmdir((dir / sub).c_str()) != 0) break;
  }
  return removed;
}

} // namespace

std::set<fs::path> read_manifest(const fs::path& file) {
  std::set<fs::path> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line.front() == '#') continue;
    const fs::path rel = fs::path(line).lexically_normal();
    if (rel.is_absolute() || rel.empty() || *rel.begin() == "..") continue;
    out.insert(rel);
  }
  return out;
}

std::string manifest_text(const std::set<fs::path>& files) {
  std::ostringstream text;
  text << "# geartopo: the files its last run wrote into this folder (relative paths). Files listed here that a later\n"
          "# run does not write are removed by that run (and a subfolder that leaves empty); nothing else in the folder\n"
          "# is touched.\n";
  for (const auto& f : files) text << f.generic_string() << "\n";
  return text.str();
}

void sync_folder(const fs::path& dir) noexcept {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

std::vector<fs::path> complete_commit(const fs::path& dir, const fs::path& commit) {
  std::error_code ec;
  if (!fs::exists(commit / kManifestName, ec)) { // moved last: every other step is done
    fs::remove_all(commit, ec);
    return {};
  }
  const auto before = read_manifest(dir / kManifestName);
  const auto after = read_manifest(commit / kManifestName);
  const std::vector<fs::path> files = files_to_move_in(commit, ec);
  // A failure here (a full disk: a rename that must grow the folder fails with ENOSPC) leaves the folder a mix of
  // the two runs; the commit folder stays, readers refuse the folder (input_file.hpp), the next run completes it.
  const auto unfinished = [&](const std::string& what) {
    std::string reason = what;
    reason += "; the folder now holds files of two runs: the next geartopo run with --out ";
    reason += dir.string();
    reason += " completes this commit (";
    reason += commit.filename().string();
    reason += "), and until then geartopo refuses to read from the folder";
    return reason;
  };
  if (ec) throw OutputError(commit, unfinished("cannot read the files to move in: " + ec.message()));
  for (const auto& rel : files) {
    const fs::path target = dir / rel;
    std::error_code mk;
    fs::create_directories(target.parent_path(), mk);
    if (::rename((commit / rel).c_str(), target.c_str()) != 0) throw OutputError(target, unfinished(std::strerror(errno)));
    write_step();
  }
  std::vector<fs::path> removed = remove_earlier_files(dir, before, after);
  if (::rename((commit / kManifestName).c_str(), (dir / kManifestName).c_str()) != 0)
    throw OutputError(dir / kManifestName, unfinished(std::strerror(errno)));
  write_step();
  fs::remove_all(commit, ec);
  sync_folder(dir);
  return removed;
}

} // namespace detail

std::string unfinished_commit(const fs::path& folder) {
  std::error_code ec;
  for (auto it = fs::directory_iterator(folder, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(detail::kCommitPrefix, 0) == 0) return name;
  }
  return {};
}

} // namespace geartopo::output
