// geartopo — the kinematic chain as data: validation, pose order, the ISO 230-1 components and their names, the
// presets, the inverse and ideal forward kinematics (kinematic_chain.hpp, docs/machine-model.md §1–2). Units: mm, rad.
#include "geartopo/machine/kinematic_chain.hpp"

#include "geartopo/core/units.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/transforms.hpp"

#include <Eigen/LU>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>

namespace geartopo::machine {

namespace {

constexpr std::string_view kLinearLetters = "XYZUVW"; // ISO 841: pose order of the linear axes
constexpr std::string_view kRotaryLetters = "ABC";
constexpr std::string_view kCoordinate = "xyz";
constexpr std::string_view kCoordinateUpper = "XYZ";
constexpr std::string_view kRotationUpper = "ABC"; // rotations about x, y, z (ISO 841)

char lower(char c) { return static_cast<char>(c - 'A' + 'a'); }

/// The coordinate index of a direction along ±x, ±y or ±z, and its sign; none when it is not along one.
std::optional<std::pair<int, double>> coordinate_direction(const Eigen::Vector3d& d) {
  const double n = d.norm();
  int k = 0;
  d.cwiseAbs().maxCoeff(&k);
  for (int i = 0; i < 3; ++i)
    if (i != k && std::abs(d(i)) > 1e-12 * n) return std::nullopt;
  return std::pair{k, d(k) > 0.0 ? 1.0 : -1.0};
}

std::string interval_text(const Interval& s, bool rotary) {
  const double k = rotary ? units::kDegPerRad : 1.0;
  return fmt::format("[{:g}, {:g}] {}", s.min * k, s.max * k, rotary ? "deg" : "mm");
}

/// Checks one axis on its own (ChainError at index i).
void check_axis(const AxisSpec& a, int i) {
  const std::string_view letters = a.kind == AxisKind::Linear ? kLinearLetters : kRotaryLetters;
  if (a.name.size() != 1 || letters.find(a.name[0]) == std::string_view::npos)
    throw ChainError(i, "name",
                     fmt::format("'{}' is not a {} axis name: one ISO 841 letter of {}", a.name,
                                 a.kind == AxisKind::Linear ? "linear" : "rotary", letters));
  if (!a.direction.allFinite() || !(a.direction.norm() > 1e-12))
    throw ChainError(i, "direction", fmt::format("axis {}: the direction has zero length", a.name));
  if (!coordinate_direction(a.direction))
    throw ChainError(i, "direction",
                     fmt::format("axis {}: the direction ({:g}, {:g}, {:g}) is not along ±x, ±y or ±z (every body frame "
                                 "is parallel at the home pose; describe the machine in such axes)",
                                 a.name, a.direction.x(), a.direction.y(), a.direction.z()));
  if (!a.offset_mm.allFinite()) throw ChainError(i, "offset_mm", fmt::format("axis {}: the offset is not finite", a.name));
  if (a.stroke && !(std::isfinite(a.stroke->min) && std::isfinite(a.stroke->max) && a.stroke->max > a.stroke->min))
    throw ChainError(i, "stroke", fmt::format("axis {}: the stroke is not a finite, non-empty interval", a.name));
}

/// The meaning of motion component k (0..5: δ_x δ_y δ_z ε_x ε_y ε_z) of an axis, in the words of
/// docs/error-components.md (the CFXZAY's words: X's pitch and yaw, Y "along the spindle", the C "table").
std::string motion_meaning(const AxisSpec& a, int dir, int k, bool spindle, bool along_wheel_spindle) {
  const char c = kCoordinate[static_cast<std::size_t>(k % 3)];
  const bool own = k % 3 == dir;
  const std::string& n = a.name;
  if (a.kind == AxisKind::Linear) {
    if (k < 3) {
      if (!own) return fmt::format("straightness of {} in {}", n, c);
      return along_wheel_spindle ? fmt::format("positioning error of {} (along the spindle)", n)
                                 : fmt::format("positioning error of {} (along {})", n, c);
    }
    if (own) return fmt::format("roll of {} (about {})", n, c);
    if (dir == 0) return fmt::format("{} of {} (about {})", c == 'y' ? "pitch" : "yaw", n, c);
    return fmt::format("angular error of {} about {}", n, c);
  }
  const std::string body = spindle ? "the table's" : fmt::format("the {} body's", n);
  if (k < 3)
    return own ? fmt::format("axial error motion of {} (along {})", n, c)
               : fmt::format("radial error motion of {} along {} {}", n, body, c);
  return own ? fmt::format("angular positioning error of {} (about {})", n, c)
             : fmt::format("tilt error motion of {} about {} {}", n, body, c);
}

std::vector<std::unique_ptr<KinematicChain>>& chain_store() {
  static std::vector<std::unique_ptr<KinematicChain>> store;
  return store;
}
std::mutex& chain_store_mutex() {
  static std::mutex m;
  return m;
}

// --- Presets (docs/machine-model.md §1, "Presets", cites the sources) ---------------------------------------------

AxisSpec linear(std::string name, Eigen::Vector3d dir, Interval stroke, Eigen::Vector3d offset = Eigen::Vector3d::Zero()) {
  return {std::move(name), AxisKind::Linear, dir, offset, stroke};
}
AxisSpec rotary(std::string name, Eigen::Vector3d dir, std::optional<Interval> stroke_deg,
                Eigen::Vector3d offset = Eigen::Vector3d::Zero()) {
  std::optional<Interval> stroke;
  if (stroke_deg) stroke = Interval{stroke_deg->min * units::kRadPerDeg, stroke_deg->max * units::kRadPerDeg};
  return {std::move(name), AxisKind::Rotary, dir, offset, stroke};
}

/// The seed paper's SKMC-1200W/10 (Section 4: X900 Y400 Z800 mm, A ±45°; zero positions assumed: X, Z from 0, Y
/// centred). w → C → F → X → Z → A → Y → g, every offset zero (Eq. 11).
ChainSpec cfxzay_spec() {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  return {"CFXZAY",
          {rotary("C", z, std::nullopt)},
          {linear("X", x, {0.0, 900.0}), linear("Z", z, {0.0, 800.0}), rotary("A", x, Interval{-45.0, 45.0}),
           linear("Y", y, {-200.0, 200.0})}};
}

/// The swivel on the workpiece side: the gear on a C table carried by an A tilting table (trunnion), the wheel head on
/// X, Z, Y slides with its spindle along y — a five-axis machine "with workpiece table" (Beckhoff TF5240 universal
/// kinematics, example 3: axes C, A, X, Y, Z from the workpiece to the tool; LinuxCNC xyzac-trt-kins: a horizontal
/// rotary C on a tilting A table, the table face offset from the A pivot). The C table face sits 150 mm above the A
/// pivot (assumed). A tilts the gear by the cross angle; a stroke along the tilted gear axis moves Y and Z together.
ChainSpec cafxzy_spec() {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  return {"CAFXZY",
          {rotary("C", z, std::nullopt, Eigen::Vector3d(0.0, 0.0, 150.0)), rotary("A", x, Interval{-45.0, 45.0})},
          {linear("X", x, {0.0, 900.0}), linear("Z", z, {-300.0, 700.0}), linear("Y", y, {-500.0, 500.0})}};
}

/// The radial axis on the workpiece side: the gear on a C table carried by an X slide that moves it radially towards
/// the wheel, the wheel head on a Z column slide, an A swivel and a Y shift slide, w → C → X → F → Z → A → Y → g. ISG's
/// volumetric compensation describes a machine by this axis sequence (`chain`, from the workpiece to the tool, with
/// `workpiece_axes` 2: C and X move the workpiece); no grinder data sheet of this exact layout was found, so the
/// geometry is illustrative (docs/machine-model.md §9, "Presets"). X moves the table along −x (ISO 841: a positive X′
/// of a table moves the workpiece away from the tool's +X), so X is the centre distance; the C table's face sits
/// 250 mm above the X slide and the A axis line 120 mm above the wheel centre (assumed).
/// Closed form: X = x, Y = y − 120·tan α, Z = z + 250 + 120 / cos α, A = α, C = γ.
ChainSpec cxfzay_spec() {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  return {"CXFZAY",
          {rotary("C", z, std::nullopt, Eigen::Vector3d(0.0, 0.0, 250.0)), linear("X", -x, {0.0, 900.0})},
          {linear("Z", z, {0.0, 1200.0}), rotary("A", x, Interval{-45.0, 45.0}),
           linear("Y", y, {-200.0, 200.0}, Eigen::Vector3d(0.0, 0.0, -120.0))}};
}

/// Eq. 11 inverted on a pose of its form R = Rz(−γ)·Rx(α): (x, y, z, α, γ).
AxisPose setting_of(const Pose& M) {
  const Eigen::Matrix3d& R = M.linear();
  const double g = std::atan2(-R(1, 0), R(0, 0));
  const double a = std::atan2(R(2, 1), R(2, 2));
  const double cg = std::cos(g), sg = std::sin(g);
  const Eigen::Vector3d& p = M.translation();
  const double y = (p.x() * sg + p.y() * cg) / std::cos(a);
  return {p.x() * cg - p.y() * sg, y, p.z() - y * std::sin(a), a, g < 0.0 ? g + 2.0 * std::numbers::pi : g};
}

} // namespace

const AxisSpec& KinematicChain::at(int i) const {
  return i < static_cast<int>(spec_.workpiece.size()) ? spec_.workpiece[static_cast<std::size_t>(i)]
                                                       : spec_.tool[static_cast<std::size_t>(i) - spec_.workpiece.size()];
}

Axis KinematicChain::slot_at(int position) const {
  for (int s = 0; s < kAxisCount; ++s)
    if (chain_position_[static_cast<std::size_t>(s)] == position) return static_cast<Axis>(s);
  return Axis::X;
}

std::string_view KinematicChain::keep(std::string s) {
  strings_.push_back(std::move(s));
  return strings_.back();
}

int KinematicChain::validate() const {
  const int n = static_cast<int>(spec_.workpiece.size() + spec_.tool.size());
  if (n != kAxisCount)
    throw ChainError(-1, "", fmt::format("a profile grinder's chain has five moving axes (three linear, two rotary); "
                                         "this one has {}", n));
  for (int i = 0; i < n; ++i) {
    check_axis(at(i), i);
    for (int j = 0; j < i; ++j)
      if (at(j).name == at(i).name)
        throw ChainError(i, "name", fmt::format("axis {} is named twice (axes {} and {})", at(i).name, j + 1, i + 1));
  }
  // The spindle: the first body from the workpiece, about ±z, turning without limit.
  if (spec_.workpiece.empty() || at(0).kind != AxisKind::Rotary || coordinate_direction(at(0).direction)->first != 2)
    throw ChainError(0, spec_.workpiece.empty() ? "" : "kind",
                     "the first body from the workpiece must be the workpiece spindle: a rotary axis about ±z (the gear "
                     "axis), which turns the gear for the screw motion and the indexing");
  if (at(0).stroke)
    throw ChainError(0, "stroke", fmt::format("the workpiece spindle {} turns without limit: give it no stroke", at(0).name));
  int linear_count = 0, swivel = -1;
  for (int i = 1; i < n; ++i) {
    if (at(i).kind == AxisKind::Linear) {
      ++linear_count;
      continue;
    }
    if (swivel >= 0)
      throw ChainError(i, "kind", "a profile grinder's chain has two rotary axes: the workpiece spindle and the swivel");
    swivel = i;
  }
  if (swivel < 0 || linear_count != 3)
    throw ChainError(-1, "", fmt::format("a profile grinder's chain has three linear and two rotary axes; this one has "
                                         "{} linear and {} rotary", linear_count, n - linear_count));
  if (coordinate_direction(at(swivel).direction)->first != 0)
    throw ChainError(swivel, "direction",
                     fmt::format("the swivel {} must turn about ±x: the cross angle turns the wheel spindle (y) "
                                 "against the gear axis (z) about their common perpendicular", at(swivel).name));
  if (!at(swivel).stroke)
    throw ChainError(swivel, "stroke", fmt::format("the swivel {} needs a stroke", at(swivel).name));
  for (int i = 0; i < n; ++i)
    if (at(i).kind == AxisKind::Linear) {
      if (!at(i).stroke) throw ChainError(i, "stroke", fmt::format("the linear axis {} needs a stroke", at(i).name));
      for (int j = 0; j < i; ++j)
        if (at(j).kind == AxisKind::Linear &&
            coordinate_direction(at(j).direction)->first == coordinate_direction(at(i).direction)->first)
          throw ChainError(i, "direction",
                           fmt::format("axes {} and {} both move along {}: the wheel centre needs three independent "
                                       "directions", at(j).name, at(i).name,
                                       kCoordinate[static_cast<std::size_t>(coordinate_direction(at(i).direction)->first)]));
    }
  return swivel;
}

void KinematicChain::order_axes(int swivel) {
  const int n = kAxisCount;
  // Pose order: the linear axes by ISO 841 letter, the swivel, the spindle.
  std::vector<int> linear_positions;
  for (int i = 0; i < n; ++i)
    if (at(i).kind == AxisKind::Linear) linear_positions.push_back(i);
  std::sort(linear_positions.begin(), linear_positions.end(),
            [&](int a, int b) { return kLinearLetters.find(at(a).name[0]) < kLinearLetters.find(at(b).name[0]); });
  for (int s = 0; s < 3; ++s) chain_position_[static_cast<std::size_t>(s)] = linear_positions[static_cast<std::size_t>(s)];
  chain_position_[3] = swivel;
  chain_position_[4] = 0;
  for (int s = 0; s < kAxisCount; ++s) axes_[static_cast<std::size_t>(s)] = &at(chain_position_[static_cast<std::size_t>(s)]);
  workpiece_count_ = static_cast<int>(spec_.workpiece.size());
  layout_.clear();
  for (auto it = spec_.workpiece.begin(); it != spec_.workpiece.end(); ++it) layout_ += it->name;
  layout_ += "F";
  for (const auto& a : spec_.tool) layout_ += a.name;
}

void KinematicChain::name_components() {
  const int n = kAxisCount;
  // Components: motion blocks by slot, squareness, location (spindle, then swivel).
  bool rotary_after = false; // a rotary axis between this axis and the wheel
  std::array<bool, kAxisCount> rotary_after_slot{};
  for (int i = n - 1; i >= 0; --i) {
    rotary_after_slot[static_cast<std::size_t>(slot_at(i))] = rotary_after;
    if (at(i).kind == AxisKind::Rotary && i >= workpiece_count_) rotary_after = true;
  }
  for (int s = 0; s < kAxisCount; ++s) {
    const AxisSpec& a = axis(static_cast<Axis>(s));
    const int pos = chain_position_[static_cast<std::size_t>(s)];
    const int dir = coordinate_direction(a.direction)->first;
    const bool along_wheel_spindle = pos >= workpiece_count_ && dir == 1 && !rotary_after_slot[static_cast<std::size_t>(s)];
    for (int k = 0; k < 6; ++k) {
      const int idx = 6 * s + k;
      const char c = kCoordinate[static_cast<std::size_t>(k % 3)];
      const std::string stem = std::string(k < 3 ? "delta_" : "epsilon_") + c + lower(a.name[0]);
      info_[static_cast<std::size_t>(idx)] = {
          component_at(idx), keep(stem), keep(std::string(k < 3 ? "δ_" : "ε_") + c + lower(a.name[0])),
          static_cast<Axis>(s), k < 3 ? Quantity::Length : Quantity::Angle, true,
          keep(motion_meaning(a, dir, k, pos == 0, along_wheel_spindle))};
    }
  }
  int idx = kMotionComponentCount;
  for (int s = 0; s < 3; ++s) {
    const int pos_k = chain_position_[static_cast<std::size_t>(s)];
    const AxisSpec& k = axis(static_cast<Axis>(s));
    for (int pos_j = 0; pos_j < pos_k; ++pos_j) {
      const AxisSpec& j = at(pos_j);
      if (j.kind != AxisKind::Linear) continue;
      const auto [jdir, jsign] = *coordinate_direction(j.direction);
      const std::string name = fmt::format("S_{}{}", lower(j.name[0]), lower(k.name[0]));
      info_[static_cast<std::size_t>(idx)] = {
          component_at(idx), keep(name), keep(name), static_cast<Axis>(s), Quantity::Angle, false,
          keep(fmt::format("squareness of {} to {} ({} travel leans towards {}{})", k.name, j.name, k.name,
                           jsign > 0.0 ? "−" : "+", kCoordinate[static_cast<std::size_t>(jdir)]))};
      ++idx;
    }
  }
  for (const Axis s : {Axis::C, Axis::A}) {
    const AxisSpec& a = axis(s);
    const int dir = coordinate_direction(a.direction)->first;
    std::array<int, 2> perp{};
    for (int c = 0, m = 0; c < 3; ++c)
      if (c != dir) perp[static_cast<std::size_t>(m++)] = c;
    const auto add = [&](char letter, std::string meaning, Quantity q) {
      const std::string name = fmt::format("E_{}O{}", letter, a.name);
      info_[static_cast<std::size_t>(idx)] = {component_at(idx), keep(name), keep(name), s, q, false, keep(std::move(meaning))};
      ++idx;
    };
    for (int p : perp)
      add(kCoordinateUpper[static_cast<std::size_t>(p)],
          fmt::format("{} offset of the {} axis line", kCoordinate[static_cast<std::size_t>(p)], a.name), Quantity::Length);
    for (int p : perp)
      add(kRotationUpper[static_cast<std::size_t>(p)],
          fmt::format("tilt of the {} axis line about {}", a.name, kCoordinate[static_cast<std::size_t>(p)]), Quantity::Angle);
    add(kRotationUpper[static_cast<std::size_t>(dir)], fmt::format("zero-position error of {}", a.name), Quantity::Angle);
  }
}

void KinematicChain::compile_joints() {
  const int n = kAxisCount;
  // Joints, in chain order.
  for (int i = 0; i < n; ++i) {
    const AxisSpec& a = at(i);
    Joint& jt = joints_[static_cast<std::size_t>(i)];
    jt.slot = slot_at(i);
    jt.kind = a.kind;
    std::tie(jt.dir, jt.sign) = *coordinate_direction(a.direction);
    jt.workpiece_side = i < workpiece_count_;
    jt.carries_workpiece = i == 0;
    jt.offset = a.offset_mm;
    jt.has_offset = !a.offset_mm.isZero(0.0);
    jt.motion = 6 * static_cast<int>(jt.slot);
    if (a.kind == AxisKind::Rotary) {
      for (int c = 0, m = 0; c < 3; ++c)
        if (c != jt.dir) jt.perpendicular[static_cast<std::size_t>(m++)] = c;
      jt.location = index(jt.slot == Axis::C ? ComponentId::E_XOC : ComponentId::E_YOA);
    }
  }
  for (int c = kMotionComponentCount; c < index(ComponentId::E_XOC); ++c) {
    const ComponentInfo& ci = info_[static_cast<std::size_t>(c)];
    const std::string_view name = ci.name; // S_jk
    Joint& jt = joints_[static_cast<std::size_t>(chain_position_[static_cast<std::size_t>(ci.axis)])];
    for (int j = 0; j < n; ++j)
      if (at(j).kind == AxisKind::Linear && lower(at(j).name[0]) == name[2]) {
        const auto [jdir, jsign] = *coordinate_direction(at(j).direction);
        jt.squareness[static_cast<std::size_t>(jt.squareness_count)] = c;
        jt.lean[static_cast<std::size_t>(jt.squareness_count)] = jsign * Eigen::Vector3d::Unit(jdir);
        ++jt.squareness_count;
      }
  }
}

bool KinematicChain::is_setting_layout() const {
  // The CFXZAY itself (names aside): its axes are the setting's coordinates.
  const ChainSpec seed = cfxzay_spec();
  const auto same_geometry = [](const std::vector<AxisSpec>& a, const std::vector<AxisSpec>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].kind != b[i].kind || a[i].direction.normalized() != b[i].direction || a[i].offset_mm != b[i].offset_mm)
        return false;
    return true;
  };
  // The slots must be the setting's too: slot s of the linear axes moving along +x, +y, +z (names decide the order).
  bool slots_are_setting = true;
  for (int s = 0; s < 3; ++s)
    slots_are_setting = slots_are_setting && coordinate_direction(axis(static_cast<Axis>(s)).direction) ==
                                                 std::optional<std::pair<int, double>>(std::pair{s, 1.0});
  return slots_are_setting && same_geometry(spec_.workpiece, seed.workpiece) && same_geometry(spec_.tool, seed.tool);
}

