// geartopo — a five-axis profile grinder's kinematic chain as data (docs/machine-model.md §1–2): the bodies from the
// workpiece to the wheel, each moving axis with its name, kind, direction and nominal offset in its parent frame, and
// which axes carry the workpiece and which the wheel; the 43 ISO 230-1 error components that chain has and their
// names; its inverse kinematics (the axis values that make a wheel–gear setting) and its ideal forward kinematics.
// The seed paper's CFXZAY is a preset, and so are the CAFXZY (swivel on the workpiece side) and the CXFZAY (radial
// axis on the workpiece side); docs/machine-model.md cites the sources.
//
// Conventions (how a CNC control describes a machine: Beckhoff TF5240 "universal kinematics", Heidenhain's
// kinematics table, ISG TF5280 `chain` and `workpiece_axes`):
//   - All body frames are parallel at the home pose (every axis at 0); an offset is a translation. The gear axis is z
//     (the workpiece spindle turns about ±z), the wheel spindle is y of the wheel frame.
//   - The chain lists the workpiece side from the workpiece towards the bed and the tool side from the bed towards
//     the wheel. A joint is written parent → child as the machine is built (the bed carries both sides), so the
//     workpiece side enters wMg inverted: wMg = M_w1⁻¹ · M_w2⁻¹ ⋯ · M_t1 · M_t2 ⋯ .
//   - Three linear axes and two rotary axes: the workpiece spindle (the first body from the workpiece, about ±z, turns
//     without limit) and the swivel that sets the cross angle (about ±x: perpendicular to the gear axis and to the
//     wheel spindle at home). Anything else cannot make a profile grinder's wheel–gear motion and is refused.
//   - Pose order (slots of AxisValues, columns of J_*_θ, blocks of ErrorVector): the linear axes in ISO 841 letter
//     order (X Y Z U V W), then the swivel, then the spindle — the CFXZAY's (X, Y, Z, A, C).
// Units: mm and rad inside (strokes too); deg only where a file or message says so.
#pragma once

#include "geartopo/machine/axis_pose.hpp"
#include "geartopo/machine/error_component.hpp"
#include "geartopo/machine/machine_model.hpp" // Interval
#include "geartopo/machine/twist.hpp"

#include <Eigen/Core>

#include <array>
#include <deque>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::machine {

enum class AxisKind { Linear, Rotary };

/// One moving axis as a description gives it.
struct AxisSpec {
  std::string name;                 ///< one ISO 841 letter: X Y Z U V W (linear), A B C (rotary)
  AxisKind kind = AxisKind::Linear;
  /// Direction of its positive motion (linear) or its positive turn (rotary, right-handed) in its parent frame:
  /// along ±x, ±y or ±z, any length > 0.
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  Eigen::Vector3d offset_mm = Eigen::Vector3d::Zero(); ///< its frame at position 0 in its parent frame (mm)
  /// Travel limits, mm (linear) or rad (rotary); none: a rotary axis that turns without limit (the spindle).
  std::optional<Interval> stroke;
};

/// A chain: the axes carrying the workpiece and those carrying the wheel.
struct ChainSpec {
  std::string name;                ///< "CFXZAY", or what a machine file calls it
  std::vector<AxisSpec> workpiece; ///< from the workpiece towards the bed: workpiece.front() carries the gear
  std::vector<AxisSpec> tool;      ///< from the bed towards the wheel: tool.back() carries the wheel
};

/// True when two descriptions are the same, field by field (make_chain keeps one chain per description).
bool same_spec(const ChainSpec& a, const ChainSpec& b);

/// A description refused: which axis (its index in workpiece then tool order; −1 for the chain as a whole), which of
/// its fields ("name", "kind", "direction", "offset_mm", "stroke"; empty for the chain) and why.
class ChainError : public std::runtime_error {
public:
  ChainError(int axis, std::string field, const std::string& message)
      : std::runtime_error(message), axis_(axis), field_(std::move(field)) {}
  int axis() const noexcept { return axis_; }
  const std::string& field() const noexcept { return field_; }

private:
  int axis_;
  std::string field_;
};

