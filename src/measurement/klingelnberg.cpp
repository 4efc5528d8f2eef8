#include "geartopo/measurement/klingelnberg.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/core/text_field.hpp"
#include "geartopo/core/units.hpp"
#include "klingelnberg_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <istream>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>
#include <tuple>

namespace geartopo::measurement {
namespace {

using namespace kl_text;

[[noreturn]] void fail(const std::string& source, int line, const std::string& field, const std::string& message) {
  throw InputError(source, line, 0, field, message);
}

// An export with English labels (docs/measurement-formats.md, "English labels" [M]) read as its German twin: the words
// of heads, block titles and pitch tables replaced word by word, so every rule and message is the German one's.
// Header lines keep their labels (they are read by their code). `out` is reused; returns the line to parse.
// `from[i]`: the byte of `line` that byte i of `out` comes from (for columns in the file's own line).
std::string_view german_words(std::string_view line, std::string& out, std::vector<size_t>& from) {
  static const std::pair<std::string_view, std::string_view> kWords[] = {
      {"Tooth-No.", "Zahn-Nr."}, {"Tooth No.", "Zahn-Nr."}, {"TOPOGRAPHY", "TOPOGRAFIE"}, {"Profile", "Profil"},
      {"Lead", "Flankenlinie"},  {"left flank", "linke Zahnflanke"}, {"right flank", "rechte Zahnflanke"},
      {"left", "links"},         {"right", "rechts"}, {"Values", "Werte"}, {"values", "Werte"}};
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; };
  bool any = false;
  for (const auto& [en, de] : kWords)
    if (line.find(en) != std::string_view::npos) any = true;
  if (!any) return line;
  out.clear();
  from.clear();
  for (size_t i = 0; i < line.size();) {
    bool replaced = false;
    if (i == 0 || !word_char(line[i - 1]))
      for (const auto& [en, de] : kWords)
        if (line.substr(i, en.size()) == en && (i + en.size() == line.size() || !word_char(line[i + en.size()]) ||
                                                en.back() == '.')) {
          out += de;
          from.insert(from.end(), de.size(), i);
          i += en.size();
          replaced = true;
          break;
        }
    if (!replaced) {
      from.push_back(i);
      out += line[i++];
    }
  }
  return out;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kSlackMm = 1e-3; // points within 1 µm of the active flank count as on it (as measured_points does)
constexpr double kMaxPositionMm = 1e5; // positions and ranges: 100 m, beyond any gear (a wrong unit or a corrupt file)


// Every token of the line is a number (a value line of a trace, or of a block being skipped).
bool all_numbers(std::string_view line) {
  const auto t = tokens(line);
  if (t.empty()) return false;
  return std::all_of(t.begin(), t.end(), [](std::string_view s) { return number(s).has_value(); });
}

// A line inside a trace that still expects values that is neither a header line, a head nor a block title: a value
// line, even when its values are not numbers ("--", "2,838" in a file with decimal points, "inf"), which are then
// refused as such at their place rather than as a trace that ends too early.
bool is_value_line(std::string_view line, const KlingelnbergTrace& t) {
  if (static_cast<int>(t.values_um.size()) >= t.announced_values) return false;
  std::string_view unused;
  if (header_code(line, unused) || line.find("Zahn-Nr.") != std::string_view::npos) return false;
  // Block titles have a colon ("Profil:", "Teilung:"); the pitch tables' titles are known by name.
  if (line.find(':') != std::string_view::npos || line == "linke Zahnflanke" || line == "rechte Zahnflanke") return false;
  return !tokens(line).empty();
}


const char* kRangeSymbols[] = {"da", "de", "d1", "d2", "ba", "be", "b1", "b2"};

// Only measuring ("Mess…", "measuring") and evaluation ("Auswerte…", "evaluation") lines define ranges: line 27 may say
// "Kopfkreis … da".
std::optional<std::string> range_symbol(std::string_view label) {
  std::string lower(label);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.find("mess") == std::string::npos && lower.find("auswert") == std::string::npos &&
      lower.find("measur") == std::string::npos && lower.find("evaluat") == std::string::npos)
    return std::nullopt;
  for (const auto t : tokens(label, " \t.[]")) {
    for (const char* s : kRangeSymbols)
      if (t == s) return std::string(s);
  }
  return std::nullopt;
}


const char* kind_name(TraceKind k) { return k == TraceKind::Profile ? "profile" : "helix"; }

struct Head {
  std::optional<TraceKind> kind;
  std::string title;
  int tooth = 0;
  Flank flank = Flank::Left;
  int count = 0;
  char symbol = 0;
  double position = 0.0;
};

// "Profil:  Zahn-Nr.: 1 links / 480 Werte / z= 12.5", "Flankenlinie: Zahn-Nr.: 1 rechts / 915 Werte / d= 47.82",
// "TOPOGRAFIE: Zahn-Nr.: 26 /Profil:1 rechts / 480 Werte / z= 3.5", or a bare "Zahn-Nr.: 44 links / 480 Werte x= 8.742"
// after a title line ("Profil:").
// `teeth`: the header's number of teeth (line 22), 0 when not (yet) read.
Head parse_head(std::string_view line, std::optional<TraceKind> pending, const std::string& source, int ln,
                DecimalMark& decimal, int teeth, const std::function<int(std::string_view)>& column_in_file) {
  Head h;
  const auto at = line.find("Zahn-Nr.");
  std::string title = std::string(trim(line.substr(0, at)));
  if (!title.empty() && title.back() == ':') title.pop_back();
  h.title = title.empty() && pending ? (*pending == TraceKind::Profile ? "Profil" : "Flankenlinie") : title;
  auto kind_of = [](std::string_view t) -> std::optional<TraceKind> {
    if (t == "Profil") return TraceKind::Profile;
    if (t == "Flankenlinie") return TraceKind::Helix;
    return std::nullopt;
  };
  std::string_view rest = line.substr(at + 8); // after "Zahn-Nr."
  if (!rest.empty() && rest.front() == ':') rest.remove_prefix(1);
  rest = trim(rest);
  // Tooth number: digits, possibly followed by a letter tag (twist traces: 1k, 1f, …), which marks a block we skip.
  size_t i = 0;
  while (i < rest.size() && rest[i] >= '0' && rest[i] <= '9') ++i;
  // A tag is letters only: "1e9", "1.5" or "1,5" is a tooth number that is not one, not a tagged block.
  size_t tag_end = i;
  while (tag_end < rest.size() && std::isalpha(static_cast<unsigned char>(rest[tag_end]))) ++tag_end;
  const bool tag_ends = tag_end == rest.size() || rest[tag_end] == ' ' || rest[tag_end] == '\t' || rest[tag_end] == '/';
  const auto tooth = whole(rest.substr(0, i));
  const std::string_view tooth_text = rest.substr(0, rest.find_first_of(" \t/"));
  const std::string allowed = teeth > 0 ? fmt::format("a whole number 1 … {} (z, header line 22)", teeth) : "a whole number from 1";
  if (!tooth || *tooth < 1 || !tag_ends)
    fail(source, ln, "Zahn-Nr.", fmt::format("'{}' is not a tooth number: {}", text::excerpt(tooth_text), allowed));
  if (teeth > 0 && *tooth > teeth)
    fail(source, ln, "Zahn-Nr.", fmt::format("tooth {} of a gear with {} teeth: {}", *tooth, teeth, allowed));
  h.tooth = *tooth;
  const bool tagged = tag_end > i;
  rest.remove_prefix(i);
  if (title == "TOPOGRAFIE") {
    // "/Profil:1 rechts" or "/Flankenlinie:3 links": the kind of line in the topography, its number.
    const auto slash = rest.find('/');
    const auto colon = rest.find(':');
    if (slash == std::string_view::npos || colon == std::string_view::npos || colon < slash)
      fail(source, ln, "TOPOGRAFIE", "expected '/Profil:n' or '/Flankenlinie:n' after the tooth number");
    h.kind = kind_of(trim(rest.substr(slash + 1, colon - slash - 1)));
    rest = rest.substr(colon + 1);
    while (!rest.empty() && rest.front() >= '0' && rest.front() <= '9') rest.remove_prefix(1);
  } else {
    h.kind = title.empty() ? pending : kind_of(title);
  }
  if (tagged) h.kind.reset();
  const auto t = tokens(rest, " \t/");
  bool have_flank = false, have_count = false;
  for (size_t k = 0; k < t.size(); ++k) {
    if (t[k] == "links" || t[k] == "rechts") {
      h.flank = t[k] == "links" ? Flank::Left : Flank::Right;
      have_flank = true;
    } else if (t[k] == "Werte" && k > 0) {
      const auto n = whole(t[k - 1]);
      if (!n || *n < 1) fail(source, ln, "Werte", fmt::format("'{}' is not a number of values", text::excerpt(t[k - 1])));
      h.count = *n;
      have_count = true;
    } else if (t[k].size() >= 2 && t[k][1] == '=' && (t[k][0] == 'x' || t[k][0] == 'z' || t[k][0] == 'd')) {
      h.symbol = t[k][0];
      const std::string field(t[k].substr(0, 2));
      const std::string_view at = t[k].size() > 2 ? t[k].substr(2) : (k + 1 < t.size() ? t[k + 1] : std::string_view());
      if (at.empty()) fail(source, ln, field, "expected a position in mm after it");
      const int column = column_in_file(at);
      if (const auto why = read_number(at, ln, decimal, h.position); !why.empty())
        throw InputError(source, ln, column, field, fmt::format("{}: expected a position in mm after it; {}", why, kNumberRule));
      if (std::abs(h.position) > kMaxPositionMm)
        throw InputError(source, ln, column, field,
                         fmt::format("{} mm is beyond ±{:g} mm, further than any gear reaches (a wrong unit?)",
                                     text::excerpt(at), kMaxPositionMm));
    }
  }
  if (!have_flank) fail(source, ln, "Zahn-Nr.", "expected 'links' or 'rechts' after the tooth number");
  if (!have_count) fail(source, ln, "Werte", "expected '<n> Werte' (the number of values) in the head");
  if (h.kind && h.symbol == 0) fail(source, ln, "Zahn-Nr.", "expected the trace position 'z=', 'd=' or 'x=' in the head");
  return h;
}

// A measuring (da < de, ba < be) or evaluation range (d1 < d2, b1 < b2) must run forwards and not be empty, for each
// flank (two values: left and right; one: both). Positions spread over a reversed range would land in the wrong order
// on the flank, over an empty one on a single point.
void check_ranges(const KlingelnbergFile& f) {
  const std::pair<const char*, const char*> pairs[] = {{"da", "de"}, {"ba", "be"}, {"d1", "d2"}, {"b1", "b2"}};
  for (const auto& [lo, hi] : pairs) {
    const auto a = f.ranges.find(lo), b = f.ranges.find(hi);
    if (a == f.ranges.end() || b == f.ranges.end()) continue;
    for (int flank = 0; flank < 2; ++flank) {
      const auto& va = a->second.values;
      const auto& vb = b->second.values;
      const double x = flank == 1 && va.size() >= 2 ? va[1] : va[0];
      const double y = flank == 1 && vb.size() >= 2 ? vb[1] : vb[0];
      if (x < y) continue;
      const bool two = va.size() >= 2 || vb.size() >= 2;
      fail(f.source, b->second.line, fmt::format("{} {}", hi, b->second.label),
           fmt::format("the range {} … {} = {} … {} mm{} is {}: it must run forwards ({} < {}; {} at line {})", lo, hi, x,
                       y, two ? (flank == 0 ? " (left flank)" : " (right flank)") : "", x == y ? "empty" : "reversed", lo,
                       hi, lo, a->second.line));
    }
  }
}

} // namespace

