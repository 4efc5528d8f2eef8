// geartopo — opening an input file: only a regular file, of at most a documented size, checked before anything is
// read. A directory, a device (/dev/zero, /dev/urandom), a FIFO or a socket named as a scene or a measurement used to
// hang a reader or give a misleading message ("empty scene", "missing header"); every reader opens its file through
// here and so refuses them by name (docs/performance.md, "Input bounds").
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace geartopo::input {

// Byte bounds of the inputs, each far above any real file of its kind and far below what could exhaust memory.
inline constexpr std::uintmax_t kMiB = std::uintmax_t{1} << 20;
inline constexpr std::uintmax_t kMaxSceneBytes = 1 * kMiB;        ///< a scene is a page of YAML (read whole)
inline constexpr std::uintmax_t kMaxErrorTableBytes = 16 * kMiB;  ///< ~10⁵ rows of 43 components (read whole)
inline constexpr std::uintmax_t kMaxMeasurementBytes = 2048 * kMiB; ///< 2 GiB, ~6·10⁷ points (streamed line by line)

/// Checks that `file` is a regular file (symbolic links followed) of at most `max_bytes` and returns its size. Throws
/// geartopo::InputError naming the file otherwise: "cannot open the <what>: it does not exist", "is a directory, not a <what>", "is a FIFO / a
/// device / a socket, not a regular <what>", "is N bytes, more than the M bytes a <what> may have", and when its folder
/// holds an unfinished geartopo commit (output::unfinished_commit: the folder's files are a mix of two runs).
std::uintmax_t check_regular_file(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what);

/// check_regular_file, then opens it (binary). Throws InputError when it cannot be opened (permissions).
std::ifstream open_input_file(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what);

/// check_regular_file, then reads it whole; throws InputError on a read error.
std::string read_input_file(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what);

} // namespace geartopo::input
