// geartopo — the machine's error components as an ISG/Beckhoff TF5280 volumetric compensation table ("ISG CSV"),
// and the flank deviation such a table leaves (docs/compensation.md, "Controller table: ISG CSV").
//
// The format (public ISG kernel / Beckhoff TF5280 manual; what had to be assumed is marked [M] in the docs):
// whitespace-separated columns, a header naming the argument (X, Y, Z in mm; A, C in deg) and the ISO 230-1
// parameters (component errors EXX … ECC as functions of their axis; position errors X0C, C0Y, … as constants),
// values in mm (offsets) and rad (angles), `//` comment lines, `#` starting a new block with a new header.
// The file carries the machine's ERRORS (actual − nominal, the ISO 230 model); the controller computes from them the
// setpoint corrections it adds. It corrects the tool's POSITION only, not its orientation: what the orientation errors
// do to the flank is simulated (PositionCompensatedProcess) and reported.
//
// Mapping of our 43 components (error_component.hpp) to ISO 230-1 names, derived in the docs:
//   X, Y, Z:  EXk EYk EZk EAk EBk ECk = δ_xk δ_yk δ_zk ε_xk ε_yk ε_zk   (k = x, y, z; Y in the A body's axes [M])
//   A (α):    EXA = δ_xa, (EYA, EZA) = Rx(α)·(δ_ya, δ_za), EAA = ε_xa, (EBA, ECA) = Rx(α)·(ε_ya, ε_za)
//   C (γ):    (EXC, EYC) = Rz(γ)·(δ_xc, δ_yc), EZC = δ_zc, (EAC, EBC) = Rz(γ)·(ε_xc, ε_yc), ECC = ε_zc
//   constant: X0C Y0C A0C B0C C0C = E_XOC E_YOC E_AOC E_BOC E_COC; Y0A Z0A B0A C0A A0A = E_YOA E_ZOA E_BOA E_COA E_AOA;
//             C0Y = S_xy, A0Y = −S_zy, B0Z = −S_xz
// Units: mm and rad inside and in the file; arguments mm (X, Y, Z) and deg (A, C) in the file.
#pragma once

#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/machine_model.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace geartopo::compensation {

/// One block of an ISG CSV file: a header and its records.
struct IsgBlock {
  std::string argument;                    ///< "X", "Y", "Z" (mm), "A", "C" (deg); empty for the constants block
  std::vector<std::string> parameters;     ///< ISO 230-1 names in column order: "EXX", …, or "X0C", "C0Y", …
  std::vector<double> arguments;           ///< one per record, mm or deg, equidistant and increasing; empty: constants
  std::vector<std::vector<double>> values; ///< [record][parameter], mm or rad; one record for the constants block
  std::vector<std::string> comments;       ///< written as `//` lines before the header
};

struct IsgTable {
  std::vector<std::string> comments; ///< written as `//` lines at the top of the file
  std::vector<IsgBlock> blocks;
  /// Records (data rows) over all blocks: what the controller's vol_comp[i].max_records bounds.
  int records() const;
};

/// The controller's limits the table must respect.
struct IsgLimits {
  /// The controller's vol_comp[i].max_records (the manual's example value; set it to the controller's configuration).
  int max_records = 2000;
  /// Largest departure of an argument step from the block's mean step, in the argument's file unit (mm or deg).
  double step_tolerance = 1e-6;
};

/// What make_isg_table samples and how.
struct IsgOptions {
  double linear_step_mm = 10.0;  ///< largest grid step of X, Y, Z blocks when sampling (polynomials, resampled tables)
  double rotary_step_deg = 1.0;  ///< the same for A and C
  IsgLimits limits;
};

/// The ISG table of a machine model. Per axis the grid is the knots of its tables when all of them share one
/// equidistant grid (values exact); otherwise an equidistant grid over the stroke (C: [0, 360] deg) no coarser than
/// the options' step, sampled from the sources — a resampled table is said so in the block's comments. Axes whose
/// components are all constant get two records, the ends of the stroke. Throws InputError naming the source table
/// (file, line, column) when its own grid already exceeds limits.max_records, std::invalid_argument for bad options.
IsgTable make_isg_table(const machine::MachineModel& model, const IsgOptions& options = {});

/// The ISG table of a machine model on `chain`: the CFXZAY's table above when it is the setting chain (the same bytes);
/// otherwise one block per axis in chain order, named by the chain's letters — its component errors relative to the
/// body that carries it, in that body's axes, a rotary axis' turned into the fixed axes — and the position errors of
/// its rotary axis lines and its squareness named for its axes; the comments give ISG's `chain` (the letters from the
/// workpiece to the tool) and `workpiece_axes` (docs/compensation.md). std::invalid_argument for a chain letter ISG
/// has no name for (U, V, W) and as make_isg_table above.
IsgTable make_isg_table(const machine::MachineModel& model, const machine::KinematicChain& chain,
                        const IsgOptions& options = {});

/// The ISO 230-1 component errors of one axis at its position (mm or rad, internal), in the block's column order
/// (EXk EYk EZk EAk EBk ECk), mapped as in the header above.  // 6×1
Eigen::Matrix<double, 6, 1> iso_component_errors(const machine::MachineModel& model, machine::Axis axis,
                                                 double position);

/// Refuses a table the controller would refuse: std::invalid_argument naming the block ("block 2 'Y EXY …'") and the
/// limit when arguments are not equidistant or not increasing, a record's width differs from its header, a value is
/// not finite, or the records exceed limits.max_records.
void check_isg_table(const IsgTable& table, const IsgLimits& limits);

/// check_isg_table, then the file text. Arguments with 6 decimals, lengths with 9 (mm), angles with 12 (rad).
void write_isg_table(std::ostream& out, const IsgTable& table, const IsgLimits& limits);
/// The same, atomically (output::write_atomically).
void write_isg_table(const std::filesystem::path& file, const IsgTable& table, const IsgLimits& limits);

/// The machine after a position-only compensation: the inner process's wheel orientation error is kept and its
/// position error at the tool centre point removed — the TCP sits where the ideal chain puts it. This is what a
/// volumetric table that corrects "tool position, not orientation" leaves (to first order in the errors: the
/// controller's small X, Y, Z moves change the orientation error only at second order). The wheel radius error is
/// passed through (no machine table carries it).
class PositionCompensatedProcess final : public grinding::GrindingProcess {
public:
  /// tcp_g: the controller's tool centre point in the wheel frame g, mm (the wheel centre: zero) [M].
  PositionCompensatedProcess(const grinding::GrindingProcess& inner, const Eigen::Vector3d& tcp_g)
      : inner_(inner), tcp_g_(tcp_g) {}

  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override;
  /// (tcp_w × δθ; δθ): the inner rotation δθ about the TCP, tcp_w = wMg_ideal·tcp_g.  // 6×1
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override;
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    return inner_.wheel_radius_error_mm(v, pp);
  }
  bool changes_wheel_radius() const override { return inner_.changes_wheel_radius(); }

private:
  const grinding::GrindingProcess& inner_;
  Eigen::Vector3d tcp_g_;
};

} // namespace geartopo::compensation
