#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/core/atomic_file.hpp"
#include "geartopo/core/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>

namespace geartopo::compensation {

CorrectionTable::CorrectionTable(std::vector<CorrectionRow> rows) : rows_(std::move(rows)) {
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
  const auto hi = std::lower_bound(first, last, z);
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
  out << "space,z_stroke_mm,time_s,X_mm,Y_mm,Z_mm,A_deg,C_deg,dX_um,dY_um,dZ_um,dA_urad,dC_urad,within_strokes\n";
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

} // namespace geartopo::compensation
