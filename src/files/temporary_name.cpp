// The temporaries' names: made (temporary_for) and recognised (is_geartopo_temporary) in one place.
#include "temporary_name.hpp"

#include "geartopo/files/output_folder.hpp"

#include <atomic>
#include <cctype>
#include <string>
#include <unistd.h>

namespace geartopo::output {

namespace detail {

std::filesystem::path temporary_for(const std::filesystem::path& file) {
  static std::atomic<unsigned> counter{0};
  std::string name = ".gt-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  const std::string ext = file.extension().string();
  if (ext.size() <= 16) name += ext;
  return file.parent_path() / name;
}

} // namespace detail

bool is_geartopo_temporary(const std::string& name, long& pid) {
  // ".gt-<pid>-<n><ext>" only: the ".<stem>.tmp-<pid>-<n><ext>" names of earlier versions also match users' files
  // (".notes.tmp-2024-11.md"), and a clean-up must never take one of those.
  if (name.rfind(".gt-", 0) != 0) return false;
  std::size_t i = 4, digits = 0;
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

} // namespace geartopo::output