KinematicChain::KinematicChain(ChainSpec spec) : spec_(std::move(spec)) {
  order_axes(validate());
  name_components();
  compile_joints();
  setting_chain_ = is_setting_layout();
}

bool KinematicChain::on_workpiece_side(Axis slot) const {
  return chain_position_[static_cast<std::size_t>(slot)] < workpiece_count_;
}

std::optional<Axis> KinematicChain::axis_named(std::string_view name) const {
  for (int s = 0; s < kAxisCount; ++s) {
    const std::string& n = axis(static_cast<Axis>(s)).name;
    if (name == n || (name.size() == 1 && name[0] == lower(n[0]))) return static_cast<Axis>(s);
  }
  return std::nullopt;
}

std::optional<ComponentId> KinematicChain::component_from_name(std::string_view name) const {
  for (const auto& c : info_)
    if (c.name == name) return c.id;
  return std::nullopt;
}

Pose KinematicChain::ideal_wMg(const AxisValues& theta) const {
  if (setting_chain_) return machine::ideal_wMg(AxisPose::from_vector(theta.v));
  Pose M = Pose::Identity();
  for (const Joint& j : joints_) {
    const double t = j.sign * theta[j.slot];
    Pose J = Pose::Identity();
    if (j.kind == AxisKind::Linear) J.translation()(j.dir) = t;
    else J.linear() = j.dir == 0 ? rot_x(t) : j.dir == 1 ? rot_y(t) : rot_z(t);
    if (j.has_offset) J = translation(j.offset) * J;
    M = M * (j.workpiece_side ? J.inverse(Eigen::Isometry) : J);
  }
  return M;
}

