// geartopo — axis corrections along the wheel path, as a controller would load them (docs/compensation.md).
// One row per path sample: which space, where along the stroke, when, the commanded machine axes and the five
// corrections. Between rows the corrections are interpolated linearly in the stroke position, as a controller's
// compensation table is. The axes are the scene's chain's own (ChainAxes: the CFXZAY's X, Y, Z, A, C are the setting's
// coordinates; on another chain its own axis letters in its pose order). Units: mm and rad inside; the CSV writes µm
// and µrad.
#pragma once

#include "geartopo/compensation/chain_axes.hpp"
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
  machine::AxisPose machine_axes; ///< commanded axes θ as the machine receives them (machine Z), the chain's pose order
  /// δX, δY, δZ (mm), εA, εC (rad) — the chain's axes in pose order — added to the command
  machine::Vector5d correction = machine::Vector5d::Zero();
  double residual_um = 0.0;       ///< what the method could not remove at this pose (its own measure, µm)
  bool within_strokes = true;     ///< the corrected command stays within the machine's strokes
};

class CorrectionTable {
public:
  /// Rows of every space, each space's rows in increasing stroke position, in the axes `axes` (default: the
  /// setting's, the CFXZAY's).
  explicit CorrectionTable(std::vector<CorrectionRow> rows, ChainAxes axes = {});

  /// Correction in space s at stroke position Z (linear between rows, held beyond the ends).
  machine::Vector5d at(int space, double z_stroke_mm) const;

  const std::vector<CorrectionRow>& rows() const { return rows_; }
  /// The axes the corrections and machine_axes are in.
  const ChainAxes& axes() const { return axes_; }
  /// Rows whose corrected command leaves a stroke (reported, never clipped).
  int rows_outside_strokes() const;
  /// Largest |correction| per axis: δX, δY, δZ (mm), εA, εC (rad).
  machine::Vector5d max_abs() const;

  /// Header: space,z_stroke_mm,time_s,X_mm,Y_mm,Z_mm,A_deg,C_deg,dX_um,dY_um,dZ_um,dA_urad,dC_urad,within_strokes
  /// (the chain's own axis letters in its pose order, e.g. U_mm and dU_um for a radial slide called U).
  void write_csv(std::ostream& out) const;
  void write_csv(const std::filesystem::path& file) const;
  /// The 14 names of that header, in order.
  std::vector<std::string> column_names() const;

  /// Reads what write_csv wrote (the header above, '#' comment lines and blank lines skipped, a UTF-8 BOM and CRLF
  /// accepted). Throws InputError at file:line:column and field for a wrong header, a field that is not a finite
  /// number, a space < 1, a correction beyond ±kMaxCorrectionUm (µm or µrad: a wrong unit), a (space, z_stroke_mm)
  /// given twice, no rows. `axes`: the scene's chain the table was written for (its letters in the header).
  static CorrectionTable read_csv(std::istream& in, const std::string& source, ChainAxes axes = {});
  static CorrectionTable read_csv(const std::filesystem::path& file, ChainAxes axes = {});

private:
  std::vector<CorrectionRow> rows_;
  ChainAxes axes_;
  std::vector<double> z_;                          // rows' stroke positions, for the search
  std::vector<std::pair<size_t, size_t>> span_;    // space → [first, last) rows; empty span: no rows
};

} // namespace geartopo::compensation