/// The chain's own axis positions in pose order (slots 0–4): what its controller is commanded. mm and rad.
struct AxisValues {
  Vector5d v = Vector5d::Zero();
  double operator[](Axis a) const { return v(static_cast<int>(a)); }
  double& operator[](Axis a) { return v(static_cast<int>(a)); }
};

/// The chain's inverse kinematics at one setting.
struct InverseKinematics {
  AxisValues theta;
  /// det of the three linear axes' unit directions in the workpiece frame (|det| ≤ 1). Near 0 the configuration is
  /// singular: the linear axes cannot move the wheel centre in some direction (e.g. the cross angle at 90°).
  double linear_det = 1.0;
};

/// Below this |det| a configuration is refused as singular: a direction the linear axes can move along at less than
/// 10⁻³ of their travel (a wheel-centre error of 1 µm would need 1 mm of axis travel).
inline constexpr double kSingularDet = 1e-3;

/// One joint of the chain, compiled from its AxisSpec: what the evaluators need (src/machine/chain_joints.hpp).
struct Joint {
  Axis slot = Axis::X;
  AxisKind kind = AxisKind::Linear;
  int dir = 0;                ///< coordinate index of the direction (0 x, 1 y, 2 z)
  double sign = 1.0;          ///< +1 or −1: the direction along +dir or −dir
  bool workpiece_side = false;
  bool carries_workpiece = false;  ///< the spindle: the workpiece sits on its actual axis line (no trailing S⁻¹)
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  bool has_offset = false;
  int motion = 0;             ///< index of its δ_x: δ_x δ_y δ_z ε_x ε_y ε_z follow
  std::array<int, 2> perpendicular{}; ///< rotary: the two coordinate indices across its axis, ascending
  int location = -1;          ///< rotary: index of its first location error (two offsets, two tilts, the zero)
  int squareness_count = 0;   ///< linear: squareness to the linear axes before it in the chain (0, 1 or 2)
  std::array<int, 2> squareness{};             ///< their component indices
  std::array<Eigen::Vector3d, 2> lean{};        ///< the unit direction each leans away from, in the parent frame
};

/// A five-axis profile grinder's chain. Immutable; made only by make_chain or a preset, which keep every chain alive
/// until the program ends, so a pointer to one stays valid (error sources and component changes hold one).
class KinematicChain {
public:
  const std::string& name() const { return spec_.name; }
  const ChainSpec& spec() const { return spec_; }
  /// The bodies from the workpiece to the wheel with F for the bed: "CFXZAY".
  const std::string& layout() const { return layout_; }

  /// The axis in pose slot `slot`.
  const AxisSpec& axis(Axis slot) const { return *axes_[static_cast<std::size_t>(slot)]; }
  std::string_view axis_name(Axis slot) const { return axis(slot).name; }
  bool is_rotary(Axis slot) const { return axis(slot).kind == AxisKind::Rotary; }
  bool on_workpiece_side(Axis slot) const;
  /// The slot of the axis called `name` (exact, or its lower case: "x" for X); none if the chain has no such axis.
  std::optional<Axis> axis_named(std::string_view name) const;
  /// The chain's joints from the workpiece to the wheel (workpiece side first).
  const std::array<Joint, kAxisCount>& joints() const { return joints_; }

  /// Every one of the 43 components of this chain: name, symbol, axis slot, quantity, meaning
  /// (docs/error-components.md, "Naming").
  const ComponentInfo& info(ComponentId id) const { return info_[static_cast<std::size_t>(index(id))]; }
  /// The component called `name` ("delta_xx", "S_xy", "E_XOC" on the CFXZAY); none if this chain has none.
  std::optional<ComponentId> component_from_name(std::string_view name) const;