InverseKinematics KinematicChain::solve(const AxisPose& q) const {
  InverseKinematics ik;
  // Orientation: wRg = Rz(−s_C·θ_C)·Rx(±s_A·θ_A) must be Eq. 11's Rz(−γ)·Rx(α).
  const Joint& spindle = joints_[0];
  const Joint& swivel = joints_[static_cast<std::size_t>(chain_position_[3])];
  ik.theta[Axis::C] = spindle.sign * q.c;
  ik.theta[Axis::A] = (swivel.workpiece_side ? -1.0 : 1.0) * swivel.sign * q.a;
  // Position: with the rotations fixed the wheel centre is affine in the linear axes, p = b + A·θ_lin.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity(); // rotation of the frame before the joint, in w
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (const Joint& j : joints_) {
    if (j.kind == AxisKind::Linear) {
      const Eigen::Vector3d d = j.sign * Eigen::Vector3d::Unit(j.dir);
      A.col(static_cast<int>(j.slot)) = j.workpiece_side ? Eigen::Vector3d(-(R * d)) : Eigen::Vector3d(R * d);
      b += j.workpiece_side ? Eigen::Vector3d(-(R * j.offset)) : Eigen::Vector3d(R * j.offset);
      continue;
    }
    const double t = j.sign * ik.theta[j.slot];
    const Eigen::Matrix3d Rj = j.dir == 0 ? rot_x(t) : j.dir == 1 ? rot_y(t) : rot_z(t);
    if (j.workpiece_side) { // M⁻¹ = R⁻¹·T(−o)
      R = R * Rj.transpose();
      b -= R * j.offset;
    } else { // M = T(o)·R
      b += R * j.offset;
      R = R * Rj;
    }
  }
  ik.linear_det = A.determinant();
  const Eigen::Vector3d lin = A.inverse() * (machine::ideal_wMg(q).translation() - b);
  for (int s = 0; s < 3; ++s) ik.theta.v(s) = lin(s);
  if (!(std::abs(ik.linear_det) >= kSingularDet)) ik.theta.v.head<3>().setConstant(std::nan(""));
  return ik;
}

