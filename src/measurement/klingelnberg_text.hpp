// geartopo — the text rules shared by the readers of Klingelnberg-style exports (the curve file .mka, klingelnberg.cpp,
// and the value file .mew, klingelnberg_values.cpp): encodings, tokens, numbers with one decimal separator per file,
// numbered header lines (docs/measurement-formats.md, "Text"). Private to the measurement library.
#pragma once

#include "geartopo/core/text_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::measurement::kl_text {

// Valid UTF-8 (so a file without BOM but with "ä" as two bytes is UTF-8); else the text is latin-1.
inline bool is_utf8(std::string_view s) {
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const int n = c < 0x80 ? 0 : (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2 : (c & 0xF8) == 0xF0 ? 3 : -1;
    if (n < 0) return false;
    for (int k = 1; k <= n; ++k)
      if (i + k >= s.size() || (static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
    i += static_cast<size_t>(n) + 1;
  }
  return true;
}

inline std::string latin1_to_utf8(std::string_view s) {
  std::string out;
  out.reserve(s.size() + s.size() / 8);
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// Fields are separated by blanks or ';' (exports with decimal commas).
inline std::vector<std::string_view> tokens(std::string_view s, std::string_view separators = " \t;") {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && separators.find(s[i]) != std::string_view::npos) ++i;
    const size_t start = i;
    while (i < s.size() && separators.find(s[i]) == std::string_view::npos) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

// A finite number written with '.' or with ',' as its decimal separator (which one the file uses is checked where a
// number is read: DecimalMark).
inline std::optional<double> number(std::string_view s) {
  double v = 0.0;
  std::string dotted;
  if (s.find(',') != std::string_view::npos) {
    if (s.find('.') != std::string_view::npos) return std::nullopt;
    dotted.assign(s);
    std::replace(dotted.begin(), dotted.end(), ',', '.');
    s = dotted;
  }
  if (text::parse_number(s, v) != std::errc() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// The 1-based character column of `tok` in `line` (a view into it): UTF-8 continuation bytes do not count, so a
// column after "Zähnezahl" is where an editor shows it.
inline int column_of(std::string_view line, std::string_view tok) {
  const auto before = line.substr(0, static_cast<size_t>(tok.data() - line.data()));
  return 1 + static_cast<int>(std::count_if(before.begin(), before.end(), [](char c) {
           return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
         }));
}

// The file's decimal separator, one for the whole file: '.' or ',' (German exports), decided by the first number the
// reader uses that is written with one (docs/measurement-formats.md, "Text").
struct DecimalMark {
  char mark = 0; ///< 0 until decided
  int line = 0;
  std::string token;
};

// Why `tok` is not a number of this file, or "" when it is one (and then `value` holds it; the first number written
// with a separator decides the file's).
inline std::string read_number(std::string_view tok, int ln, DecimalMark& d, double& value) {
  const bool comma = tok.find(',') != std::string_view::npos, dot = tok.find('.') != std::string_view::npos;
  const auto v = number(tok);
  if (!v) return fmt::format("'{}' is not a number", text::excerpt(tok));
  if (comma || dot) {
    const char mark = comma ? ',' : '.';
    if (d.mark == 0) d = {mark, ln, std::string(text::excerpt(tok))};
    if (d.mark != mark)
      return fmt::format("'{}' has a decimal {}, but this file's numbers have a decimal {} (the first, '{}', at line {}): "
                         "one decimal separator for the whole file",
                         text::excerpt(tok), comma ? "comma" : "point", comma ? "point" : "comma", d.token, d.line);
  }
  value = *v;
  return {};
}

// What the message of a bad number adds: how numbers are written.
inline constexpr const char* kNumberRule = "numbers are written 1.5, -.046 or 1e-3 (1,5 and -,046 throughout a file with decimal "
                                    "commas)";

inline std::optional<int> whole(std::string_view s) {
  int v = 0;
  if (text::parse_number(s, v) != std::errc()) return std::nullopt;
  return v;
}

// "  21 :Normalmodul mn [mm]......: 2.5" → code 21.
inline std::optional<int> header_code(std::string_view line, std::string_view& rest) {
  const auto t = trim(line);
  size_t i = 0;
  while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
  if (i == 0 || i > 4) return std::nullopt;
  size_t j = i;
  while (j < t.size() && t[j] == ' ') ++j;
  if (j >= t.size() || t[j] != ':') return std::nullopt;
  rest = t.substr(j + 1);
  return whole(t.substr(0, i));
}

inline std::string strip_leaders(std::string_view label) {
  std::string s(trim(label));
  while (!s.empty() && (s.back() == '.' || s.back() == ' ')) s.pop_back();
  // Dot leaders inside ("Messbereich.....da") become one space.
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '.' && i + 1 < s.size() && s[i + 1] == '.') {
      while (i + 1 < s.size() && s[i + 1] == '.') ++i;
      out += ' ';
    } else {
      out += s[i];
    }
  }
  return out;
}

} // namespace geartopo::measurement::kl_text
