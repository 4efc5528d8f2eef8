// geartopo — the value file (.mew) of a Klingelnberg-style export (klingelnberg_values.hpp). Units: µm.
#include "geartopo/measurement/klingelnberg_values.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "klingelnberg_text.hpp"

#include <filesystem>
#include <fmt/format.h>

#include <sstream>

namespace geartopo::measurement {
namespace {

using namespace kl_text;

[[noreturn]] void fail(const std::string& source, int line, int column, const std::string& field, const std::string& message) {
  throw InputError(source, line, column, field, message);
}

const char* statistic_name(MachineStatistic s) {
  switch (s) {
  case MachineStatistic::Tooth: return "per tooth";
  case MachineStatistic::Mean: return "mean";
  case MachineStatistic::Variation: return "variation";
  case MachineStatistic::Max: return "max";
  case MachineStatistic::Min: return "min";
  }
  return "";
}

// The label's short name of a group and measurand ([V] gearcore: fHb Fb ffb, fHa Fa ffa, fKo).
std::string short_name(char group, int mm) {
  if (mm == 16) return "fKo";
  const char* kind = (mm - 1) / 3 == 0 ? "fH" : (mm - 1) / 3 == 1 ? "F" : "ff";
  return std::string(kind) + (group == 'h' ? "b" : "a");
}

std::optional<MachineQuantity> quantity_of(char group, int mm) {
  const bool h = group == 'h';
  if (mm == 1) return h ? MachineQuantity::HelixSlope : MachineQuantity::ProfileSlope;
  if (mm == 4) return h ? MachineQuantity::HelixTotal : MachineQuantity::ProfileTotal;
  if (mm == 7) return h ? MachineQuantity::HelixForm : MachineQuantity::ProfileForm;
  return std::nullopt;
}

bool second_position(int mm) { return mm != 16 && (mm - 1) % 3 != 0; }

// What a label says, word by word ("fHb links 12", "fHb links f 12f", "fHbm links", "Fb m links", "fHb Var links",
// "V ffa rechts", "fHa links max").
struct LabelReading {
  std::string name;
  std::optional<Flank> flank;
  std::optional<MachineStatistic> statistic; // nullopt: per tooth
  char position = 0;
  std::optional<int> tooth;
  char tooth_suffix = 0;
  std::string problem; // a word not understood, or a word given twice
};

LabelReading read_label(std::string_view label) {
  static const std::string kNames[] = {"fHb", "Fb", "ffb", "fHa", "Fa", "ffa", "fKo"};
  LabelReading r;
  const auto set_statistic = [&](MachineStatistic s, std::string_view word) {
    if (r.statistic && r.problem.empty()) r.problem = fmt::format("'{}' is a second statistic", word);
    r.statistic = s;
  };
  for (const auto w : tokens(label, " \t")) {
    bool known = false;
    if (r.name.empty())
      for (const auto& n : kNames) {
        if (w == n) r.name = n, known = true;
        else if (w == n + "m") r.name = n, set_statistic(MachineStatistic::Mean, w), known = true;
        if (known) break;
      }
    if (known) continue;
    if (w == "V" || w == "Var") set_statistic(MachineStatistic::Variation, w);
    else if (w == "m") set_statistic(MachineStatistic::Mean, w);
    else if (w == "max") set_statistic(MachineStatistic::Max, w);
    else if (w == "min") set_statistic(MachineStatistic::Min, w);
    else if (w == "links" || w == "left" || w == "rechts" || w == "right") {
      if (r.flank && r.problem.empty()) r.problem = fmt::format("'{}' is a second flank", w);
      r.flank = w == "links" || w == "left" ? Flank::Left : Flank::Right;
    } else if (w.size() == 1 && std::string_view("fkuo").find(w[0]) != std::string_view::npos) {
      r.position = w[0];
    } else if (w[0] >= '0' && w[0] <= '9') {
      std::string_view digits = w;
      if (std::isalpha(static_cast<unsigned char>(digits.back()))) r.tooth_suffix = digits.back(), digits.remove_suffix(1);
      if (const auto t = whole(digits); t && *t >= 1) r.tooth = *t;
      else if (r.problem.empty()) r.problem = fmt::format("'{}' is not a tooth number", text::excerpt(w));
    } else if (r.problem.empty()) {
      r.problem = fmt::format("the word '{}' is not understood", text::excerpt(w));
    }
  }
  return r;
}

std::string describe(const MachineFlankValue& v) {
  std::string s = short_name(v.group, v.measurand) + " " + (v.flank == Flank::Left ? "links" : "rechts");
  s += v.statistic == MachineStatistic::Tooth ? fmt::format(", tooth slot {}", v.slot)
                                              : fmt::format(", {}", statistic_name(v.statistic));
  if (second_position(v.measurand)) s += ", at a second position";
  return s;
}

// Decodes "GMMST"; nullopt when the code is not a flank-deviation code (G 1/2, MM 01 … 09 or 16 for the profile).
std::optional<MachineFlankValue> decode(int code) {
  const int g = code / 10000, mm = code / 100 % 100, s = code / 10 % 10, t = code % 10;
  if (code < 10000 || code > 99999 || (g != 1 && g != 2)) return std::nullopt;
  if (!((mm >= 1 && mm <= 9) || (mm == 16 && g == 2))) return std::nullopt;
  MachineFlankValue v;
  v.code = code;
  v.group = g == 1 ? 'h' : 'p';
  v.measurand = mm;
  v.quantity = quantity_of(v.group, mm);
  v.flank = s % 2 == 1 ? Flank::Left : Flank::Right;
  v.statistic = s == 1 || s == 2 ? MachineStatistic::Tooth
                : s == 3 || s == 4 ? MachineStatistic::Mean
                : s == 5 || s == 6 ? MachineStatistic::Variation
                : s == 7 || s == 8 ? MachineStatistic::Max
                                   : MachineStatistic::Min;
  v.slot = t;
  return v;
}

std::string_view flank_word(Flank f) { return f == Flank::Left ? "links" : "rechts"; }

// The label must say what the code says: a changed export is refused rather than misread.
void check_label(const MachineFlankValue& v, const LabelReading& r, const std::string& source, int ln, int column,
                 const std::string& field) {
  const auto mismatch = [&](const std::string& what) {
    fail(source, ln, column, field,
         fmt::format("the code says {} ({}), the label '{}' {}: code and label disagree", v.code, describe(v), v.label, what));
  };
  if (!r.problem.empty()) mismatch(fmt::format("cannot be read ({})", r.problem));
  const std::string name = short_name(v.group, v.measurand);
  if (r.name != name) mismatch(r.name.empty() ? fmt::format("names no quantity (expected '{}')", name)
                                              : fmt::format("names '{}' (expected '{}')", r.name, name));
  if (!r.flank) mismatch(fmt::format("names no flank (expected '{}')", flank_word(v.flank)));
  if (*r.flank != v.flank) mismatch(fmt::format("names the {} flank", flank_word(*r.flank)));
  const MachineStatistic said = r.statistic.value_or(MachineStatistic::Tooth);
  if (said != v.statistic) mismatch(fmt::format("says {}", statistic_name(said)));
  const bool second = second_position(v.measurand);
  const std::string_view letters = v.group == 'h' ? "fk" : "uo";
  if (second && (r.position == 0 || letters.find(r.position) == std::string_view::npos))
    mismatch(fmt::format("names no second position ('{}' or '{}')", letters[0], letters[1]));
  if (!second && r.position != 0) mismatch(fmt::format("names a second position '{}'", r.position));
  if (v.statistic == MachineStatistic::Tooth && !r.tooth) mismatch("names no tooth");
  if (v.statistic != MachineStatistic::Tooth && r.tooth) mismatch(fmt::format("names tooth {}", *r.tooth));
  if (r.tooth_suffix != 0 && r.tooth_suffix != r.position)
    mismatch(fmt::format("tags tooth {} with '{}' but names the position '{}'", *r.tooth, r.tooth_suffix, r.position));
}

// "fp max", "Fp", "Fpz/8", … with the flank words taken out; "" when the label is none of them.
std::string pitch_name(std::string_view label, std::optional<Flank>& flank) {
  static const std::string_view kNames[] = {"fp max", "fu max", "Fp", "Fpz/8", "Fr", "Rp", "Rs"};
  std::string rest;
  for (const auto w : tokens(label, " \t")) {
    if (w == "links" || w == "left") flank = Flank::Left;
    else if (w == "rechts" || w == "right") flank = Flank::Right;
    else {
      if (!rest.empty()) rest += ' ';
      rest.append(w.data(), w.size());
    }
  }
  for (const auto n : kNames)
    if (rest == n) return rest;
  return {};
}

bool is_preamble(std::string_view first_word) {
  return first_word.size() >= 2 && std::all_of(first_word.begin(), first_word.end(), [](char c) {
           return (c >= 'A' && c <= 'Z') || c == '_' || c == '.';
         });
}

// "  12345 : label : value" → 12345 and the text after its colon; nullopt when the line does not start with five
// digits and a colon.
std::optional<int> result_code(std::string_view line, std::string_view& rest) {
  size_t i = 0;
  while (i < line.size() && line[i] >= '0' && line[i] <= '9') ++i;
  if (i != 5) return std::nullopt;
  size_t j = i;
  while (j < line.size() && (line[j] == ' ' || line[j] == '\t')) ++j;
  if (j >= line.size() || line[j] != ':') return std::nullopt;
  rest = line.substr(j + 1);
  return whole(line.substr(0, i));
}

} // namespace

const char* symbol(MachineQuantity q) {
  switch (q) {
  case MachineQuantity::ProfileSlope: return "f_Hα";
  case MachineQuantity::ProfileForm: return "f_fα";
  case MachineQuantity::ProfileTotal: return "F_α";
  case MachineQuantity::HelixSlope: return "f_Hβ";
  case MachineQuantity::HelixForm: return "f_fβ";
  case MachineQuantity::HelixTotal: return "F_β";
  }
  return "";
}

const MachineFlankValue* KlingelnbergValues::find(MachineQuantity q, int tooth, Flank flank) const {
  for (const auto& v : flank_values)
    if (v.quantity == q && v.statistic == MachineStatistic::Tooth && v.tooth == tooth && v.flank == flank) return &v;
  return nullptr;
}

bool KlingelnbergValues::helix_slope_referred_to_face_width() const {
  const auto it = settings.find(179);
  return it != settings.end() && it->second.number == 1;
}

KlingelnbergValues parse_klingelnberg_values(std::string_view raw, const std::string& source) {
  KlingelnbergValues f;
  f.source = source;
  refuse_utf16(raw, source);
  std::string converted;
  if (!text::strip_bom(raw) && !is_utf8(raw)) { // no BOM and not UTF-8: latin-1, as the curve files
    converted = latin1_to_utf8(raw);
    raw = converted;
  }
  DecimalMark decimal;
  std::map<int, int> code_line;                    // code → line
  std::map<int, std::pair<int, int>> slot_tooth;   // slot → (tooth, line)
  std::map<int, std::pair<int, int>> tooth_slot;   // tooth → (slot, line)
  int ln = 0;
  bool first = true;
  for (size_t pos = 0; pos < raw.size();) {
    const size_t nl = raw.find('\n', pos);
    const std::string_view full = raw.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? raw.size() : nl + 1;
    ++ln;
    const std::string_view line = trim(full);
    if (line.empty()) continue;
    if (first) {
      first = false;
      const auto t = tokens(line, " \t");
      if (t.size() >= 2 && t[0] == "HEADER" && t[1] == "KS.MW.FILE") continue;
      fail(source, ln, 1, "HEADER",
           t.size() >= 2 && t[0] == "HEADER" && t[1] == "KS.MK.FILE"
               ? std::string("this is a curve file (HEADER KS.MK.FILE, .mka): --machine-values takes the value file "
                             "(HEADER KS.MW.FILE, .mew) the machine writes beside it")
               : fmt::format("'{}' is not a value file's first line 'HEADER KS.MW.FILE'", text::excerpt(line)));
    }
    std::string_view rest;
    if (const auto code = result_code(line, rest)) {
      const auto last = rest.rfind(':');
      const std::string field = std::to_string(*code);
      if (last == std::string_view::npos || trim(rest.substr(0, last)).empty())
        fail(source, ln, column_of(full, line), field, "expected '<code> : <label> : <value>'");
      const std::string label(trim(rest.substr(0, last)));
      const auto value_tokens = tokens(rest.substr(last + 1), " \t");
      if (value_tokens.size() != 1)
        fail(source, ln, value_tokens.empty() ? static_cast<int>(full.size()) + 1 : column_of(full, value_tokens[1]), field,
             fmt::format("expected one value in µm after the label '{}', found {}", label, value_tokens.size()));
      const auto tok = value_tokens[0];
      double v = 0.0;
      if (const auto why = read_number(tok, ln, decimal, v); !why.empty())
        fail(source, ln, column_of(full, tok), field,
             fmt::format("{}: the value of '{}' in µm; {}; not measured is written {}, not available {}", why, label,
                         kNumberRule, kMachineNotMeasured, kMachineNotAvailable));
      const bool placeholder = v == kMachineNotMeasured || v == kMachineNotAvailable;
      if (!placeholder && std::abs(v) > grinding::kMaxDeviationUm)
        fail(source, ln, column_of(full, tok), field,
             fmt::format("{} µm is beyond ±{} µm, more than any ground flank deviates (a wrong unit?)", text::excerpt(tok),
                         grinding::kMaxDeviationUm));
      const std::optional<double> value = placeholder ? std::nullopt : std::optional<double>(v);
      if (const auto [at, fresh] = code_line.emplace(*code, ln); !fresh)
        fail(source, ln, 1, field, fmt::format("code {} is given twice (first at line {}): which value is meant is unknown",
                                               *code, at->second));
      if (auto d = decode(*code)) {
        d->label = label;
        d->line = ln;
        d->value_um = value;
        const auto reading = read_label(label);
        check_label(*d, reading, source, ln, column_of(full, rest), field);
        d->position = reading.position;
        if (d->statistic == MachineStatistic::Tooth) {
          if (d->slot < 1 || d->slot > 5)
            fail(source, ln, 1, field, fmt::format("tooth slot {} (the code's last digit) of a per-tooth value: slots are 1 … 5", d->slot));
          d->tooth = *reading.tooth;
          const auto [s, s_fresh] = slot_tooth.emplace(d->slot, std::pair{d->tooth, ln});
          if (!s_fresh && s->second.first != d->tooth)
            fail(source, ln, 1, field, fmt::format("slot {} is tooth {} here and tooth {} at line {}", d->slot, d->tooth,
                                                   s->second.first, s->second.second));
          const auto [t, t_fresh] = tooth_slot.emplace(d->tooth, std::pair{d->slot, ln});
          if (!t_fresh && t->second.first != d->slot)
            fail(source, ln, 1, field, fmt::format("tooth {} is in slot {} here and in slot {} at line {}", d->tooth,
                                                   d->slot, t->second.first, t->second.second));
        } else if (d->slot != 0) {
          fail(source, ln, 1, field,
               fmt::format("a {} value has tooth slot {} (the code's last digit): statistics have 0", statistic_name(d->statistic), d->slot));
        }
        f.placeholders += placeholder;
        f.flank_values.push_back(std::move(*d));
        continue;
      }
      std::optional<Flank> flank;
      if (const auto name = pitch_name(label, flank); !name.empty()) {
        f.placeholders += placeholder;
        f.pitch_values.push_back({name, flank, value, *code, ln});
        continue;
      }
      f.unknown_lines.push_back(fmt::format("{} {} (line {})", *code, label, ln));
      continue;
    }
    if (const auto code = header_code(line, rest)) {
      if (*code == 165 || *code == 178 || *code == 179 || *code == 180) {
        MachineHeaderSetting s;
        s.text = std::string(trim(rest));
        s.line = ln;
        for (const auto part : tokens(rest, ":"))
          if (const auto n = whole(trim(part))) {
            s.number = *n;
            break;
          }
        f.settings[*code] = std::move(s);
      }
      continue; // the rest of the header is the curve file's (read there)
    }
    const auto words = tokens(line, " \t");
    if (is_preamble(words[0])) {
      f.preamble.emplace_back(line);
      if (words[0] == "FILTER") f.filters.emplace_back(line);
      continue;
    }
    fail(source, ln, column_of(full, line), "",
         fmt::format("'{}' is neither a setting 'KEY value', a header line '<code> :<text>' nor a result line "
                     "'<5-digit code> : <label> : <value>'",
                     text::excerpt(line)));
  }
  if (first) fail(source, 0, 0, "HEADER", "the file is empty: expected 'HEADER KS.MW.FILE' and result lines");
  return f;
}

std::optional<std::string> value_file_beside(const std::string& export_file) {
  const auto beside = std::filesystem::path(export_file).replace_extension(".mew");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(beside, ec)) return std::nullopt;
  return beside.string();
}

KlingelnbergValues read_klingelnberg_values(const std::string& file) {
  constexpr std::uintmax_t kMaxValueFileBytes = 16 * input::kMiB; // a few thousand lines in practice
  auto in = input::open_input_file(file, kMaxValueFileBytes, "Klingelnberg value file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_klingelnberg_values(ss.str(), file);
}

} // namespace geartopo::measurement
