#include "geartopo/grinding/form_wheel.hpp"

#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/machine/chain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geartopo::grinding {
namespace {

struct ContactSample {
  double xi, z_c, v, r;
};

/// The designed tooth space the dresser is programmed from (gears/flank_modifications.hpp): the flank point moved
/// along its normal by the design's profile part m(ξ), and that surface's normal. S = P + m n has the tangents
/// S_ξ = P_ξ + m′ n + m n_ξ and S_z = P_z + m n_z; to first order in m its normal is n − m′ ∇ξ, ∇ξ the surface
/// gradient of ξ (inverse metric of P_ξ, P_z). The terms m n_ξ, m n_z tilt it by m/ρ ≈ 10⁻⁵ rad and are left out.
struct DesignedPoint {
  Eigen::Vector3d p, n;
};
DesignedPoint designed(const gears::FlankPoint& fp, const gears::FlankDesign* design, geartopo::Flank flank, double xi) {
  if (design == nullptr || !design->modifications().has_profile(flank)) return {fp.p, fp.n};
  constexpr double h = 1e-3; // mm: the relief's kink is smoothed over ±1 µm of roll length, far below the 0.05 mm samples
  const double m = units::mm_from_um(design->profile_um(flank, xi));
  const double dm = units::mm_from_um(design->profile_um(flank, xi + h) - design->profile_um(flank, xi - h)) / (2 * h);
  const double aa = fp.d_xi.dot(fp.d_xi), ab = fp.d_xi.dot(fp.d_z), bb = fp.d_z.dot(fp.d_z), det = aa * bb - ab * ab;
  const Eigen::Vector3d grad_xi = (bb * fp.d_xi - ab * fp.d_z) / det;
  return {fp.p + m * fp.n, (fp.n - dm * grad_xi).normalized()};
}

// Contact points of one flank with the wheel at pose wMg, for roll lengths xi_lo..xi_hi (continuation in ξ), on the
// designed flank (`design`'s profile part; null: the bare involute).
std::vector<ContactSample> contact_line(const gears::InvoluteHelicoid& flanks, const gears::FlankDesign* design,
                                        int tooth, geartopo::Flank flank, const machine::Pose& wMg, double xi_lo,
                                        double xi_hi, int n) {
  const Eigen::Vector3d O = wMg.translation();
  const Eigen::Vector3d u = wMg.linear().col(1);
  const machine::Pose gMw = wMg.inverse();
  const double k = flanks.geometry().twist_rad_per_mm();
  std::vector<ContactSample> out;
  double z = 0.0;
  for (int i = 0; i < n; ++i) {
    const double xi = xi_lo + (xi_hi - xi_lo) * i / (n - 1);
    // Newton on g(z) = (P − O)·(n × u): the flank normal meets the wheel axis. n turns with the helix,
    // ∂n/∂z = k e_z × n.
    bool converged = false;
    for (int it = 0; it < 50; ++it) {
      const auto fp = flanks.at(tooth, flank, xi, z);
      const DesignedPoint d = designed(fp, design, flank, xi);
      // g on the designed flank; its derivative from the bare one (they differ by ~m′: Newton still converges).
      const double gz = (d.p - O).dot(d.n.cross(u));
      const Eigen::Vector3d nxu = fp.n.cross(u);
      const Eigen::Vector3d dn = k * Eigen::Vector3d::UnitZ().cross(fp.n);
      const double dg = fp.d_z.dot(nxu) + (fp.p - O).dot(dn.cross(u));
      if (dg == 0.0) break;
      const double step = gz / dg;
      z -= step;
      if (std::abs(step) < 1e-13) {
        converged = true;
        break;
      }
    }
    if (!converged || !std::isfinite(z))
      throw std::runtime_error(fmt::format("form wheel: no contact point at roll length {:.3f} mm", xi));
    const Eigen::Vector3d q = gMw * designed(flanks.at(tooth, flank, xi, z), design, flank, xi).p;
    out.push_back({xi, z, q.y(), std::hypot(q.x(), q.z())});
  }
  return out;
}

// Cubic Hermite from (v0, r0, slope s0) to (v1, r1, slope s1), points strictly between the ends.
void hermite(double v0, double r0, double s0, double v1, double r1, double s1, int n, std::vector<double>& v,
             std::vector<double>& r) {
  const double h = v1 - v0;
  for (int i = 1; i < n; ++i) {
    const double t = double(i) / n, t2 = t * t, t3 = t2 * t;
    v.push_back(v0 + h * t);
    r.push_back((2 * t3 - 3 * t2 + 1) * r0 + (t3 - 2 * t2 + t) * h * s0 + (-2 * t3 + 3 * t2) * r1 + (t3 - t2) * h * s1);
  }
}

} // namespace