  /// True when the chain's axes are the setting's own coordinates (the CFXZAY): its inverse kinematics is the identity,
  /// AxisValues{q.vector()} exactly. Found by comparing the description with the CFXZAY's, names aside.
  bool is_setting_chain() const { return setting_chain_; }

  /// The axis values that make the wheel–gear setting q (Eq. 11's pose; q.z along the gear axis from the workpiece
  /// frame's origin), by the general inverse kinematics of any chain (also for the CFXZAY, where it must give q):
  /// the swivel and the spindle from the cross angle and the turn, the linear axes from the wheel centre (a 3×3
  /// solve). Strokes are not checked (outside_stroke). Never throws; NaN linear values when singular (|det| < 1e-3).
  InverseKinematics solve(const AxisPose& q) const;
  /// solve(q).theta; for a setting chain q itself, exactly (no rounding of the 3×3 solve).
  AxisValues axes(const AxisPose& q) const;
  /// The setting the chain makes at θ: Eq. 11 inverted on its ideal pose (the forward kinematics in setting terms).
  AxisPose setting(const AxisValues& theta) const;
  /// The ideal wheel pose at θ (the chain without errors).  wMg
  Pose ideal_wMg(const AxisValues& theta) const;

  /// The first axis (in pose order) outside its stroke at θ, with a message "Y = 250.000 mm is outside its stroke
  /// [−200, 200] mm"; none when all are within. The spindle turns without limit.
  struct StrokeViolation {
    Axis axis;
    std::string message;
  };
  std::optional<StrokeViolation> outside_stroke(const AxisValues& theta) const;
  bool within_strokes(const AxisValues& theta) const { return !outside_stroke(theta); }
  /// "mm" or "deg" (the file unit of the axis' positions).
  std::string_view position_unit(Axis slot) const { return is_rotary(slot) ? "deg" : "mm"; }

  /// The same chain with other strokes (a scene's `strokes`), made and kept like make_chain's.
  const KinematicChain& with_strokes(const std::array<std::optional<Interval>, kAxisCount>& strokes) const;

private:
  explicit KinematicChain(ChainSpec spec);
  friend const KinematicChain& make_chain(ChainSpec spec);
  // The constructor's steps (kinematic_chain.cpp).
  const AxisSpec& at(int position) const; ///< in workpiece then tool order
  Axis slot_at(int position) const;
  std::string_view keep(std::string s);   ///< stored in strings_, viewed by info_
  int validate() const;                   ///< throws ChainError; returns the swivel's position
  void order_axes(int swivel);            ///< pose order, layout
  void name_components();                 ///< info_
  void compile_joints();                  ///< joints_
  bool is_setting_layout() const;

  ChainSpec spec_;
  std::string layout_;
  std::array<const AxisSpec*, kAxisCount> axes_{}; // by slot, into spec_
  std::array<int, kAxisCount> chain_position_{};   // by slot: index in workpiece then tool order
  std::array<Joint, kAxisCount> joints_{};         // in chain order
  int workpiece_count_ = 0;
  std::array<ComponentInfo, kComponentCount> info_{};
  std::deque<std::string> strings_; // the names, symbols and meanings info_ views (a deque never moves them)
  bool setting_chain_ = false;
};

/// Validates `spec` (ChainError names the axis and the field) and returns the chain, kept until the program ends; an
/// equal description gives the same object.
const KinematicChain& make_chain(ChainSpec spec);

/// The seed paper's CFXZAY grinder (SKMC-1200W/10 strokes): w → C → F → X → Z → A → Y → g.
const KinematicChain& cfxzay();
/// A component's name, symbol and meaning as `chain` names it (null: the CFXZAY's, info(id)).
inline const ComponentInfo& info(const KinematicChain* chain, ComponentId id) { return chain ? chain->info(id) : info(id); }
/// A preset by name (chain_preset_names()); none if unknown.
const KinematicChain* chain_preset(std::string_view name);
/// "CFXZAY", "CAFXZY", "CXFZAY".
std::vector<std::string_view> chain_preset_names();

} // namespace geartopo::machine
