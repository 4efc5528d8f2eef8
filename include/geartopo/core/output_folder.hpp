// geartopo — the folder a command writes its outputs into (`--out DIR`). A command's folder holds exactly what its
// last run produced: files that an earlier geartopo run wrote there and this run did not write again (an old
// diagnosis.png, a dense.csv of an earlier --dense run) are removed when the run succeeds, so no figure or table from
// an earlier run can be mistaken for this one's. What geartopo wrote is recorded in the folder's manifest
// (kManifestName, one path per line relative to the folder); files geartopo never wrote are never touched.
// Temporaries of killed geartopo processes (".name.tmp-PID-N.ext", see atomic_file.hpp) are removed on opening.
#pragma once

#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace geartopo::output {

inline constexpr const char* kManifestName = ".geartopo-outputs";

class OutputFolder {
public:
  /// Creates `dir` (and its parents) if needed, and removes the temporaries left by geartopo processes that no
  /// longer run. Throws OutputError when `dir` cannot be created or is not a folder.
  explicit OutputFolder(const std::filesystem::path& dir);
  /// Without finish() (the run failed): the manifest becomes the union of the old one and what this run wrote, so the
  /// next successful run still knows every file geartopo left here. Never throws.
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::filesystem::path& path() const noexcept { return dir_; }

  /// The run succeeded: removes the files the manifest lists that this run did not write, and writes the manifest of
  /// this run. Returns the removed files (relative to the folder), for the command's message.
  std::vector<std::filesystem::path> finish();

  /// The stale temporaries removed when the folder was opened (relative paths).
  const std::vector<std::filesystem::path>& removed_temporaries() const noexcept { return removed_temporaries_; }

private:
  std::set<std::filesystem::path> written_here() const;
  void write_manifest(const std::set<std::filesystem::path>& files) const;

  std::filesystem::path dir_;
  std::size_t written_before_ = 0; ///< files_written().size() when the folder was opened
  std::set<std::filesystem::path> previous_;
  std::vector<std::filesystem::path> removed_temporaries_;
  bool finished_ = false;
};

/// True for a name made by atomic_file's temporary_for (".stem.tmp-PID-N.ext"); `pid` receives PID.
bool is_geartopo_temporary(const std::string& filename, long& pid);

} // namespace geartopo::output
