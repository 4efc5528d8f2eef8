#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/core/text_field.hpp"
#include "geartopo/core/units.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <istream>
#include <numbers>
#include <set>
#include <stdexcept>

namespace geartopo::compensation {
namespace {

constexpr int kColumns = 14;

/// The 14 column names with the axes' own letters: space,z_stroke_mm,time_s,X_mm,…,C_deg,dX_um,…,dC_urad,within_strokes.
std::vector<std::string> header_names(const ChainAxes& axes) {
  std::vector<std::string> names = {"space", "z_stroke_mm", "time_s"};
  // (fmt rather than operator+: GCC 12 warns falsely, -Wstringop-overflow, on the concatenation at -O3)
  for (int a = 0; a < 5; ++a) names.push_back(fmt::format("{}_{}", axes.axis_name(a), a < 3 ? "mm" : "deg"));
  for (int a = 0; a < 5; ++a) names.push_back(fmt::format("d{}_{}", axes.axis_name(a), a < 3 ? "um" : "urad"));
  names.emplace_back("within_strokes");
  return names;
}

} // namespace

std::vector<std::string> CorrectionTable::column_names() const { return header_names(axes_); }

CorrectionTable::CorrectionTable(std::vector<CorrectionRow> rows, ChainAxes axes) : rows_(std::move(rows)), axes_(axes) {
  std::stable_sort(rows_.begin(), rows_.end(), [](const CorrectionRow& a, const CorrectionRow& b) {
    return a.space != b.space ? a.space < b.space : a.z_stroke_mm < b.z_stroke_mm;
  });
  z_.reserve(rows_.size());
  for (const auto& r : rows_) z_.push_back(r.z_stroke_mm);
  for (size_t i = 0; i < rows_.size(); ++i) {
    const int space = rows_[i].space;
    if (space < 0) throw std::invalid_argument(fmt::format("correction row {}: space {} < 0", i + 1, space));
    if (static_cast<size_t>(space) >= span_.size()) span_.resize(static_cast<size_t>(space) + 1, {0, 0});
    auto& span = span_[static_cast<size_t>(space)];
    if (span.first == span.second) span = {i, i + 1};
    else span.second = i + 1;
  }
}

machine::Vector5d CorrectionTable::at(int space, double z) const {
  // Looked up at every pose of a compensated simulation: a vector by space and the stroke positions on their own.
  if (space < 0 || static_cast<size_t>(space) >= span_.size()) return machine::Vector5d::Zero();
  const auto [first_row, last_row] = span_[static_cast<size_t>(space)];
  if (first_row == last_row) return machine::Vector5d::Zero();
  const auto first = z_.begin() + static_cast<long>(first_row);
  const auto last = z_.begin() + static_cast<long>(last_row);
  // std::lower_bound's answer (the first row with z_stroke ≥ z), found from where an even spacing puts z and walked
  // to the exact row: the rows are sampled at a constant step, so the guess is almost always right.
  auto hi = first;
  if (const long n = last - first; n > 1) {
    const double guess = std::ceil((z - *first) / (*(last - 1) - *first) * static_cast<double>(n - 1));
    // (a NaN guess — one row position repeated — starts the walk at the first row)
    hi = first + (guess > 0.0 ? static_cast<long>(std::min(guess, static_cast<double>(n))) : 0L);
    while (hi != first && *(hi - 1) >= z) --hi;
    while (hi != last && *hi < z) ++hi;
  } else if (*first < z) {
    hi = last;
  }
  const auto row = [&](std::vector<double>::const_iterator it) -> const CorrectionRow& {
    return rows_[static_cast<size_t>(it - z_.begin())];
  };
  if (hi == first) return row(first).correction;
  if (hi == last) return row(last - 1).correction;
  const auto lo = hi - 1;
  const double t = (z - *lo) / (*hi - *lo);
  return (1.0 - t) * row(lo).correction + t * row(hi).correction;
}

int CorrectionTable::rows_outside_strokes() const {
  return static_cast<int>(std::count_if(rows_.begin(), rows_.end(), [](const CorrectionRow& r) { return !r.within_strokes; }));
}

machine::Vector5d CorrectionTable::max_abs() const {
  machine::Vector5d m = machine::Vector5d::Zero();
  for (const auto& r : rows_) m = m.cwiseMax(r.correction.cwiseAbs());
  return m;
}

void CorrectionTable::write_csv(std::ostream& out) const {
  out << fmt::format("{}", fmt::join(header_names(axes_), ",")) << "\n";
  for (const auto& r : rows_) {
    const auto& q = r.machine_axes;
    const auto& c = r.correction;
    out << fmt::format("{},{:.4f},{:.3f},{:.5f},{:.5f},{:.5f},{:.7f},{:.7f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{}\n", r.space,
                       r.z_stroke_mm, r.time_s, q.x, q.y, q.z, q.a * units::kDegPerRad, q.c * units::kDegPerRad, units::um_from_mm(c(0)), units::um_from_mm(c(1)), units::um_from_mm(c(2)),
                       units::urad_from_rad(c(3)), units::urad_from_rad(c(4)), r.within_strokes ? "yes" : "no");
  }
}

void CorrectionTable::write_csv(const std::filesystem::path& file) const {
  output::write_atomically(file, [&](std::ostream& out) { write_csv(out); });
}

CorrectionTable CorrectionTable::read_csv(std::istream& in, const std::string& source, ChainAxes axes) {
  const auto fail = [&](int line, int column, const std::string& field, const std::string& message) {
    throw InputError(source, line, column, field, message);
  };
  const std::vector<std::string> names = header_names(axes);
  const std::string header_text = fmt::format("{}", fmt::join(names, ","));
  std::vector<CorrectionRow> rows;
  std::set<std::pair<int, double>> seen;
  bool header = false;
  int lineno = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (lineno == 1 && line.rfind(text::kUtf8Bom, 0) == 0) line.erase(0, text::kUtf8Bom.size());
    if (line.empty() || line[0] == '#') continue;
    const auto f = text::split_fields(line);
    if (!header) {
      for (int i = 0; i < kColumns; ++i)
        if (static_cast<int>(f.size()) <= i || f[static_cast<size_t>(i)].text != names[static_cast<size_t>(i)])
          fail(lineno, i < static_cast<int>(f.size()) ? f[static_cast<size_t>(i)].column : static_cast<int>(line.size()) + 1,
               "header", fmt::format("expected the columns {} (column {} should be '{}'): a corrections.csv of "
                                     "geartopo compensate", header_text, i + 1, names[static_cast<size_t>(i)]));
      header = true;
      continue;
    }
    if (f.size() != kColumns)
      fail(lineno, f.size() > kColumns ? f[kColumns].column : static_cast<int>(line.size()) + 1, "row",
           fmt::format("{} fields, expected {}", f.size(), kColumns));
    const auto number = [&](int i, double limit) {
      double v = 0.0;
      const auto& [t, column] = f[static_cast<size_t>(i)];
      if (text::parse_number(t, v) != std::errc() || !std::isfinite(v))
        fail(lineno, column, names[static_cast<size_t>(i)], fmt::format("'{}' is not a finite number", text::excerpt(t)));
      if (std::abs(v) > limit)
        fail(lineno, column, names[static_cast<size_t>(i)], fmt::format("{} is beyond ±{} (a wrong unit?)", text::excerpt(t), limit));
      return v;
    };
    CorrectionRow r;
    if (text::parse_number(f[0].text, r.space) != std::errc() || r.space < 1)
      fail(lineno, f[0].column, "space", fmt::format("'{}' is not a tooth space number (1, 2, …)", text::excerpt(f[0].text)));
    constexpr double kAnyPosition = 1e7; // mm, s, deg: finite is what matters
    r.z_stroke_mm = number(1, kAnyPosition);
    r.time_s = number(2, kAnyPosition);
    r.machine_axes.x = number(3, kAnyPosition);
    r.machine_axes.y = number(4, kAnyPosition);
    r.machine_axes.z = number(5, kAnyPosition);
    r.machine_axes.a = number(6, kAnyPosition) * units::kRadPerDeg;
    r.machine_axes.c = number(7, kAnyPosition) * units::kRadPerDeg;
    for (int a = 0; a < 3; ++a) r.correction(a) = units::mm_from_um(number(8 + a, kMaxCorrectionUm));
    for (int a = 3; a < 5; ++a) r.correction(a) = units::rad_from_urad(number(8 + a, kMaxCorrectionUm));
    const auto within = f[13].text;
    if (within != "yes" && within != "no")
      fail(lineno, f[13].column, "within_strokes", fmt::format("'{}' is neither yes nor no", text::excerpt(within)));
    r.within_strokes = within == "yes";
    if (!seen.emplace(r.space, r.z_stroke_mm).second)
      fail(lineno, f[1].column, "z_stroke_mm",
           fmt::format("space {} at {} mm is given twice", r.space, f[1].text));
    rows.push_back(r);
  }
  if (!header) fail(std::max(lineno, 1), 1, "header", fmt::format("missing header {}", header_text));
  if (rows.empty()) fail(lineno, 1, "rows", "no correction rows");
  return CorrectionTable(std::move(rows), axes);
}

CorrectionTable CorrectionTable::read_csv(const std::filesystem::path& file, ChainAxes axes) {
  auto in = input::open_input_file(file, input::kMaxMeasurementBytes, "corrections file");
  return read_csv(in, file.string(), axes);
}

} // namespace geartopo::compensation