void refuse_utf16(std::string_view head, const std::string& source) {
  constexpr const char* kSave = "save it as UTF-8 or latin-1 (Windows Notepad: Save as, Encoding UTF-8)";
  if (head.starts_with("\xFF\xFE") || head.starts_with("\xFE\xFF"))
    fail(source, 0, "", fmt::format("the file is UTF-16 ({} byte-order mark {}), which geartopo does not read: {}",
                                    head[0] == '\xFF' ? "little-endian," : "big-endian,",
                                    head[0] == '\xFF' ? "FF FE" : "FE FF", kSave));
  // UTF-16 of Latin text without a byte-order mark: every other byte is NUL. A stray NUL is left to the readers,
  // which name it at its place.
  const auto sample = head.substr(0, 4096);
  const auto nuls = std::count(sample.begin(), sample.end(), '\0');
  if (sample.size() < 4 || 3 * nuls < static_cast<std::ptrdiff_t>(sample.size())) return;
  fail(source, 0, "",
       fmt::format("the file is UTF-16 without a byte-order mark (NUL in {} of its first {} bytes), which geartopo does "
                   "not read: {}",
                   nuls, sample.size(), kSave));
}

namespace {

/// The export read line by line: a state machine over its blocks (header lines, trace heads and their values, the
/// pitch tables, blocks this reader skips), keeping what the rules across lines need (the teeth, the traces seen).
class ExportParser {
public:
  ExportParser(const std::string& source, const std::function<void()>& keep_going) : keep_going_(keep_going) {
    f_.source = source;
  }
  /// `raw`: UTF-8 (any BOM stripped).
  KlingelnbergFile parse(std::string_view raw);

private:
  enum class State { Free, Values, Skip, PitchHead, PitchRows };
  // (tooth, flank, kind, TOPOGRAFIE, position symbol, position in µm) → line of the trace's head
  using TraceKey = std::tuple<int, int, int, bool, char, double>;

