#include "geartopo/files/input_file.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/core/limits.hpp"
#include "geartopo/files/input_registry.hpp"
#include "geartopo/files/output_folder.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <sstream>
#include <sys/stat.h>

namespace geartopo::input {

namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& message) {
  throw InputError(file.string(), 0, 0, "", message);
}

} // namespace

std::uintmax_t check_regular_file(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what) {
  if (file.empty()) throw InputError(std::string("\"\""), 0, 0, "", fmt::format("an empty name is not a {}", what));
  // A NUL ends the C string stat() and open() are given: "m.csv\0.bak" would read m.csv.
  limits::require(limits::path_refusal(file.native()), what);
  // A folder whose commit is unfinished holds files of two runs (output_folder.hpp); a reader must not write, so it
  // refuses and says how the folder is completed.
  const std::filesystem::path folder = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  if (const std::string commit = output::unfinished_commit(folder); !commit.empty())
    fail(file, fmt::format("its folder {} holds an unfinished geartopo commit ({}), so its files are a mix of two "
                           "runs: run any geartopo command with --out {} to complete the commit (that is done "
                           "before the command's work), then read it again",
                           folder.string(), commit, folder.string()));
  // stat(), not std::filesystem::status: the same call gives the type and the size, and its errno names the cause.
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) {
    const int err = errno;
    fail(file, err == ENOENT ? fmt::format("cannot open the {}: it does not exist", what)
                             : fmt::format("cannot open the {}: {}", what, std::strerror(err)));
  }
  if (S_ISDIR(st.st_mode)) fail(file, fmt::format("is a directory, not a {}", what));
  if (S_ISFIFO(st.st_mode)) fail(file, fmt::format("is a FIFO (named pipe), not a regular {}", what));
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) fail(file, fmt::format("is a device, not a regular {}", what));
  if (S_ISSOCK(st.st_mode)) fail(file, fmt::format("is a socket, not a regular {}", what));
  if (!S_ISREG(st.st_mode)) fail(file, fmt::format("is not a regular file (a {} was expected)", what));
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > max_bytes)
    fail(file, fmt::format("is {} bytes, more than the {} bytes a {} may have", size, max_bytes, what));
  output::note_input(file); // no output of this run may replace it (input_registry.hpp)
  return size;
}

std::ifstream open_input_file(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what) {
  check_regular_file(file, max_bytes, what);
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, fmt::format("cannot open the {}: {}", what, std::strerror(errno)));
  return in;
}

std::string read_input_file(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what) {
  const std::uintmax_t size = check_regular_file(file, max_bytes, what);
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, fmt::format("cannot open the {}: {}", what, std::strerror(errno)));
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  // A file that shrank since the check reads short; one that grew would be read cut at the checked size.
  text.resize(static_cast<size_t>(in.gcount()));
  if (in.bad()) fail(file, fmt::format("read error in the {}", what));
  if (in && in.peek() != std::ifstream::traits_type::eof()) fail(file, fmt::format("the {} grew while it was read", what));
  return text;
}

} // namespace geartopo::input
