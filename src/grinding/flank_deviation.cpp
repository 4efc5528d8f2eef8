#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/core/minimize.hpp"
#include "geartopo/machine/chain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <limits>
#include <stdexcept>

namespace geartopo::grinding {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();


} // namespace

void require_reached(double deviation, int tooth, geartopo::Flank flank, double diameter_mm, double z_mm) {
  if (std::isfinite(deviation)) return;
  throw std::runtime_error(fmt::format(
      "tooth {} {} flank at d = {:.3f} mm, z = {:.3f} mm: the wheel never reaches this point, so it is not ground there "
      "(the errors move the wheel's profile off it); check the size of the machine errors and effects",
      tooth, gears::to_string(flank), diameter_mm, z_mm));
}

int space_of(int tooth, geartopo::Flank flank, int teeth) {
  if (flank == geartopo::Flank::Right) return tooth;
  return tooth == 1 ? teeth : tooth - 1;
}

double FlankDeviation::entry_depth(const gears::FlankPoint& fp, const machine::Pose& wMg, const PathPoint& pp,
                                   double t_start_mm) const {
  // The normal line in the wheel frame: q(t) = q0 + t m. Solve f(t) = ρ(q) − R(v(q)) = 0 by Newton from t_start;
  // entering the wheel means f goes from + (outside the wheel) to − (inside).
  const machine::Pose gMw = wMg.inverse();
  const Eigen::Vector3d q0 = gMw * fp.p;
  const Eigen::Vector3d m = gMw.linear() * fp.n;
  const bool wheel_changes = process_.changes_wheel_radius();
  double t = t_start_mm;
  for (int it = 0; it < 30; ++it) {
    const Eigen::Vector3d q = q0 + t * m;
    // ρ of a point a wheel radius (~10² mm) from the wheel axis: no overflow to guard against, so no std::hypot.
    const double rho = std::sqrt(q.x() * q.x() + q.z() * q.z());
    const FormWheel::ProfilePoint w = wheel_.profile_at(q.y());
    if (!std::isfinite(w.radius) || rho == 0.0) return kInf;
    const double f = rho - w.radius - (wheel_changes ? process_.wheel_radius_error_mm(q.y(), pp) : 0.0);
    const double df = (q.x() * m.x() + q.z() * m.z()) / rho - w.slope * m.y();
    if (!(df < 0.0)) return kInf; // the line does not run into the wheel here
    const double step = f / df;
    t -= step;
    if (std::abs(step) < 1e-12) return t;
    if (wheel_changes) continue; // the process's radius error has no known bound on its second derivative
    // Stop once the step just taken leaves t within kNewtonTolMm of the root (Newton–Kantorovich). With |f″| ≤ M on
    // [t_k − r, t_k + r], r = 2|s| (s = f/f′ the step from t_k): f(t) = ½ f″(ξ) s² by Taylor at t_k, the root t*
    // lies within r of t_k (Kantorovich: M|s|/|f′| ≤ ½), and |t − t*| = |f(t)|/|f′(η)| ≤ ½ M s² / (|f′(t_k)| − M r).
    // M: ρ″ = (m_x² + m_z² − ρ′²)/ρ ∈ [0, 1/ρ] with ρ ≥ ρ_k − r, and (R∘v)″ = R″ m_y² with |m_y| ≤ 1 (|m| = 1).
    // Quadratic convergence makes this save the last step (|s| ~ 1e-6 mm leaves ~1e-14 mm; the step after it is
    // rounding; measured in docs/performance.md at commit 845718f and before).
    const double r = 2.0 * std::abs(step);
    if (!(rho > r) || q.y() - r < wheel_.v_min() || q.y() + r > wheel_.v_max()) continue;
    const double f2_bound = 1.0 / (rho - r) + wheel_.second_derivative_bound(w, r);
    const double df_low = -df - f2_bound * r; // |f′| ≥ this on [t_k − r, t_k + r]
    if (df_low > 0.0 && 0.5 * f2_bound * step * step <= kNewtonTolMm * df_low) return t;
  }
  return t;
}

FlankDeviation::Target FlankDeviation::target(int tooth, geartopo::Flank flank, double xi, double z) const {
  Target t{space_of(tooth, flank, flanks_.geometry().teeth()), flanks_.at(tooth, flank, xi, z),
           z - wheel_.contact_offset_mm(flank, xi)};
  const auto& design = wheel_.design();
  if (!design.empty()) {
    t.design_profile_mm = units::mm_from_um(design.profile_um(flank, xi));
    t.design_mm = units::mm_from_um(design.at_um(flank, xi, z));
  }
  return t;
}