FormWheel::FormWheel(const gears::GearGeometry& g, const WheelSetting& setting, gears::FlankDesign design)
    : design_(std::move(design)) {
  const gears::InvoluteHelicoid flanks(g);
  const double xi_ff = g.roll_length_at(g.root_form_diameter_mm());
  const double xi_a = g.roll_length_at(g.tip_diameter_mm());
  // The involute part of the wheel reaches a little below d_Ff and beyond d_a, so that the spline's ends and the
  // tip blend stay away from every evaluated point.
  const double xi_lo = std::max(xi_ff - 1.0, 0.5 * xi_ff), xi_hi = xi_a + 1.0;
  const int n = std::max(200, static_cast<int>(std::ceil((xi_hi - xi_lo) / 0.05)) + 1);

  const double space_centre = std::numbers::pi / g.teeth(); // space 1 at z = 0
  const machine::AxisPose q{setting.centre_distance_mm, setting.axial_position_mm, 0.0, setting.tilt_rad,
                            -space_centre};
  wMg_ref_ = machine::ideal_wMg(q);

  // Space 1: right flank of tooth 1 and left flank of tooth 2.
  auto right = contact_line(flanks, &design_, 1, geartopo::Flank::Right, wMg_ref_, xi_lo, xi_hi, n);
  auto left = contact_line(flanks, &design_, 2, geartopo::Flank::Left, wMg_ref_, xi_lo, xi_hi, n);

  std::vector<double> xi_r, zc_r, xi_l, zc_l;
  for (const auto& s : right) xi_r.push_back(s.xi), zc_r.push_back(s.z_c);
  for (const auto& s : left) xi_l.push_back(s.xi), zc_l.push_back(s.z_c);
  contact_right_ = geartopo::CubicSpline(xi_r, zc_r, geartopo::CubicSpline::Ends::NotAKnot);
  contact_left_ = geartopo::CubicSpline(xi_l, zc_l, geartopo::CubicSpline::Ends::NotAKnot);
  const auto [zr_min, zr_max] = std::minmax_element(zc_r.begin(), zc_r.end());
  const auto [zl_min, zl_max] = std::minmax_element(zc_l.begin(), zc_l.end());
  z_c_min_ = std::min(*zr_min, *zl_min);
  z_c_max_ = std::max(*zr_max, *zl_max);

  // Order the two wheel flanks along v: on the lower side v falls as ξ grows (towards the gear tip).
  auto* lower = &right;
  auto* upper = &left;
  if (right[n / 2].v > left[n / 2].v) std::swap(lower, upper);

  for (auto it = lower->rbegin(); it != lower->rend(); ++it) v_.push_back(it->v), r_.push_back(it->r);
  const auto& a0 = (*lower)[0];
  const auto& a1 = (*lower)[1];
  const auto& b0 = (*upper)[0];
  const auto& b1 = (*upper)[1];
  const double s_lo = (a0.r - a1.r) / (a0.v - a1.v), s_hi = (b1.r - b0.r) / (b1.v - b0.v);
  const double v_mid = 0.5 * (a0.v + b0.v), r_tip = 0.5 * setting.outer_diameter_mm;
  hermite(a0.v, a0.r, s_lo, v_mid, r_tip, 0.0, 30, v_, r_);
  v_.push_back(v_mid), r_.push_back(r_tip);
  hermite(v_mid, r_tip, 0.0, b0.v, b0.r, s_hi, 30, v_, r_);
  for (const auto& s : *upper) v_.push_back(s.v), r_.push_back(s.r);

  for (size_t i = 1; i < v_.size(); ++i)
    if (!(v_[i] > v_[i - 1]))
      throw std::runtime_error(fmt::format(
          "form wheel: the wheel profile folds over near v = {:.3f} mm (wheel too small or setting wrong)", v_[i]));
  if (r_tip - std::max(a0.r, b0.r) <= 0.0)
    throw std::runtime_error("form wheel: the wheel tip does not reach below the root form circle");
  profile_ = geartopo::CubicSpline(v_, r_, geartopo::CubicSpline::Ends::NotAKnot);
  v_min_ = v_.front();
  v_max_ = v_.back();
}

double FormWheel::contact_offset_mm(geartopo::Flank flank, double xi) const {
  return flank == geartopo::Flank::Right ? contact_right_.value(xi) : contact_left_.value(xi);
}

} // namespace geartopo::grinding