  /// The column of a token of line_ in the file's own line.
  int column(std::string_view token) const;
  /// A value line of the trace being read: its values taken; false when the line is not one (the trace ends).
  bool read_value_line();
  /// A trace block ends at the first line that is not all numbers: it must have had the values its head announced.
  void end_trace() const;
  /// A skipped block lasts until a line this reader knows starts something (its rows need not be numbers:
  /// "Teilung:" has "1   R  0.0000 …").
  bool still_skipping() const;
  void skip_block(const std::string& title);
  void read_pitch_head();
  /// A row of the pitch table; false when the line is not one (the table ends).
  bool read_pitch_row();
  void read_header_line(int code, std::string_view rest);
  void check_header_values(int code, bool range, const KlingelnbergHeaderLine& h, const std::string& field);
  void read_trace_head();
  /// A line outside any block: a header line, a trace head, a title, a pitch table's flank, the preamble, or the
  /// start of a block this reader does not know.
  void read_free_line();
  void read_preamble_line(const std::vector<std::string_view>& t);

  KlingelnbergFile f_;
  State state_ = State::Free;
  std::optional<TraceKind> pending_; // a title line "Profil:" announces the kind of the next bare head
  std::map<TraceKey, int> first_line_;
  Flank pitch_flank_ = Flank::Left;
  std::vector<std::string> pitch_columns_;
  std::map<std::string, int> skipped_count_;
  std::map<std::pair<int, int>, int> pitch_rows_; // (tooth, flank) → line
  DecimalMark decimal_;
  int teeth_ = 0;       // header line 22, once read
  std::string english_; // a line with English labels in German words (german_words)
  std::vector<size_t> english_from_;
  bool skip_numbers_only_ = false; // a skipped trace ends at its last number line, an unknown block at a known line
  // The line being read: its number, the line as in the file, trimmed, and as parsed (in German words).
  int ln_ = 0;
  std::string_view full_, trimmed_, line_;
  const std::function<void()>& keep_going_; // KlingelnbergOptions::keep_going, may be empty
};

KlingelnbergFile ExportParser::parse(std::string_view raw) {
  size_t pos = 0;
  while (pos < raw.size()) {
    const size_t nl = raw.find('\n', pos);
    full_ = raw.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? raw.size() : nl + 1;
    if (++ln_ % 4096 == 0 && keep_going_) keep_going_(); // a Ctrl-C check: 4096 lines take ~1 ms
    trimmed_ = trim(full_);
    // A line of separators only (";") is a blank line in every block: the pitch table's head and rows read their
    // first token unchecked (fuzz_klingelnberg, 2026-11-28: a ";" after the last pitch row).
    if (trimmed_.find_first_not_of(" \t;") == std::string_view::npos) continue;
    line_ = trimmed_;
    if (std::string_view unused; !header_code(line_, unused)) line_ = german_words(line_, english_, english_from_);

    if (state_ == State::Values) {
      if (read_value_line()) continue;
      end_trace();
      state_ = State::Free;
    }
    if (state_ == State::Skip) {
      if (still_skipping()) continue;
      state_ = State::Free;
    }
    if (state_ == State::PitchHead) {
      read_pitch_head();
      continue;
    }
    if (state_ == State::PitchRows) {
      if (read_pitch_row()) continue;
      state_ = State::Free;
    }
    read_free_line();
  }
  f_.last_line = ln_;
  if (state_ == State::Values) end_trace();
  check_ranges(f_);
  for (const auto& t : f_.traces)
    f_.undefined_points += static_cast<int>(std::count_if(t.values_um.begin(), t.values_um.end(), [](double v) { return std::isnan(v); }));
  return std::move(f_);
}

int ExportParser::column(std::string_view tok) const {
  if (line_.data() == trimmed_.data()) return column_of(full_, tok);
  return column_of(full_, trimmed_.substr(english_from_[static_cast<size_t>(tok.data() - line_.data())]));
}

bool ExportParser::read_value_line() {
  auto& t = f_.traces.back();
  if (!all_numbers(line_) && !is_value_line(line_, t)) return false;
  for (const auto tok : tokens(line_)) {
    if (static_cast<int>(t.values_um.size()) == t.announced_values)
      fail(f_.source, ln_, "Werte",
           fmt::format("more values than the {} announced by the head at line {}", t.announced_values, t.line));
    const int col = column(tok);
    double v = 0.0;
    // nan, inf, "--" or text among the values: said as such, at its place (not as a trace that ends too early).
    if (const auto why = read_number(tok, ln_, decimal_, v); !why.empty())
      throw InputError(f_.source, ln_, col, "Werte",
                       fmt::format("{}: value {} of the {} trace of tooth {} (head at line {}); {}; a point "
                                   "the machine could not measure is written {}",
                                   why, t.values_um.size() + 1, kind_name(t.kind), t.tooth, t.line, kNumberRule,
                                   kKlingelnbergUndefined));
    if (v > kKlingelnbergUndefined + 1.0 && std::abs(v) > grinding::kMaxDeviationUm)
      throw InputError(f_.source, ln_, col, "Werte",
                       fmt::format("{} µm is beyond ±{} µm, more than any ground flank deviates (a wrong unit?)",
                                   text::excerpt(tok), grinding::kMaxDeviationUm));
    t.values_um.push_back(v <= kKlingelnbergUndefined + 1.0 ? kNaN : v);
    t.value_lines.push_back(ln_);
  }
  return true;
}

void ExportParser::end_trace() const {
  const auto& t = f_.traces.back();
  if (static_cast<int>(t.values_um.size()) != t.announced_values)
    fail(f_.source, t.line, "Werte",
         fmt::format("the head announces {} values, {} follow", t.announced_values, t.values_um.size()));
}

bool ExportParser::still_skipping() const {
  std::string_view unused;
  const bool known = header_code(line_, unused) || line_.find("Zahn-Nr.") != std::string_view::npos ||
                     line_ == "Profil:" || line_ == "Flankenlinie:" || line_ == "linke Zahnflanke" ||
                     line_ == "rechte Zahnflanke";
  return !known && !(skip_numbers_only_ && !all_numbers(line_));
}

void ExportParser::skip_block(const std::string& title) {
  if (skipped_count_[title]++ == 0) f_.skipped_blocks.push_back(fmt::format("{} (line {})", title, ln_));
  state_ = State::Skip;
}

void ExportParser::read_pitch_head() {
  const auto t = tokens(line_);
  if (t[0] != "Zahn-Nr.") fail(f_.source, ln_, "Zahn-Nr.", "expected the pitch table's column line 'Zahn-Nr. fp Fp Fr'");
  pitch_columns_.assign(t.begin() + 1, t.end());
  for (const char* need : {"fp", "Fp", "Fr"})
    if (std::find(pitch_columns_.begin(), pitch_columns_.end(), need) == pitch_columns_.end())
      fail(f_.source, ln_, "Zahn-Nr.", fmt::format("the pitch table has no column '{}' (expected 'Zahn-Nr. fp Fp Fr')", need));
  state_ = State::PitchRows;
}

bool ExportParser::read_pitch_row() {
  const auto t = tokens(line_);
  // A row starts with a whole number (the tooth); every other field must be a number of this file (nan, inf or
  // "--" is an error at its place, not the end of the table). A numbered header line ("  2 :Datum…") ends it.
  std::string_view header_rest;
  if (!whole(t[0]) || header_code(line_, header_rest)) return false;
  if (t.size() != pitch_columns_.size() + 1)
    fail(f_.source, ln_, "Zahn-Nr.", fmt::format("{} fields, the pitch table has {} columns", t.size(), pitch_columns_.size() + 1));
  KlingelnbergPitchRow r;
  r.tooth = *whole(t[0]);
  r.flank = pitch_flank_;
  r.line = ln_;
  const std::string allowed = teeth_ > 0 ? fmt::format("1 … {} (z, header line 22)", teeth_) : "from 1";
  if (r.tooth < 1 || (teeth_ > 0 && r.tooth > teeth_))
    throw InputError(f_.source, ln_, column(t[0]), "Zahn-Nr.",
                     fmt::format("tooth {} in the pitch table: a tooth number is {}", r.tooth, allowed));
  const auto [at, fresh] = pitch_rows_.emplace(std::pair{r.tooth, static_cast<int>(pitch_flank_)}, ln_);
  if (!fresh)
    fail(f_.source, ln_, "Zahn-Nr.",
         fmt::format("tooth {} is in the {} pitch table twice (first at line {})", r.tooth, to_string(pitch_flank_), at->second));
  for (size_t c = 0; c < pitch_columns_.size(); ++c) {
    const auto tok = t[c + 1];
    const int col = column(tok);
    double v = 0.0;
    if (const auto why = read_number(tok, ln_, decimal_, v); !why.empty())
      throw InputError(f_.source, ln_, col, pitch_columns_[c],
                       fmt::format("{}: the pitch table's {} of tooth {} ({} flank), in µm; {}", why, pitch_columns_[c],
                                   r.tooth, to_string(pitch_flank_), kNumberRule));
    if (std::abs(v) > grinding::kMaxDeviationUm)
      throw InputError(f_.source, ln_, col, pitch_columns_[c],
                       fmt::format("{} µm is beyond ±{} µm, more than any ground gear's pitch deviates (a wrong unit?)",
                                   text::excerpt(tok), grinding::kMaxDeviationUm));
    if (pitch_columns_[c] == "fp") r.fp_um = v;
    if (pitch_columns_[c] == "Fp") r.Fp_um = v;
    if (pitch_columns_[c] == "Fr") r.Fr_um = v;
  }
  f_.pitch.push_back(r);
  return true;
}

void ExportParser::check_header_values(int code, bool range, const KlingelnbergHeaderLine& h, const std::string& field) {
  // A line the reader uses or compares given twice with other values: which one the machine meant is not known.
  const bool checked = code == 21 || code == 22 || code == 23 || code == 24 || code == 26 || range;
  if (const auto first = f_.codes.find(code); checked && first != f_.codes.end() && first->second.values != h.values)
    fail(f_.source, ln_, field, fmt::format("given again with other values (first at line {})", first->second.line));
  if (range && h.values.size() > 2)
    fail(f_.source, ln_, field,
         fmt::format("{} values: a measuring range has one (both flanks) or two (left, right)", h.values.size()));
  if (h.values.empty()) return;
  const double v = h.values[0];
  if (code == 23 && !(std::abs(v) < 90.0))
    fail(f_.source, ln_, field, fmt::format("{}° is not a helix angle: |β| < 90°", v));
  if (code == 24 && !(v > 0.0 && v < 90.0))
    fail(f_.source, ln_, field, fmt::format("{}° is not a normal pressure angle: 0° < α_n < 90°", v));
  if (code == 26 && !(v > 0.0))
    fail(f_.source, ln_, field, fmt::format("{} mm is not a face width: a length > 0 mm", v));
}

void ExportParser::read_header_line(int code, std::string_view rest) {
  const auto colon = rest.find(':');
  KlingelnbergHeaderLine h;
  h.label = strip_leaders(rest.substr(0, colon));
  h.line = ln_;
  const auto sym = range_symbol(h.label);
  // The lines the reader checks or uses (module, teeth, ranges) must hold numbers only, at least one; on any other
  // line (a date, an order number) what is not a number is text.
  const bool used = code == 21 || code == 22 || sym.has_value();
  const std::string field = fmt::format("{} {}", code, h.label);
  if (colon != std::string_view::npos)
    for (const auto t : tokens(rest.substr(colon + 1), " \t:;")) {
      double v = 0.0;
      if (!used) {
        if (const auto n = number(t)) h.values.push_back(*n);
        continue;
      }
      if (const auto why = read_number(t, ln_, decimal_, v); !why.empty())
        throw InputError(f_.source, ln_, column(t), field, fmt::format("{}; this line's values are numbers ({})", why, kNumberRule));
      if (std::abs(v) > kMaxPositionMm)
        throw InputError(f_.source, ln_, column(t), field,
                         fmt::format("{} is beyond ±{:g}, more than any gear measures (a wrong unit?)", text::excerpt(t),
                                     kMaxPositionMm));
      h.values.push_back(v);
    }
  if (used && h.values.empty())
    fail(f_.source, ln_, field, "no value after the label: expected a number (the reader uses this line)");
  check_header_values(code, sym.has_value(), h, field);
  if (code == 21 && h.values[0] <= 0.0)
    fail(f_.source, ln_, field, fmt::format("{} mm is not a normal module: a length > 0 mm", h.values[0]));
  if (code == 22) {
    const double z = h.values[0];
    if (z != std::floor(z) || z < 1.0 || z > 10000.0)
      fail(f_.source, ln_, field, fmt::format("{} is not a number of teeth: a whole number 1 … 10000", z));
    teeth_ = static_cast<int>(z);
    for (const auto& t : f_.traces)
      if (t.tooth > teeth_)
        fail(f_.source, t.line, "Zahn-Nr.", fmt::format("tooth {} of a gear with {} teeth (header line 22 at line {})", t.tooth, teeth_, ln_));
  }
  if (sym) f_.ranges[*sym] = h;
  f_.codes[code] = std::move(h);
}

void ExportParser::read_trace_head() {
  const Head h = parse_head(line_, pending_, f_.source, ln_, decimal_, teeth_, [this](std::string_view t) { return column(t); });
  pending_.reset();
  if (!h.kind) { // e.g. "Verschränkung:" (twist) traces: listed, their values skipped
    skip_block(h.title.empty() ? std::string("Zahn-Nr.") : h.title);
    skip_numbers_only_ = true;
    return;
  }
  // One trace per tooth, flank, kind and position (to the µm the positions are printed to): a second one is either
  // another tooth's block numbered wrongly or a repeat, and a repeat would count the flank twice in every fit and
  // evaluation. Refused (docs/measurement-formats.md, "Repeated traces").
  const TraceKey key{h.tooth, static_cast<int>(h.flank), static_cast<int>(*h.kind), h.title == "TOPOGRAFIE", h.symbol,
                     std::round(h.position * 1000.0)}; // a double: a position of 1e300 mm must not overflow
  if (const auto [at, fresh] = first_line_.emplace(key, ln_); !fresh)
    fail(f_.source, ln_, "Zahn-Nr.",
         fmt::format("tooth {} {} {} {}at {}= {} mm is measured twice (first at line {}): a repeated measurement is "
                     "refused. If another tooth's blocks carry this number by mistake, correct it; to state the "
                     "repeatability, export each measurement to a file of its own",
                     h.tooth, to_string(h.flank), kind_name(*h.kind), h.title == "TOPOGRAFIE" ? "(TOPOGRAFIE) " : "",
                     h.symbol, h.position, at->second));
  KlingelnbergTrace t;
  t.kind = *h.kind;
  t.tooth = h.tooth;
  t.flank = h.flank;
  t.topography = h.title == "TOPOGRAFIE";
  t.position_symbol = h.symbol;
  t.position_mm = h.position;
  t.announced_values = h.count;
  t.line = ln_;
  f_.traces.push_back(std::move(t));
  state_ = State::Values;
}

void ExportParser::read_preamble_line(const std::vector<std::string_view>& t) {
  // The mark of an undefined point changes what the numbers mean: a file marking them -999.999 would have that read
  // as a deviation. The reader knows one mark (with a decimal point or comma); another is refused.
  if (t[0] == "UNDEFINED") {
    std::string mark = t.size() >= 2 ? std::string(t[1]) : std::string();
    std::replace(mark.begin(), mark.end(), ',', '.');
    const auto v = number(mark);
    if (!v || std::abs(*v - kKlingelnbergUndefined) > 1e-6)
      fail(f_.source, ln_, "UNDEFINED",
           fmt::format("'{}' is not the mark of an undefined point this reader knows ({}): its points would be read "
                       "as deviations",
                       t.size() >= 2 ? text::excerpt(t[1]) : std::string(), kKlingelnbergUndefined));
  }
}

void ExportParser::read_free_line() {
  std::string_view rest;
  if (const auto code = header_code(line_, rest)) return read_header_line(*code, rest);
  if (line_.find("Zahn-Nr.") != std::string_view::npos) return read_trace_head();
  if (line_ == "Profil:" || line_ == "Flankenlinie:") {
    pending_ = line_ == "Profil:" ? TraceKind::Profile : TraceKind::Helix;
    return;
  }
  if (line_ == "linke Zahnflanke" || line_ == "rechte Zahnflanke") {
    pitch_flank_ = line_ == "linke Zahnflanke" ? Flank::Left : Flank::Right;
    state_ = State::PitchHead;
    return;
  }
  // Preamble ("HEADER KS.MK.FILE", "TYPE STI ! comment", …): settings of the export, not data.
  const auto t = tokens(line_); // never empty: a line of separators only is skipped as blank (parse)
  const bool preamble = t[0].size() >= 2 && std::all_of(t[0].begin(), t[0].end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || c == '_' || c == '.';
  });
  if (preamble) return read_preamble_line(t);
  // Anything else opens a block this reader does not know: skipped with the numbers that follow it, and listed.
  std::string title(text::utf8_prefix(line_, 40));
  if (const auto c = title.find(':'); c != std::string::npos) title = std::string(trim(title.substr(0, c)));
  skip_block(title);
  skip_numbers_only_ = false;
}

} // namespace

