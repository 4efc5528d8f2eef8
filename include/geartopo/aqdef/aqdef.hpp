// geartopo — the AQDEF transfer format (Q-DAS ASCII, .dfq) that qs-STAT and most automotive quality systems read: one
// part, its characteristics and their measured values, as K-key lines "Kxxxx/i value" (docs/aqdef.md: the keys
// written, where they are described, and the mapping of ISO 1328-1 values onto them). Plain data in, plain data out;
// numbers locale-free with a '.' decimal point; text ASCII or UTF-8, never a line break.
#pragma once

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::aqdef {

/// One measured value of a characteristic (K0001) and when it was measured (K0004, "dd.mm.yyyy/hh:mm:ss"; empty: none).
struct Value {
  double value = 0.0;
  std::string time;
  std::string batch; ///< K0006 (empty: none)
  std::string part_ident; ///< K0014: the part's own identity, its serial number (empty: none; ≤ 40 characters)
};

/// One characteristic (K2xxx/i) and its values.
struct Characteristic {
  std::string code;                  ///< K2001 characteristic number
  std::string description;           ///< K2002
  std::optional<double> nominal;     ///< K2101
  std::optional<double> lower_limit; ///< K2110 (lower specification limit)
  std::optional<double> upper_limit; ///< K2111 (upper specification limit)
  std::string unit;                  ///< K2142
  std::vector<Value> values;         ///< K0001/K0004/K0006, in file order
};

/// One part (K1xxx/1) with its characteristics; K0100 is their number.
struct Part {
  std::string number;      ///< K1001 part number
  std::string description; ///< K1002 part description
  std::string machine;     ///< K1082 machine
  std::vector<Characteristic> characteristics;
};

/// The most characters (UTF-8 code points) a text key holds in the Q-DAS database behind the format, from
/// diribet/aqdef-tools' KKeyRepository (generated from the Q-DAS MDB): K1001 30, K1002 80, K1082 40, K2001 20,
/// K2002 80, K2142 20, K0006 14 (batch), K0014 40; a number (K0001, K2101, K2110, K2111) 22. 0 for another key.
std::size_t max_characters(const std::string& key);
/// Why `text` cannot be written as `key` (longer than max_characters, or holding a line break), or nullopt: the check
/// write_dfq makes of every text, for the readers of what is later written (a series file's name, machine and ids).
std::optional<std::string> text_refusal(const std::string& key, const std::string& text);

/// "dd.mm.yyyy/hh:mm:ss" of a time given as seconds since 1970-01-01 00:00:00 (shop time, no time zone applied).
std::string format_time(long long seconds_since_epoch);

/// Writes the part: K0100, then K1001/1, K1002/1, K1082/1, then per characteristic i its K2001/i … K2142/i and its
/// values, each K0001/i followed by its K0004/i, K0006/i and K0014/i. Numbers with `decimals` decimals. Throws
/// std::invalid_argument naming the key for a text text_refusal refuses, a value that is not finite or a number
/// longer than 22 characters, before anything is written.
void write_dfq(std::ostream& out, const Part& part, int decimals = 4);
/// Atomically (files/atomic_write.hpp).
void write_dfq(const std::filesystem::path& file, const Part& part, int decimals = 4);

/// Reads what write_dfq writes, strictly: every line "Kdddd[/i] value" with a key of the list above, K0100 first, an
/// index in 1 … K0100 (part keys /1), a number where the key holds one, K0004, K0006 and K0014 only right after a
/// K0001 of the same index, no key of a characteristic given twice, every characteristic with a K2001. Blank lines are skipped; a
/// UTF-8 BOM and CRLF are accepted. Throws InputError at file:line:column naming the key.
Part read_dfq(std::istream& in, const std::string& source);
Part read_dfq(const std::filesystem::path& file);

} // namespace geartopo::aqdef
