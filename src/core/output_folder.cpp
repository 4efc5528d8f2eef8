#include "geartopo/core/output_folder.hpp"

#include "geartopo/core/atomic_file.hpp"

#include <cctype>
#include <cerrno>
#include <csignal>
#include <fstream>
#include <sstream>
#include <sys/types.h>
#include <unistd.h>

namespace geartopo::output {

namespace fs = std::filesystem;

namespace {

// A process that cannot be signalled because it does not exist (ESRCH) is dead; EPERM means it exists.
bool process_alive(long pid) {
  if (pid <= 0) return false;
  if (pid == static_cast<long>(::getpid())) return true;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

std::set<fs::path> read_manifest(const fs::path& file) {
  std::set<fs::path> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line.front() == '#') continue;
    const fs::path rel = fs::path(line).lexically_normal();
    // Only plain relative paths inside the folder: a hand-edited manifest naming "../x" or "/etc/x" is ignored.
    if (rel.is_absolute() || rel.empty() || *rel.begin() == "..") continue;
    out.insert(rel);
  }
  return out;
}

} // namespace

bool is_geartopo_temporary(const std::string& name, long& pid) {
  // ".<stem>.tmp-<pid>-<n><ext>"
  if (name.size() < 8 || name.front() != '.') return false;
  const auto at = name.rfind(".tmp-");
  if (at == std::string::npos || at == 0) return false;
  std::size_t i = at + 5, digits = 0;
  long value = 0;
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i])) && digits < 10)
    value = value * 10 + (name[i++] - '0'), ++digits;
  if (digits == 0 || i >= name.size() || name[i] != '-') return false;
  ++i;
  std::size_t counter_digits = 0;
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i]))) ++i, ++counter_digits;
  if (counter_digits == 0) return false;
  if (i < name.size() && name[i] != '.') return false;
  pid = value;
  return true;
}

OutputFolder::OutputFolder(const fs::path& dir) : dir_(dir) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (!fs::is_directory(dir_)) throw OutputError(dir_, ec ? "cannot create the folder: " + ec.message() : "it is not a folder");
  dir_ = fs::absolute(dir_).lexically_normal();
  written_before_ = files_written().size();
  previous_ = read_manifest(dir_ / kManifestName);
  // Leftovers of killed runs: in the folder and one level below (meshes/), never following links.
  for (auto it = fs::recursive_directory_iterator(dir_, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it.depth() > 1) it.disable_recursion_pending();
    long pid = 0;
    if (!it->is_regular_file(ec) || !is_geartopo_temporary(it->path().filename().string(), pid)) continue;
    if (process_alive(pid)) continue;
    std::error_code rm;
    if (fs::remove(it->path(), rm)) removed_temporaries_.push_back(it->path().lexically_relative(dir_));
  }
}

std::set<fs::path> OutputFolder::written_here() const {
  std::set<fs::path> out;
  const auto all = files_written();
  for (std::size_t i = written_before_; i < all.size(); ++i) {
    const fs::path rel = all[i].lexically_relative(dir_);
    if (!rel.empty() && *rel.begin() != ".." && rel != kManifestName) out.insert(rel);
  }
  return out;
}

void OutputFolder::write_manifest(const std::set<fs::path>& files) const {
  std::ostringstream text;
  text << "# geartopo: the files its last run wrote into this folder (relative paths). Files listed here that a later\n"
          "# run does not write are removed by that run; nothing else in the folder is ever touched.\n";
  for (const auto& f : files) text << f.generic_string() << "\n";
  write_text_atomically(dir_ / kManifestName, text.str());
}

std::vector<fs::path> OutputFolder::finish() {
  finished_ = true;
  const auto now = written_here();
  std::vector<fs::path> removed;
  for (const auto& old : previous_) {
    if (now.count(old) != 0) continue;
    std::error_code ec;
    const fs::path p = dir_ / old;
    if (fs::is_regular_file(fs::symlink_status(p, ec)) && fs::remove(p, ec)) removed.push_back(old);
  }
  write_manifest(now);
  return removed;
}

OutputFolder::~OutputFolder() {
  if (finished_) return;
  try {
    auto all = previous_;
    const auto now = written_here();
    all.insert(now.begin(), now.end());
    if (!now.empty()) write_manifest(all);
  } catch (...) {
    // A failed run whose folder cannot even take the manifest: the files it wrote stay, unlisted.
  }
}

} // namespace geartopo::output
