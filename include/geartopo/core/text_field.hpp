// geartopo — the one rule for numbers, fields and quoted fields in every text file geartopo reads (scene YAML, error
// tables, topology and traces CSV, point clouds, corrections), so that a file one reader accepts the others read the
// same way.
// Header-only; no units (the callers know theirs).
#pragma once

#include <charconv>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace geartopo::text {

inline constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

/// Removes a leading UTF-8 byte-order mark (Excel's "CSV UTF-8" writes one); true if there was one.
inline bool strip_bom(std::string_view& s) {
  if (s.substr(0, kUtf8Bom.size()) != kUtf8Bom) return false;
  s.remove_prefix(kUtf8Bom.size());
  return true;
}

/// Parses the whole of `s` as a number (double or integer) with std::from_chars (locale-free, exact round trip).
/// One leading '+' is allowed before a digit or '.', as C and spreadsheets write it; "+-5", "++5" and "+" are not
/// numbers. Returns std::errc{} on success, result_out_of_range, or invalid_argument (empty, trailing characters …).
template <class T>
std::errc parse_number(std::string_view s, T& value) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (s.empty() || !((s.front() >= '0' && s.front() <= '9') || s.front() == '.')) return std::errc::invalid_argument;
  }
  if (s.empty()) return std::errc::invalid_argument;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc()) return ec;
  return end == s.data() + s.size() ? std::errc() : std::errc::invalid_argument;
}

/// At most `bytes` bytes of `s`, cut back to a UTF-8 character boundary (never half a 'µ').
inline std::string_view utf8_prefix(std::string_view s, size_t bytes) {
  if (s.size() <= bytes) return s;
  while (bytes > 0 && (static_cast<unsigned char>(s[bytes]) & 0xC0) == 0x80) --bytes; // s[bytes] continues a character
  return s.substr(0, bytes);
}

/// What an error message quotes of a field: the field itself, or its first 40 bytes and its length when it is longer
/// (a corrupt file can hold a 64 KiB "number"; the message must stay readable). A NUL byte is shown as \0: a message
/// is printed as a C string, which would end at it ("'1.000" and nothing after).
inline std::string excerpt(std::string_view s) {
  const std::string_view shown = s.size() <= 40 ? s : utf8_prefix(s, 40);
  std::string out;
  out.reserve(shown.size());
  for (const char c : shown) {
    if (c == '\0') out += "\\0";
    else out += c;
  }
  if (s.size() > 40) out += "… (" + std::to_string(s.size()) + " characters)";
  return out;
}

/// One comma-separated field of a CSV line: its text with the blanks (space, tab) around it trimmed, viewing into the
/// line, and the 1-based column of its first non-blank character (of the field's start when it is blank), for
/// messages that point at the field.
struct Field {
  std::string_view text;
  int column;
};

/// Splits `line` at every comma into `out` (cleared first; its storage is reused, so a reader of 10⁶ rows allocates
/// once). No quoting: geartopo's CSV files hold numbers and plain words.
inline void split_fields(std::string_view line, std::vector<Field>& out) {
  constexpr std::string_view blanks = " \t";
  out.clear();
  for (std::size_t start = 0;;) {
    const std::size_t comma = line.find(',', start);
    const std::string_view raw = line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    const std::size_t a = raw.find_first_not_of(blanks);
    const std::string_view trimmed = a == std::string_view::npos ? std::string_view() : raw.substr(a, raw.find_last_not_of(blanks) - a + 1);
    out.push_back({trimmed, static_cast<int>(start + (a == std::string_view::npos ? 0 : a)) + 1});
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

/// split_fields into a new vector.
inline std::vector<Field> split_fields(std::string_view line) {
  std::vector<Field> out;
  split_fields(line, out);
  return out;
}

} // namespace geartopo::text
