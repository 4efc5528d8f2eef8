// geartopo — the one error of every writer: a file that could not be written (atomic_write.hpp, output_folder.hpp).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace geartopo::output {

/// A file could not be written; what() is "<file>: cannot write: <reason>".
class OutputError : public std::runtime_error {
public:
  OutputError(const std::filesystem::path& file, const std::string& reason);
  const std::filesystem::path& file() const noexcept { return file_; }

private:
  std::filesystem::path file_;
};

} // namespace geartopo::output
