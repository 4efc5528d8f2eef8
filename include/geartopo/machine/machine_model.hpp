// geartopo — the machine model: axis strokes and the 43 error sources (Pinocchio style: const, shared;
// all per-evaluation results go to a MachineData workspace, machine_data.hpp).
// Units: X, Y, Z strokes in mm, A stroke in deg (as data sheets give it), C a full turn; inside mm and rad.
#pragma once

#include <array>
#include <cstdint>

#include "geartopo/machine/axis_pose.hpp"
#include "geartopo/machine/error_component.hpp"
#include "geartopo/machine/error_source.hpp"

#include <vector>

namespace geartopo::machine {

struct Interval {
  double min = 0.0;
  double max = 0.0;
};

/// Travel limits. C turns without limit (error tables for C are periodic over one turn).
struct Strokes {
  Interval x_mm;  ///< X, mm
  Interval y_mm;  ///< Y, mm
  Interval z_mm;  ///< Z, mm
  Interval a_deg; ///< A, deg

  /// The paper's SKMC-1200W/10 (Section 4: X900 Y400 Z800 mm, A [−45, 45] deg, C [0, 360] deg).
  /// The zero positions are not published: we assume X and Z start at 0 and Y is centred, [−200, 200].
  static Strokes skmc_1200w() { return {{0.0, 900.0}, {-200.0, 200.0}, {0.0, 800.0}, {-45.0, 45.0}}; }
};

class MachineModel {
public:
  /// An error-free machine. Throws std::invalid_argument if a stroke is empty or not finite.
  explicit MachineModel(const Strokes& strokes);
  /// A machine with the given error sources; components not given are zero. Throws InputError
  /// (error_table.hpp) when a table does not cover its axis' stroke — the message names the file, the line
  /// of the first or last row and the position column — and std::invalid_argument when a component is
  /// given twice or a stroke is invalid.
  MachineModel(const Strokes& strokes, std::vector<ErrorSource> sources);

  const Strokes& strokes() const { return strokes_; }
  const ErrorSource& source(ComponentId id) const { return sources_[static_cast<std::size_t>(index(id))]; }
  /// True when X, Y, Z and A lie within their strokes (C always does).
  bool within_strokes(const AxisPose& q) const;

  /// All component values at q, e(k) = source k evaluated at its own axis' position (mm, rad). The squareness
  /// and location components are constants. No allocation.
  void errors_at(const AxisPose& q, ErrorVector& e) const noexcept;
  /// de(k) = d e(k) / d(position of component k's axis): mm/mm, rad/mm, mm/rad or rad/rad. No allocation.
  void error_rates_at(const AxisPose& q, ErrorVector& de) const noexcept;
  /// Only the position-dependent components of `axis`, at `position` (mm or rad): the others of e are left as they
  /// are. For evaluators that reuse the components of axes that did not move (ChainEvaluator, chain.hpp).
  void axis_errors_at(Axis axis, double position, ErrorVector& e) const noexcept;

  /// Identifies the model's content: a model and its copies share it, models constructed separately never do (a
  /// process-wide counter). Caches keyed by it never confuse two models, even one built where another was freed.
  std::uint64_t id() const { return id_; }

private:
  void check_coverage(const ErrorSource& s) const;

  Strokes strokes_;
  std::vector<ErrorSource> sources_; // kComponentCount entries, indexed by ComponentId
  std::uint64_t id_;
  /// Per axis: its position-dependent components, table columns that share their knots grouped (one spline search for
  /// the group, CubicSpline::value_at), then the others (polynomials, constants of a moving axis).
  struct AxisComponents {
    std::vector<std::vector<int>> shared_knots; ///< groups of table components with identical knots
    std::vector<int> others;
  };
  std::array<AxisComponents, kAxisCount> varying_on_;
};

} // namespace geartopo::machine
