// The AQDEF K-key writer and its strict reader (aqdef.hpp).
#include "geartopo/aqdef/aqdef.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/core/text_field.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <istream>
#include <map>
#include <ostream>
#include <stdexcept>

namespace geartopo::aqdef {
namespace {

constexpr std::uintmax_t kMaxDfqBytes = 256ull * 1024 * 1024;

std::string checked_text(const std::string& key, const std::string& s) {
  if (const auto why = text_refusal(key, s)) throw std::invalid_argument(fmt::format("AQDEF {}: {}", key, *why));
  return s;
}

constexpr std::size_t kMaxNumberCharacters = 22; // K0001, K2101, K2110, K2111: BigDecimal, 22 (KKeyRepository)

std::string number(const std::string& key, double v, int decimals) {
  if (!std::isfinite(v)) throw std::invalid_argument(fmt::format("AQDEF {}: value is not finite", key));
  if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0.0; // never "-0.0000"
  std::string s = fmt::format("{:.{}f}", v, decimals);
  if (s.size() > kMaxNumberCharacters)
    throw std::invalid_argument(fmt::format("AQDEF {}: {} has {} characters, more than the {} a number holds", key, s,
                                            s.size(), kMaxNumberCharacters));
  return s;
}

/// UTF-8 code points (bytes that do not continue a sequence).
std::size_t characters(const std::string& s) {
  return static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

/// What a key of the reader's list holds, and on which level.
enum class Level { Count, Part, Characteristic, Value };
struct KeySpec {
  Level level;
  bool numeric;
};
const std::map<std::string, KeySpec>& known_keys() {
  static const std::map<std::string, KeySpec> k{
      {"K0100", {Level::Count, true}},           {"K1001", {Level::Part, false}},
      {"K1002", {Level::Part, false}},           {"K1082", {Level::Part, false}},
      {"K2001", {Level::Characteristic, false}}, {"K2002", {Level::Characteristic, false}},
      {"K2101", {Level::Characteristic, true}},  {"K2110", {Level::Characteristic, true}},
      {"K2111", {Level::Characteristic, true}},  {"K2142", {Level::Characteristic, false}},
      {"K0001", {Level::Value, true}},           {"K0004", {Level::Value, false}},
      {"K0006", {Level::Value, false}},          {"K0014", {Level::Value, false}}};
  return k;
}

/// The state of one read: the part, which characteristic keys were seen, the last K0001's index.
struct Reader {
  std::string source;
  Part part;
  long long count = -1; // K0100, −1: not yet read
  std::map<std::pair<std::string, long long>, int> seen;
  long long last_value_index = 0; // index of the last K0001, 0 after any other key
  std::map<std::string, bool> last_value_has;

  [[noreturn]] void fail(int line, int column, const std::string& key, const std::string& message) const {
    throw InputError(source, line, column, key, message);
  }
  double parse(int line, int column, const std::string& key, std::string_view value) const {
    double v = 0.0;
    if (text::parse_number(value, v) != std::errc() || !std::isfinite(v))
      fail(line, column, key, fmt::format("'{}' is not a finite number", text::excerpt(value)));
    return v;
  }
  void take(int line, std::string_view raw);
  void take_characteristic(int line, int column, const std::string& key, long long i, std::string_view value);
  void take_value(int line, int column, const std::string& key, long long i, std::string_view value);
};

void Reader::take(int line, std::string_view raw) {
  const size_t space = raw.find(' ');
  const std::string_view head = raw.substr(0, space);
  const std::string_view value = space == std::string_view::npos ? std::string_view{} : raw.substr(space + 1);
  const std::string key(head.substr(0, head.find('/')));
  const auto spec = known_keys().find(key);
  if (spec == known_keys().end())
    fail(line, 1, text::excerpt(key), "not a key geartopo writes (K0100, K1001, K1002, K1082, K2001, K2002, K2101, "
                                      "K2110, K2111, K2142, K0001, K0004, K0006, K0014)");
  const int value_column = static_cast<int>(head.size()) + 2;
  if (spec->second.level == Level::Count) {
    if (head.size() != key.size()) fail(line, 1, key, "takes no index");
    if (count >= 0) fail(line, 1, key, "given twice");
    const double n = parse(line, value_column, key, value);
    if (n < 0 || n != std::floor(n) || n > 1e6) fail(line, value_column, key, "not a whole number of characteristics");
    count = static_cast<long long>(n);
    part.characteristics.resize(static_cast<size_t>(count));
    return;
  }
  if (count < 0) fail(line, 1, key, "before K0100 (the number of characteristics comes first)");
  if (head.size() == key.size()) fail(line, 1, key, "has no index (/i)");
  long long i = 0;
  if (text::parse_number(head.substr(key.size() + 1), i) != std::errc())
    fail(line, static_cast<int>(key.size()) + 2, key, fmt::format("'{}' is not an index", text::excerpt(head)));
  if (spec->second.numeric) parse(line, value_column, key, value); // checked here, stored below
  if (const auto why = text_refusal(key, std::string(value))) fail(line, value_column, key, *why); // as write_dfq
  if (spec->second.level == Level::Part) {
    if (i != 1) fail(line, 1, key, "a part key of part 1 only (/1): geartopo writes one part per file");
    if (seen[{key, 1}]++) fail(line, 1, key, "given twice");
    (key == "K1001" ? part.number : key == "K1002" ? part.description : part.machine) = std::string(value);
    last_value_index = 0;
    return;
  }
  if (i < 1 || i > count) fail(line, 1, key, fmt::format("index {} outside 1 … {} (K0100)", i, count));
  if (spec->second.level == Level::Characteristic) take_characteristic(line, value_column, key, i, value);
  else take_value(line, value_column, key, i, value);
}

void Reader::take_characteristic(int line, int column, const std::string& key, long long i, std::string_view value) {
  if (seen[{key, i}]++) fail(line, 1, key, fmt::format("given twice for characteristic {}", i));
  auto& c = part.characteristics[static_cast<size_t>(i - 1)];
  const std::string v(value);
  if (key == "K2001") c.code = v;
  else if (key == "K2002") c.description = v;
  else if (key == "K2142") c.unit = v;
  else {
    const double x = parse(line, column, key, value);
    (key == "K2101" ? c.nominal : key == "K2110" ? c.lower_limit : c.upper_limit) = x;
  }
  last_value_index = 0;
}

void Reader::take_value(int line, int column, const std::string& key, long long i, std::string_view value) {
  auto& c = part.characteristics[static_cast<size_t>(i - 1)];
  if (key == "K0001") {
    c.values.push_back({parse(line, column, key, value), "", "", ""});
    last_value_index = i;
    last_value_has.clear();
    return;
  }
  if (last_value_index != i)
    fail(line, 1, key, fmt::format("not right after a K0001/{} (the value it belongs to)", i));
  if (last_value_has[key]) fail(line, 1, key, "given twice for one value");
  last_value_has[key] = true;
  auto& v = c.values.back();
  (key == "K0004" ? v.time : key == "K0006" ? v.batch : v.part_ident) = std::string(value);
}

} // namespace

std::size_t max_characters(const std::string& key) {
  static const std::map<std::string, std::size_t> most{{"K1001", 30}, {"K1002", 80}, {"K1082", 40}, {"K2001", 20},
                                                       {"K2002", 80}, {"K2142", 20}, {"K0006", 14}, {"K0014", 40},
                                                       {"K0001", kMaxNumberCharacters}, {"K2101", kMaxNumberCharacters},
                                                       {"K2110", kMaxNumberCharacters}, {"K2111", kMaxNumberCharacters}};
  const auto it = most.find(key);
  return it == most.end() ? 0 : it->second;
}

std::optional<std::string> text_refusal(const std::string& key, const std::string& text) {
  if (text.find_first_of("\r\n") != std::string::npos)
    return fmt::format("'{}' holds a line break", text::excerpt(text));
  if (const std::size_t most = max_characters(key); most > 0 && characters(text) > most)
    return fmt::format("'{}' has {} characters, more than the {} AQDEF {} holds", text::excerpt(text), characters(text),
                       most, key);
  return std::nullopt;
}

std::string format_time(long long seconds_since_epoch) {
  using namespace std::chrono;
  const sys_seconds t{seconds{seconds_since_epoch}};
  const auto day = floor<days>(t);
  const year_month_day ymd{day};
  const hh_mm_ss hms{t - day};
  return fmt::format("{:02}.{:02}.{:04}/{:02}:{:02}:{:02}", static_cast<unsigned>(ymd.day()),
                     static_cast<unsigned>(ymd.month()), static_cast<int>(ymd.year()), hms.hours().count(),
                     hms.minutes().count(), hms.seconds().count());
}

void write_dfq(std::ostream& out, const Part& part, int decimals) {
  std::string s = fmt::format("K0100 {}\n", part.characteristics.size());
  s += fmt::format("K1001/1 {}\nK1002/1 {}\n", checked_text("K1001", part.number), checked_text("K1002", part.description));
  if (!part.machine.empty()) s += fmt::format("K1082/1 {}\n", checked_text("K1082", part.machine));
  for (size_t k = 0; k < part.characteristics.size(); ++k) {
    const auto& c = part.characteristics[k];
    const size_t i = k + 1;
    s += fmt::format("K2001/{} {}\n", i, checked_text("K2001", c.code));
    if (!c.description.empty()) s += fmt::format("K2002/{} {}\n", i, checked_text("K2002", c.description));
    if (c.nominal) s += fmt::format("K2101/{} {}\n", i, number("K2101", *c.nominal, decimals));
    if (c.lower_limit) s += fmt::format("K2110/{} {}\n", i, number("K2110", *c.lower_limit, decimals));
    if (c.upper_limit) s += fmt::format("K2111/{} {}\n", i, number("K2111", *c.upper_limit, decimals));
    if (!c.unit.empty()) s += fmt::format("K2142/{} {}\n", i, checked_text("K2142", c.unit));
    for (const auto& v : c.values) {
      s += fmt::format("K0001/{} {}\n", i, number("K0001", v.value, decimals));
      if (!v.time.empty()) s += fmt::format("K0004/{} {}\n", i, checked_text("K0004", v.time));
      if (!v.batch.empty()) s += fmt::format("K0006/{} {}\n", i, checked_text("K0006", v.batch));
      if (!v.part_ident.empty()) s += fmt::format("K0014/{} {}\n", i, checked_text("K0014", v.part_ident));
    }
  }
  out << s;
}

void write_dfq(const std::filesystem::path& file, const Part& part, int decimals) {
  output::write_atomically(file, [&](std::ostream& out) { write_dfq(out, part, decimals); });
}

Part read_dfq(std::istream& in, const std::string& source) {
  Reader r;
  r.source = source;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::string_view v(line);
    if (n == 1) text::strip_bom(v);
    if (!v.empty() && v.back() == '\r') v.remove_suffix(1);
    if (v.find_first_not_of(" \t") == std::string_view::npos) continue;
    r.take(n, v);
  }
  if (r.count < 0) throw InputError(source, 0, 0, "K0100", "no K0100 (number of characteristics): not an AQDEF file");
  for (size_t k = 0; k < r.part.characteristics.size(); ++k)
    if (!r.seen.count({"K2001", static_cast<long long>(k + 1)}))
      throw InputError(source, 0, 0, fmt::format("K2001/{}", k + 1), "characteristic without its number (K2001)");
  return r.part;
}

Part read_dfq(const std::filesystem::path& file) {
  auto in = input::open_input_file(file, kMaxDfqBytes, "AQDEF file");
  return read_dfq(in, file.string());
}

} // namespace geartopo::aqdef
