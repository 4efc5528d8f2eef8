// geartopo — axis corrections along the wheel path, as a controller would load them (docs/compensation.md).
// One row per path sample: which space, where along the stroke, when, the commanded machine axes and the five
// corrections. Between rows the corrections are interpolated linearly in the stroke position, as a controller's
// compensation table is. Units: mm and rad inside; the CSV writes µm and µrad.
#pragma once

#include "geartopo/machine/axis_pose.hpp"

#include <filesystem>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace geartopo::compensation {

/// Largest |correction| a correction file may hold, in its units (µm, µrad): a grinder's corrections are some tens of
/// µm; beyond a millimetre (a milliradian) the file is in another unit or broken.
inline constexpr double kMaxCorrectionUm = 1000.0;

struct CorrectionRow {
  int space = 1;
  double z_stroke_mm = 0.0;       ///< stroke position in gear coordinates (datum face = 0)
  double time_s = 0.0;
  machine::AxisPose machine_axes; ///< commanded axes as the machine receives them (machine Z)
  machine::Vector5d correction = machine::Vector5d::Zero(); ///< δX, δY, δZ (mm), εA, εC (rad), added to the command
  double residual_um = 0.0;       ///< what the method could not remove at this pose (its own measure, µm)
  bool within_strokes = true;     ///< the corrected command stays within the machine's strokes
};

class CorrectionTable {
public:
  /// Rows of every space, each space's rows in increasing stroke position.
  explicit CorrectionTable(std::vector<CorrectionRow> rows);

  /// Correction in space s at stroke position Z (linear between rows, held beyond the ends).
  machine::Vector5d at(int space, double z_stroke_mm) const;

  const std::vector<CorrectionRow>& rows() const { return rows_; }
  /// Rows whose corrected command leaves a stroke (reported, never clipped).
  int rows_outside_strokes() const;
  /// Largest |correction| per axis: δX, δY, δZ (mm), εA, εC (rad).
  machine::Vector5d max_abs() const;

  /// Header: space,z_stroke_mm,time_s,X_mm,Y_mm,Z_mm,A_deg,C_deg,dX_um,dY_um,dZ_um,dA_urad,dC_urad,within_strokes
  void write_csv(std::ostream& out) const;
  void write_csv(const std::filesystem::path& file) const;

  /// Reads what write_csv wrote (the header above, '#' comment lines and blank lines skipped, a UTF-8 BOM and CRLF
  /// accepted). Throws InputError at file:line:column and field for a wrong header, a field that is not a finite
  /// number, a space < 1, a correction beyond ±kMaxCorrectionUm (µm or µrad: a wrong unit), a (space, z_stroke_mm)
  /// given twice, no rows.
  static CorrectionTable read_csv(std::istream& in, const std::string& source);
  static CorrectionTable read_csv(const std::filesystem::path& file);

private:
  std::vector<CorrectionRow> rows_;
  std::vector<double> z_;                          // rows' stroke positions, for the search
  std::vector<std::pair<size_t, size_t>> span_;    // space → [first, last) rows; empty span: no rows
};

} // namespace geartopo::compensation
