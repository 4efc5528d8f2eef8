// geartopo tests — the hand-written example files of tests/measurement/data as text (bytes as stored: BOM, CRLF), and
// that text with one passage replaced, for readers' tests that change one thing at a time.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace geartopo::test {

inline std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// `text` with the first `from` replaced by `to`; a `from` not in the text fails the test (and returns it unchanged).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

} // namespace geartopo::test