KlingelnbergFile parse_klingelnberg(std::string_view raw, const std::string& source,
                                    const std::function<void()>& keep_going) {
  refuse_utf16(raw, source);
  std::string converted;
  if (!text::strip_bom(raw) && !is_utf8(raw)) { // no BOM and not UTF-8: the older latin-1 exports
    converted = latin1_to_utf8(raw);
    raw = converted;
  }
  // CR-only line endings (an export saved by a classic-Mac tool): without a LF the whole file was one line, refused
  // as "1:642: z=: '10.0' is not a number". A CR that ends every line is read as the line break it is.
  if (raw.find('\n') == std::string_view::npos && raw.find('\r') != std::string_view::npos) {
    std::string lines(raw);
    std::replace(lines.begin(), lines.end(), '\r', '\n');
    converted = std::move(lines);
    raw = converted;
  }
  return ExportParser(source, keep_going).parse(raw);
}

KlingelnbergFile read_klingelnberg(const std::string& file, const std::function<void()>& keep_going) {
  // An export of a few gears is a few MB; it is read whole.
  constexpr std::uintmax_t kMaxExportBytes = 64 * input::kMiB;
  auto in = input::open_input_file(file, kMaxExportBytes, "Klingelnberg export");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_klingelnberg(ss.str(), file, keep_going);
}