AxisValues KinematicChain::axes(const AxisPose& q) const {
  if (setting_chain_) return AxisValues{q.vector()};
  return solve(q).theta;
}

AxisPose KinematicChain::setting(const AxisValues& theta) const {
  if (setting_chain_) return AxisPose::from_vector(theta.v);
  return setting_of(ideal_wMg(theta));
}

std::optional<KinematicChain::StrokeViolation> KinematicChain::outside_stroke(const AxisValues& theta) const {
  for (int s = 0; s < kAxisCount; ++s) {
    const AxisSpec& a = axis(static_cast<Axis>(s));
    if (!a.stroke) continue;
    const double v = theta.v(s);
    if (v >= a.stroke->min && v <= a.stroke->max) continue;
    const bool rot = a.kind == AxisKind::Rotary;
    return StrokeViolation{static_cast<Axis>(s),
                           fmt::format("{} = {:.3f} {} is outside its stroke {}", a.name, rot ? v * units::kDegPerRad : v,
                                       rot ? "deg" : "mm", interval_text(*a.stroke, rot))};
  }
  return std::nullopt;
}

const KinematicChain& KinematicChain::with_strokes(const std::array<std::optional<Interval>, kAxisCount>& strokes) const {
  ChainSpec spec = spec_;
  for (int s = 0; s < kAxisCount; ++s) {
    if (!strokes[static_cast<std::size_t>(s)]) continue;
    const int pos = chain_position_[static_cast<std::size_t>(s)];
    AxisSpec& a = pos < workpiece_count_ ? spec.workpiece[static_cast<std::size_t>(pos)]
                                         : spec.tool[static_cast<std::size_t>(pos - workpiece_count_)];
    a.stroke = strokes[static_cast<std::size_t>(s)];
  }
  return make_chain(std::move(spec));
}

