// geartopo evaluation — profile and helix deviations of one measured trace (ISO 1328-1:2013 clause 3; see
// docs/iso1328.md for the rules, their sources and confidence labels).
//
// Units: positions in mm (roll length ξ for a profile trace, axial position z from the datum face for a helix
// trace); deviations in µm, plus material positive, in whatever direction they are given (evaluate_gear passes the
// normal deviations and scales the results to the reported direction).
#pragma once

#include "geartopo/core/flank.hpp"
#include <cstddef>
#include <vector>

namespace geartopo::evaluation {

using geartopo::to_string; // Flank (core/flank.hpp)

/// A trace may miss each end of its evaluation range by up to this much (mm) and still count as covering it.
inline constexpr double kRangeSlackMm = 1e-3;

/// One measured trace: deviation (µm) against position (mm), plus the evaluation range [range_start_mm,
/// range_end_mm] in the same positional unit. Points may extend beyond the range; only the part inside is evaluated.
struct Trace {
  std::vector<double> position_mm;  ///< strictly increasing; ξ (profile, towards the tip) or z (helix, into the gear)
  std::vector<double> deviation_um; ///< normal deviation, plus material positive; same length as position_mm
  double range_start_mm = 0.0;      ///< L_α / L_β start (the caller supplies the range, see docs/iso1328.md)
  double range_end_mm = 0.0;        ///< L_α / L_β end
};

/// The three deviations of a trace over its evaluation range, plus the mean line they derive from.
struct TraceDeviations {
  double total_um = 0.0; ///< F_α / F_β: max − min of the trace (design trace = zero line, unmodified flank)
  double form_um = 0.0;  ///< f_fα / f_fβ: peak-to-valley of the residuals from the least-squares mean line
  double slope_um = 0.0; ///< f_Hα / f_Hβ: signed rise of the mean line across the range (slope × length)
  double mean_line_mid_um = 0.0;          ///< mean line value at the middle of the range
  double mean_line_slope_um_per_mm = 0.0; ///< mean line slope
  double range_length_mm = 0.0;           ///< range_end_mm − range_start_mm
  std::size_t points_in_range = 0;        ///< measured points with range_start ≤ position ≤ range_end
};

/// Evaluates a trace over its range.
///
/// The trace is taken as the polyline through its points, cut at the range ends (a range end between two points is
/// interpolated linearly; a point exactly on it is used as is). The mean line is the least-squares line of that
/// polyline over the range (the integral of the squared residual is minimised, so the fit does not depend on how
/// densely any part of the range is sampled). Extremes are taken over the polyline's vertices, which is exact for a
/// polyline.
///
/// Slope sign of one trace: f_H > 0 when material increases towards increasing position (profile: the tip; helix: away
/// from the datum face). evaluate_gear turns the helix value into the standard's f_Hβ per flank and hand and scales
/// every value to the reported direction (gear_evaluation.hpp, IsoConventions; docs/iso1328.md).
///
/// Throws std::invalid_argument (with the reason) for: position/deviation size mismatch, non-finite values, positions
/// not strictly increasing, an empty or non-finite range, a range not covered by the points (a shortfall up to
/// 1e-9 × range length is tolerated), or fewer than 3 measured points inside the range.
TraceDeviations evaluate_trace(const Trace& trace);

} // namespace geartopo::evaluation
