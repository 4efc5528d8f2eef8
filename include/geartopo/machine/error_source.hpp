// geartopo — where one error component's values come from: a constant, a polynomial in the axis position,
// or a measured table interpolated by a C² cubic spline (periodic for C).
//
// A table column may carry its standard uncertainty u(p) (k = 1) from a `u_<component>_<unit>` column of the same
// file (docs/error-components.md, "Uncertainty columns"); drawn() turns it into one Monte Carlo draw.
//
// Units: constructors take the user's units by name ("um", "urad", "mm", "deg", …) and convert once; value()
// and rate() work in internal units — position in mm (X, Y, Z) or rad (A, C), value in mm (δ, offsets) or
// rad (ε, S, tilts, zero-position errors); uncertainty() likewise.
#pragma once

#include "geartopo/core/cubic_spline.hpp"
#include "geartopo/machine/error_component.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace geartopo::machine {

/// Where a table column came from, for messages ("file:line:column: field: …").
struct TableOrigin {
  std::string file;           ///< path as given
  int header_line = 0;        ///< 1-based line of the header
  int first_line = 0;         ///< 1-based line of the first data row
  int last_line = 0;          ///< 1-based line of the last data row
  int column = 0;             ///< 1-based field number of the value column
  std::string field;          ///< header text of the value column, e.g. "delta_xx_um"
  std::string position_field; ///< header text of the position column, e.g. "x_mm"
  std::string position_unit;  ///< "mm", "deg", … (as in the file, for messages)
  double position_scale = 1;  ///< file position unit → internal (mm or rad)
  int uncertainty_column = 0; ///< 1-based field number of the column's `u_…` column; 0: the table gives none
  std::string uncertainty_field; ///< its header text, e.g. "u_delta_xx_um"; empty: none
};

class ErrorSource {
public:
  enum class Kind { Constant, Polynomial, Table };

  /// Zero error (the default of every component in a MachineModel).
  static ErrorSource zero(ComponentId id);
  /// A constant, e.g. constant(ComponentId::S_xy, 12.0, "urad"). Throws std::invalid_argument if the unit
  /// is unknown, is not of the component's quantity, or the value is not finite.
  static ErrorSource constant(ComponentId id, double value, std::string_view unit);
  /// value(p) = Σ c_i·p^i with p in `position_unit` and the value in `value_unit`, e.g.
  /// polynomial(ComponentId::delta_xx, {0.0, 0.01, 2e-6}, "um", "mm") = 0.01 µm/mm·x + 2e-6 µm/mm²·x².
  /// Throws std::invalid_argument for constants-only components (S, E_…) unless of degree 0, for C-axis
  /// components unless of degree 0 (a polynomial is not periodic: use a periodic table), for bad units or
  /// non-finite coefficients.
  static ErrorSource polynomial(ComponentId id, std::vector<double> coefficients, std::string_view value_unit,
                                std::string_view position_unit);
  /// A table column already checked by the loader (error_table.hpp): spline in internal units.
  static ErrorSource table(ComponentId id, CubicSpline spline, TableOrigin origin);
  /// The same with the column's standard uncertainty u(p) (k = 1, internal units, ≥ 0 at the knots): a spline with the
  /// same knots and ends as `spline`, already checked by the loader; origin.uncertainty_column names it.
  static ErrorSource table(ComponentId id, CubicSpline spline, TableOrigin origin, CubicSpline uncertainty);
  /// The same source plus a constant (internal units: mm or rad), e.g. one Monte Carlo draw of a calibration's
  /// uncertainty (pipeline/monte_carlo.hpp). rate() is unchanged. Throws std::invalid_argument if not finite.
  ErrorSource shifted(double offset) const;
  /// One draw of the component as a calibration knows it, z a standard normal deviate: value(p) + z·u(p) with u(p) the
  /// table's uncertainty column, fully correlated along the axis (one z for every position); without a column,
  /// shifted(default_u·z), the constant u of the scene's `machine.uncertainty` (default_u: mm or rad).
  /// docs/monte-carlo.md, "The model". Throws std::invalid_argument if the draw is not finite.
  ErrorSource drawn(double z, double default_u) const;

  ComponentId id() const { return id_; }
  Kind kind() const { return kind_; }
  bool is_zero() const { return kind_ == Kind::Constant && constant_ == 0.0 && offset_ == 0.0; }

  /// Component value at the position of its own axis (mm or rad in, mm or rad out). No allocation.
  double value(double position) const noexcept;
  /// value(position) for a table, given where position falls among the knots of a spline with the same knots as
  /// this table's (CubicSpline::locate): the same bits. Table only.
  double value_at(const CubicSpline::Location& where) const noexcept {
    const double v = spline_.value_at(where) + offset_;
    return draw_ == 0.0 ? v : v + draw_ * clamped_uncertainty(uncertainty_.value_at(where));
  }
  /// d value / d position (mm/mm, mm/rad, rad/mm or rad/rad). No allocation.
  double rate(double position) const noexcept;

  /// True for a table column with a `u_…` column (docs/error-components.md, "Uncertainty columns").
  bool has_uncertainty_column() const { return has_uncertainty_; }
  /// The column's standard uncertainty at `position` (mm or rad in, mm or rad out): the u column interpolated like
  /// the values, held at 0 where the spline would dip below (a standard uncertainty is never negative). 0 without a
  /// column. No allocation.
  double uncertainty(double position) const noexcept;

  /// Table only (nullptr otherwise): origin and spline, for stroke checks and messages.
  const TableOrigin* origin() const { return kind_ == Kind::Table ? &origin_ : nullptr; }
  const CubicSpline* spline() const { return kind_ == Kind::Table ? &spline_ : nullptr; }

  /// "constant", "polynomial of degree 2" or "table file.csv column 2 'delta_xx_um'", for messages.
  std::string describe() const;

private:
  ErrorSource(ComponentId id, Kind kind) : id_(id), kind_(kind) {}
  static double clamped_uncertainty(double u) noexcept { return u > 0.0 ? u : 0.0; }

  ComponentId id_;
  Kind kind_;
  double constant_ = 0.0;           // internal units
  double offset_ = 0.0;             // added to every value (shifted), internal units
  std::vector<double> coefficients_; // internal units, ascending powers
  CubicSpline spline_;
  TableOrigin origin_;
  CubicSpline uncertainty_;  // the u column, same knots as spline_ (has_uncertainty_), internal units
  bool has_uncertainty_ = false;
  double draw_ = 0.0;        // z of drawn(): value adds draw_·u(p)
};

} // namespace geartopo::machine
