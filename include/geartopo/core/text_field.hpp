// geartopo — the one rule for numbers and quoted fields in every text file geartopo reads (scene YAML, error tables,
// topology and traces CSV, point clouds), so that a file one reader accepts the others read the same way.
// Header-only; no units (the callers know theirs).
#pragma once

#include <charconv>
#include <string>
#include <string_view>
#include <system_error>

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
/// (a corrupt file can hold a 64 KiB "number"; the message must stay readable).
inline std::string excerpt(std::string_view s) {
  if (s.size() <= 40) return std::string(s);
  return std::string(utf8_prefix(s, 40)) + "… (" + std::to_string(s.size()) + " characters)";
}

} // namespace geartopo::text