bool same_spec(const ChainSpec& a, const ChainSpec& b) {
  const auto same_stroke = [](const std::optional<Interval>& s, const std::optional<Interval>& t) {
    return s.has_value() == t.has_value() && (!s || (s->min == t->min && s->max == t->max));
  };
  const auto same_axes = [&](const std::vector<AxisSpec>& u, const std::vector<AxisSpec>& v) {
    if (u.size() != v.size()) return false;
    for (std::size_t i = 0; i < u.size(); ++i)
      if (u[i].name != v[i].name || u[i].kind != v[i].kind || u[i].direction != v[i].direction ||
          u[i].offset_mm != v[i].offset_mm || !same_stroke(u[i].stroke, v[i].stroke))
        return false;
    return true;
  };
  return a.name == b.name && same_axes(a.workpiece, b.workpiece) && same_axes(a.tool, b.tool);
}

const KinematicChain& make_chain(ChainSpec spec) {
  const std::lock_guard lock(chain_store_mutex());
  for (const auto& c : chain_store())
    if (same_spec(c->spec(), spec)) return *c;
  chain_store().push_back(std::unique_ptr<KinematicChain>(new KinematicChain(std::move(spec))));
  return *chain_store().back();
}

const KinematicChain& cfxzay() {
  static const KinematicChain& chain = make_chain(cfxzay_spec());
  return chain;
}

const KinematicChain* chain_preset(std::string_view name) {
  if (name == "CFXZAY") return &cfxzay();
  if (name == "CAFXZY") {
    static const KinematicChain& chain = make_chain(cafxzy_spec());
    return &chain;
  }
  if (name == "CXFZAY") {
    static const KinematicChain& chain = make_chain(cxfzay_spec());
    return &chain;
  }
  return nullptr;
}

std::vector<std::string_view> chain_preset_names() { return {"CFXZAY", "CAFXZY", "CXFZAY"}; }

} // namespace geartopo::machine