bool looks_like_klingelnberg(std::istream& in) {
  std::string head(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  in.clear();
  in.seekg(0);
  return head.find("HEADER KS.") != std::string::npos || head.find("Zahn-Nr.") != std::string::npos ||
         head.find("Tooth-No.") != std::string::npos || head.find("Tooth No.") != std::string::npos;
}

namespace {

const KlingelnbergHeaderLine* code_line(const KlingelnbergFile& f, int code) {
  const auto it = f.codes.find(code);
  return it == f.codes.end() || it->second.values.empty() ? nullptr : &it->second;
}

std::string code_field(int code, const KlingelnbergHeaderLine& h) { return fmt::format("{} {}", code, h.label); }

// The range value for a flank: one number serves both flanks, two are left and right [M: the order].
double range_value(const KlingelnbergFile& f, const std::string& symbol, Flank flank, const KlingelnbergTrace& t) {
  const auto it = f.ranges.find(symbol);
  if (it == f.ranges.end() || it->second.values.empty())
    fail(f.source, t.line, symbol,
         fmt::format("a {} trace needs the measuring range '{}' in the header, which is missing", kind_name(t.kind), symbol));
  const auto& v = it->second.values;
  return flank == Flank::Right && v.size() >= 2 ? v[1] : v[0];
}

double sign_factor(const KlingelnbergTrace& t, SignConvention s) {
  if (s == SignConvention::Din) return 1.0;
  if (t.kind == TraceKind::Helix) return -1.0;
  return t.flank == Flank::Left ? -1.0 : 1.0;
}

} // namespace

KlingelnbergPoints klingelnberg_points(const KlingelnbergFile& f, const gears::GearGeometry& g, const KlingelnbergOptions& o) {
  KlingelnbergPoints out;
  const auto& spec = g.spec();
  if (const auto* h = code_line(f, 21)) {
    if (std::abs(h->values[0] - spec.normal_module_mm) > 0.5e-4) // files print m_n to 4 decimals
      fail(f.source, h->line, code_field(21, *h),
           fmt::format("{} mm in the file, the scene's gear has m_n = {} mm", h->values[0], spec.normal_module_mm));
  } else {
    out.warnings.push_back(f.source + ": no normal module (header line 21): not checked against the scene");
  }
  if (const auto* h = code_line(f, 22)) {
    if (h->values[0] != spec.teeth)
      fail(f.source, h->line, code_field(22, *h),
           fmt::format("{} in the file, the scene's gear has z = {}", h->values[0], spec.teeth));
  } else {
    out.warnings.push_back(f.source + ": no number of teeth (header line 22): not checked against the scene");
  }
  // The angles are compared as a warning only: how an export signs β for the hand is not known [M], so |β| is compared.
  const std::pair<int, double> angles[] = {{23, std::abs(units::deg_from_rad(spec.helix_angle_rad))},
                                           {24, units::deg_from_rad(spec.normal_pressure_angle_rad)}};
  for (const auto& [code, scene_deg] : angles)
    if (const auto* h = code_line(f, code); h && std::abs(std::abs(h->values[0]) - scene_deg) > 0.5e-4)
      out.warnings.push_back(fmt::format("{}:{}: {}: {:.6g}° in the file, {:.6g}° in the scene (|β| and α_n are "
                                         "compared)",
                                         f.source, h->line, code_field(code, *h), h->values[0], scene_deg));
  const double to_normal = o.direction == DeviationDirection::Transverse ? std::cos(g.base_helix_angle()) : 1.0;
  const double d_lo = g.root_form_diameter_mm(), d_hi = g.tip_diameter_mm(), b = spec.face_width_mm;
  int off_flank = 0;
  for (const auto& t : f.traces) {
    if (o.keep_going) o.keep_going(); // a Ctrl-C check: every point of a trace is put on the flank
    if (t.tooth > g.teeth())
      fail(f.source, t.line, "Zahn-Nr.", fmt::format("tooth {} of a gear with {} teeth", t.tooth, g.teeth()));
    const int n = static_cast<int>(t.values_um.size());
    const double factor = sign_factor(t, o.signs) * to_normal;
    for (int i = 0; i < n; ++i) {
      if (std::isnan(t.values_um[static_cast<size_t>(i)])) continue;
      const double u = n > 1 ? static_cast<double>(i) / (n - 1) : 0.0;
      double dia = 0.0, z = 0.0;
      if (t.kind == TraceKind::Profile) {
        if (t.position_symbol != 'z')
          fail(f.source, t.line, fmt::format("{}=", t.position_symbol), "a profile trace's position is its axial height 'z='");
        const double da = range_value(f, "da", t.flank, t), de = range_value(f, "de", t.flank, t);
        if (o.spacing == ProfileSpacing::RollLength) {
          if (da < g.base_diameter_mm() || de < g.base_diameter_mm())
            fail(f.source, f.ranges.at("da").line, "da", fmt::format("{} … {} mm reaches below the base circle {:.4f} mm", da, de, g.base_diameter_mm()));
          const double xa = g.roll_length_at(da), xe = g.roll_length_at(de);
          dia = g.diameter_at_roll_length(xa + u * (xe - xa));
        } else {
          dia = da + u * (de - da);
        }
        z = t.position_mm;
      } else {
        const double ba = range_value(f, "ba", t.flank, t), be = range_value(f, "be", t.flank, t);
        z = ba + u * (be - ba);
        if (t.position_symbol == 'd') dia = t.position_mm;
        else if (t.position_symbol == 'x') dia = g.diameter_at_roll_length(t.position_mm);
        else fail(f.source, t.line, "z=", "a helix trace's position is its diameter 'd=' or roll length 'x='");
      }
      if (dia < d_lo - kSlackMm || dia > d_hi + kSlackMm || z < -kSlackMm || z > b + kSlackMm) {
        ++off_flank;
        continue;
      }
      MeasuredPoint p;
      p.tooth = t.tooth;
      p.flank = t.flank;
      p.diameter_mm = std::clamp(dia, d_lo, d_hi);
      p.roll_length_mm = g.roll_length_at(p.diameter_mm);
      p.z_mm = std::clamp(z, 0.0, b);
      p.deviation_um = factor * t.values_um[static_cast<size_t>(i)];
      p.line = t.value_lines[static_cast<size_t>(i)];
      out.points.push_back(p);
      out.trace_of_point.push_back(static_cast<std::size_t>(&t - f.traces.data()));
    }
  }
  out.undefined_values = static_cast<std::size_t>(f.undefined_points);
  out.off_flank_points = static_cast<std::size_t>(off_flank);
  if (!f.skipped_blocks.empty())
    out.warnings.push_back(fmt::format("{}: blocks not read (this reader knows Profil, Flankenlinie, TOPOGRAFIE and the "
                                       "pitch tables): {}",
                                       f.source, fmt::join(f.skipped_blocks, ", ")));
  if (f.undefined_points > 0)
    out.warnings.push_back(fmt::format("{}: {} undefined values ({}) skipped", f.source, f.undefined_points, kKlingelnbergUndefined));
  if (off_flank > 0)
    out.warnings.push_back(fmt::format("{}: {} points off the active flank (d_Ff {:.4f} … d_a {:.4f} mm, z 0 … {} mm) skipped",
                                       f.source, off_flank, d_lo, d_hi, b));
  if (out.points.empty())
    fail(f.source, f.last_line, "Zahn-Nr.",
         fmt::format("nothing usable: {} profile/helix traces, no defined point on the active flank", f.traces.size()));
  return out;
}

std::vector<grinding::FlankTopology> klingelnberg_traces(const KlingelnbergFile& f, const gears::GearGeometry& g,
                                                         const KlingelnbergOptions& o, std::vector<std::string>* warnings) {
  auto res = klingelnberg_points(f, g, o);
  if (warnings) warnings->insert(warnings->end(), res.warnings.begin(), res.warnings.end());
  // Points per trace, in file order.
  std::map<std::size_t, std::vector<const MeasuredPoint*>> by_trace;
  for (std::size_t i = 0; i < res.points.size(); ++i) by_trace[res.trace_of_point[i]].push_back(&res.points[i]);
  const double mid_z = 0.5 * g.spec().face_width_mm;
  const double mid_xi = 0.5 * (g.roll_length_at(g.root_form_diameter_mm()) + g.roll_length_at(g.tip_diameter_mm()));
  // Per flank, the chosen trace of each kind: (topography?, distance from the middle) is the ranking, smaller wins.
  struct Choice {
    std::size_t trace = 0;
    std::pair<bool, double> rank{true, std::numeric_limits<double>::infinity()};
    bool found = false;
  };
  std::map<std::pair<int, int>, std::pair<Choice, Choice>> chosen; // (tooth, flank) → (profile, helix)
  for (const auto& [ti, pts] : by_trace) {
    if (pts.size() < 2) continue;
    const auto& t = f.traces[ti];
    const bool profile = t.kind == TraceKind::Profile;
    const double distance = profile ? std::abs(pts.front()->z_mm - mid_z) : std::abs(pts.front()->roll_length_mm - mid_xi);
    auto& c = profile ? chosen[{t.tooth, static_cast<int>(t.flank)}].first : chosen[{t.tooth, static_cast<int>(t.flank)}].second;
    const std::pair<bool, double> rank{t.topography, distance};
    if (!c.found || rank < c.rank) c = {ti, rank, true};
  }
  std::vector<grinding::FlankTopology> out;
  std::vector<std::string> incomplete;
  for (const auto& [key, pair] : chosen) {
    if (!pair.first.found || !pair.second.found) {
      incomplete.push_back(fmt::format("tooth {} {} (no {} trace)", key.first, to_string(static_cast<Flank>(key.second)),
                                       pair.first.found ? "helix" : "profile"));
      continue;
    }
    grinding::FlankTopology ft;
    ft.tooth = key.first;
    ft.flank = static_cast<Flank>(key.second);
    for (const auto* c : {&pair.first, &pair.second}) {
      auto& trace = c == &pair.first ? ft.profile : ft.helix;
      for (const auto* p : by_trace.at(c->trace))
        trace.push_back({p->roll_length_mm, p->diameter_mm, p->z_mm, p->deviation_um, p->line});
      // The evaluator wants increasing positions: roll length for a profile, z for a helix (a range may run downwards).
      const bool by_xi = c == &pair.first;
      std::sort(trace.begin(), trace.end(), [by_xi](const auto& a, const auto& b) {
        return by_xi ? a.roll_length_mm < b.roll_length_mm : a.z_mm < b.z_mm;
      });
    }
    out.push_back(std::move(ft));
  }
  if (!incomplete.empty() && warnings)
    warnings->push_back(fmt::format("{}: flanks without both a profile and a helix trace are not evaluated: {}", f.source,
                                    fmt::join(incomplete, ", ")));
  if (out.empty())
    fail(f.source, f.last_line, "Zahn-Nr.", "no flank has both a profile and a helix trace: nothing to evaluate to ISO 1328-1");
  return out;
}

void write_klingelnberg(std::ostream& out, const gears::GearGeometry& g, const std::vector<grinding::TopologyRow>& rows,
                        const KlingelnbergOptions& o) {
  // One TOPOGRAFIE profile line per tooth, flank and grid column, its values from root to tip.
  std::map<std::tuple<int, int, int>, std::vector<const grinding::TopologyRow*>> lines; // (tooth, flank, col)
  for (const auto& r : rows) lines[{r.tooth, r.flank == Flank::Left ? 0 : 1, r.col}].push_back(&r);
  if (lines.empty()) throw std::invalid_argument("write_klingelnberg: no rows");
  double da = std::numeric_limits<double>::infinity(), de = -da, ba = da, be = -da;
  for (const auto& r : rows) {
    da = std::min(da, r.diameter_mm);
    de = std::max(de, r.diameter_mm);
    ba = std::min(ba, r.z_mm);
    be = std::max(be, r.z_mm);
  }
  const auto& s = g.spec();
  const double to_file = o.direction == DeviationDirection::Transverse ? 1.0 / std::cos(g.base_helix_angle()) : 1.0;
  out << "HEADER KS.MK.FILE\r\n";
  out << "TYPE    STI     ! written by geartopo synth\r\n";
  out << fmt::format("  21 :Normalmodul mn [mm]..............: {:.4f}\r\n", s.normal_module_mm);
  out << fmt::format("  22 :Zähnezahl z......................: {}\r\n", s.teeth);
  out << fmt::format("  23 :Schrägungswinkel beta [Grad].....: {:.4f}\r\n", units::deg_from_rad(s.helix_angle_rad));
  out << fmt::format("  24 :Eingriffswinkel alpha [Grad].....: {:.4f}\r\n", units::deg_from_rad(s.normal_pressure_angle_rad));
  out << fmt::format("  25 :Profilverschiebungsfaktor x......: {:.4f}\r\n", s.profile_shift);
  out << fmt::format("  26 :Zahnbreite b [mm]................: {:.4f}\r\n", s.face_width_mm);
  out << fmt::format("  27 :Kopfkreisdurchmesser [mm]........: {:.4f}\r\n", s.tip_diameter_mm);
  out << fmt::format(" 272 :Fußkreisdurchmesser [mm].........: {:.4f}\r\n", s.root_diameter_mm);
  out << fmt::format("  41 :Start Messbereich.....da [mm]....: {:.6f} {:.6f}\r\n", da, da);
  out << fmt::format("  44 :Ende der Messstrecke..de [mm]....: {:.6f} {:.6f}\r\n", de, de);
  out << fmt::format("  61 :Messanfang............ba [mm]....: {:.6f} {:.6f}\r\n", ba, ba);
  out << fmt::format("  64 :Messende..............be [mm]....: {:.6f} {:.6f}\r\n", be, be);
  for (const auto& [key, pts] : lines) {
    auto sorted = pts;
    std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->row < b->row; });
    const int tooth = std::get<0>(key);
    const Flank flank = std::get<1>(key) == 0 ? Flank::Left : Flank::Right;
    KlingelnbergTrace probe; // for the sign factor
    probe.kind = TraceKind::Profile;
    probe.flank = flank;
    const double factor = sign_factor(probe, o.signs) * to_file;
    out << fmt::format("TOPOGRAFIE: Zahn-Nr.: {} /Profil:{} {} / {} Werte / z= {:.6f}\r\n", tooth, std::get<2>(key),
                       flank == Flank::Left ? "links" : "rechts", sorted.size(), sorted.front()->z_mm);
    // The export carries no design line: its values are the flank from the bare involute (deviation + design),
    // as the reader takes an export's values (refer_to_design).
    for (size_t i = 0; i < sorted.size(); ++i) {
      out << fmt::format("{:9.3f}", factor * (sorted[i]->deviation_um + sorted[i]->design_um));
      out << ((i + 1) % 12 == 0 || i + 1 == sorted.size() ? "\r\n" : " ");
    }
  }
}

} // namespace geartopo::measurement