double FlankDeviation::depth_at(const Target& t, double z_stroke_mm, double t_start_mm) const {
  const PathPoint pp = path_.point(t.space, z_stroke_mm);
  return entry_depth(t.fp, process_.actual_wMg(pp), pp, t_start_mm);
}

LinearContact FlankDeviation::linear_contact(const Target& t) const {
  const PathPoint pp = path_.point(t.space, t.z0);
  const double v = (machine::ideal_wMg(pp.q).inverse() * t.fp.p).y(); // wheel coordinate of the contact point
  return {pp, t.fp.p, t.fp.n, v, wheel_.normal_per_radial(v)};
}

LinearContact FlankDeviation::linear_contact(int tooth, geartopo::Flank flank, double xi, double z) const {
  return linear_contact(target(tooth, flank, xi, z));
}

double linear_deviation_mm(const LinearContact& c, const GrindingProcess& process) {
  const machine::Vector6d e = process.error_twist_w(c.pp);
  const Eigen::Vector3d shift = e.head<3>() + e.tail<3>().cross(c.p);
  // A radial change of the wheel moves its surface along the normal by δR/√(1 + R′²) (form_wheel.hpp).
  return c.n.dot(shift) - process.wheel_radius_error_mm(c.v, c.pp) * c.normal_per_radial;
}

DeviationResult FlankDeviation::at(int tooth, geartopo::Flank flank, double xi, double z, Method method) const {
  return at(target(tooth, flank, xi, z), method);
}

DeviationResult FlankDeviation::at(const Target& t, Method method) const {
  DeviationResult r = from_involute(t, method);
  r.deviation_mm -= method == Method::Linear ? t.design_mm - t.design_profile_mm : t.design_mm;
  return r;
}

DeviationResult FlankDeviation::from_involute(const Target& t, Method method) const {
  const double z0 = t.z0;

  if (method == Method::Linear) return {linear_deviation_mm(linear_contact(t), process_), z0};

  // Near its minimum the depth is t* + ½c(Z − Z*)² + d(Z − Z*)³ + … with c ≈ 1/R_wheel, and Z* lies within a fraction
  // of a millimetre of Z₀. Three depths at Z₀ − h, Z₀, Z₀ + h give the parabola's vertex u; the depth at u is a real
  // depth (never below the true minimum) and exceeds it by ½c(u − Z*)², where |u − Z*| ~ (3d s² − d h²)/c for the
  // cubic coefficient d and s = Z₀ − Z*: ~1e-9 mm for s ≤ 0.2 mm. The quadratic model is trusted only when the
  // depth at u agrees with the parabola's own prediction; otherwise Brent's search decides (tests/grinding:
  // ExactSearch.*).
  //
  // When the target knows the curvature (c_k, the ideal process's: TopologyPlan), the depths at Z₀ ± h alone give
  // the vertex, and the depth there is the third and last pose. With f(Z) = t* + ½c(Z − Z*)² + d(Z − Z*)³,
  // f(Z₀ + h) − f(Z₀ − h) = 2c s h + d(6s²h + 2h³), so u = Z₀ − (f₊ − f₋)/(2 c_k h) gives
  //   u − Z* = s (1 − c/c_k) − d (3s² + h²)/c_k,
  // and the depth at u exceeds t* by ½c(u − Z*)². The curvature's relative error ε = 1 − c/c_k is the process's
  // (µm and µrad change it by ~1e-4) plus the change of the curvature between Z₀ and Z* (6ds/c): with s ≤ 0.2 mm and
  // ε ≤ 1e-3 the first term is ≤ 2e-4 mm and the excess ≤ ½·7e-3·(2e-4)² ≈ 1e-10 mm; the cubic term is the 4-pose
  // search's own. It is not taken on trust: the parabola through all three depths (at Z₀ − h, u, Z₀ + h — its
  // curvature the measured one, not c_k) has its vertex u₂, and the depth at u is kept only when its excess over that
  // parabola's minimum, a(u − u₂)² with a = c/2, is ≤ kKnownCurvatureExcessMm (1e-8 µm), besides the 4-pose
  // search's guards (reach, agreement with the prediction, not above the samples). Otherwise the 4-pose search
  // continues from the two depths (one pose more, then its vertex), and Brent's search behind it.
  constexpr double h = kCurvatureStepMm;
  const double c_known = t.depth_curvature_per_mm;
  if (c_known > 0.0) {
    const double f_m = depth_at(t, z0 - h, 0.0);
    const double f_p = depth_at(t, z0 + h, std::isfinite(f_m) ? f_m : 0.0);
    if (std::isfinite(f_m) && std::isfinite(f_p)) {
      const double u = z0 - (f_p - f_m) / (2.0 * c_known * h);
      // Away from both samples by 1 % of h at least, so the parabola through the three is well conditioned.
      if (std::abs(u - z0) <= kParabolaReachMm && std::abs(std::abs(u - z0) - h) >= 0.01 * h) {
        const double predicted = 0.5 * (f_m + f_p) - 0.5 * c_known * (h * h + (u - z0) * (u - z0));
        const double f_u = depth_at(t, u, predicted);
        if (std::abs(f_u - predicted) <= kParabolaAgreementMm && f_u <= std::min(f_m, f_p)) {
          // Newton's divided differences of (Z₀ − h, f₋), (u, f_u), (Z₀ + h, f₊): p(Z) = f₋ + d₁(Z − Z₀ + h) + a(Z − Z₀ + h)(Z − u).
          const double d1 = (f_u - f_m) / (u - (z0 - h));
          const double a = ((f_p - f_u) / (z0 + h - u) - d1) / (2.0 * h);
          if (a > 0.0) {
            const double u2 = 0.5 * (z0 - h + u) - d1 / (2.0 * a);
            if (a * (u - u2) * (u - u2) <= kKnownCurvatureExcessMm) return {f_u, u};
          }
        }
      }
    }
    return four_pose_search(t, f_m, depth_at(t, z0, std::isfinite(f_m) ? f_m : 0.0), f_p);
  }
  // Newton starts from a depth close by: the depth at Z₀ for Z₀ ± h (~1e-5 mm away), the parabola's prediction at u.
  const double f_0 = depth_at(t, z0, 0.0);
  const double near_f_0 = std::isfinite(f_0) ? f_0 : 0.0;
  const double f_m = depth_at(t, z0 - h, near_f_0), f_p = depth_at(t, z0 + h, near_f_0);
  return four_pose_search(t, f_m, f_0, f_p);
}

DeviationResult FlankDeviation::four_pose_search(const Target& t, double f_m, double f_0, double f_p) const {
  constexpr double h = kCurvatureStepMm;
  const double z0 = t.z0;
  const double curvature = f_p + f_m - 2.0 * f_0; // c h²
  if (std::isfinite(f_m) && std::isfinite(f_0) && std::isfinite(f_p) && curvature > 0.0) {
    const double u = z0 + 0.5 * h * (f_m - f_p) / curvature;
    if (std::abs(u - z0) <= kParabolaReachMm) {
      const double predicted = f_0 - (f_p - f_m) * (f_p - f_m) / (8.0 * curvature);
      const double f_u = depth_at(t, u, predicted);
      if (std::abs(f_u - predicted) <= kParabolaAgreementMm && f_u <= std::min({f_m, f_0, f_p})) return {f_u, u};
    }
  }
  return brent_search(t, kBrentTolMm);
}

double FlankDeviation::depth_curvature_per_mm(const Target& t) const {
  constexpr double h = kCurvatureStepMm;
  const double f_0 = depth_at(t, t.z0, 0.0);
  if (!std::isfinite(f_0)) return 0.0;
  const double f_m = depth_at(t, t.z0 - h, f_0), f_p = depth_at(t, t.z0 + h, f_0);
  const double c = (f_p + f_m - 2.0 * f_0) / (h * h);
  return std::isfinite(c) && c > 0.0 ? c : 0.0;
}

DeviationResult FlankDeviation::exact_by_brent(int tooth, geartopo::Flank flank, double xi, double z, double z_tol_mm) const {
  const Target t = target(tooth, flank, xi, z);
  DeviationResult r = brent_search(t, z_tol_mm);
  r.deviation_mm -= t.design_mm;
  return r;
}

DeviationResult FlankDeviation::brent_search(const Target& t, double z_tol_mm) const {
  auto depth = [&](double zs) { return depth_at(t, zs, 0.0); };
  // The deepest cut moves from Z₀ by (error gradient)/(clearance curvature) — well under 0.2 mm for any realistic
  // error — so ±0.5 mm is searched first, and ±4 mm if the minimum lands on that window's edge. A Z tolerance of
  // 1e-4 mm leaves the depth exact to ½c·1e-8 ≈ 1e-10 mm.
  Minimum best = minimize_brent(depth, t.z0 - 0.5, t.z0 + 0.5, z_tol_mm);
  if (std::abs(best.x - t.z0) > 0.5 - 10 * z_tol_mm) best = minimize_brent(depth, t.z0 - 4.0, t.z0 + 4.0, z_tol_mm);
  return {best.value, best.x};
}

} // namespace geartopo::grinding
