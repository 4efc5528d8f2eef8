#include "geartopo/gears/involute_helicoid.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geartopo::gears {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

Eigen::Vector3d radial(double phi) { return {std::cos(phi), std::sin(phi), 0.0}; }
Eigen::Vector3d tangential(double phi) { return {-std::sin(phi), std::cos(phi), 0.0}; }

double wrap_pi(double a) { return std::remainder(a, kTwoPi); }

} // namespace

double InvoluteHelicoid::tooth_centre_angle(int tooth, double z_mm) const {
  return kTwoPi * (tooth - 1) / g_.teeth() + g_.twist_rad_per_mm() * z_mm;
}

// The transverse section at z is the section at z = 0 turned by (2 tan β / d)·z about the axis. In it, the flank of
// side σ (+1 right, −1 left) is the involute unwound from the base-circle point at φ₀ = θ_tooth + σ ψ_b towards the
// tooth centre: P = r_b e_r(φ) + σ ξ e_θ(φ) with φ = φ₀ − σ ξ / r_b (e_θ(φ) is the generating line's direction).
// Its normal is σ (cos β_b e_θ(φ) − sin β_b e_z): the generating line, tangent to the base cylinder, inclined by β_b.
FlankPoint InvoluteHelicoid::at(int tooth, Flank flank, double xi, double z) const {
  if (!(xi >= 0.0)) throw std::domain_error("InvoluteHelicoid::at: roll length must be >= 0");
  const double rb = 0.5 * g_.base_diameter_mm();
  const double s = side_sign(flank);
  const double k = g_.twist_rad_per_mm();
  const double bb = g_.base_helix_angle();
  const double phi = tooth_centre_angle(tooth, z) + s * g_.base_half_angle() - s * xi / rb;
  const Eigen::Vector3d er = radial(phi), et = tangential(phi), ez = Eigen::Vector3d::UnitZ();

  FlankPoint fp;
  fp.p = rb * er + s * xi * et + z * ez;
  fp.n = s * (std::cos(bb) * et - std::sin(bb) * ez);
  fp.d_xi = (xi / rb) * er;
  fp.d_z = ez + k * (rb * et - s * xi * er); // e_z + k e_z × P_xy
  return fp;
}

FlankPoint InvoluteHelicoid::at_diameter(int tooth, Flank flank, double dy, double z) const {
  return at(tooth, flank, g_.roll_length_at(dy), z);
}

std::optional<FlankLocation> InvoluteHelicoid::locate_on(const Eigen::Vector3d& wP, int tooth, Flank flank) const {
  const double rb = 0.5 * g_.base_diameter_mm();
  const double r = std::hypot(wP.x(), wP.y());
  if (!std::isfinite(r) || !std::isfinite(wP.z()) || r <= rb) return std::nullopt;
  double xi = std::sqrt(r * r - rb * rb);
  double z = wP.z();
  // Gauss–Newton on the foot-point conditions (P − S)·S_ξ = 0, (P − S)·S_z = 0. The residual is small for points
  // near the flank, so convergence is fast (rate ~ distance × curvature).
  for (int it = 0; it < 100; ++it) {
    const FlankPoint fp = at(tooth, flank, std::max(xi, 0.0), z);
    Eigen::Matrix<double, 3, 2> J; // 3×2: [∂S/∂ξ  ∂S/∂z]
    J << fp.d_xi, fp.d_z;
    const Eigen::Vector3d res = wP - fp.p;
    const Eigen::Vector2d step = (J.transpose() * J).ldlt().solve(J.transpose() * res);
    xi += step.x();
    z += step.y();
    if (!std::isfinite(xi) || xi < 0.0) return std::nullopt;
    if (step.norm() < 1e-12) break;
  }
  const FlankPoint fp = at(tooth, flank, xi, z);
  const Eigen::Vector3d res = wP - fp.p;
  // A converged foot point leaves only a normal residual.
  if ((res - res.dot(fp.n) * fp.n).norm() > 1e-6 * (1.0 + res.norm())) return std::nullopt;
  FlankLocation loc;
  loc.tooth = tooth;
  loc.flank = flank;
  loc.roll_length_mm = xi;
  loc.diameter_mm = g_.diameter_at_roll_length(xi);
  loc.z_mm = z;
  loc.normal_distance_mm = res.dot(fp.n);
  loc.foot = fp.p;
  loc.normal = fp.n;
  return loc;
}

std::optional<FlankLocation> InvoluteHelicoid::locate(const Eigen::Vector3d& wP) const {
  const int nz = g_.teeth();
  const double theta = std::atan2(wP.y(), wP.x()) - g_.twist_rad_per_mm() * wP.z(); // angle in the z = 0 section
  const double pitch_angle = kTwoPi / nz;
  const long idx = std::lround(theta / pitch_angle);
  const int tooth = static_cast<int>(((idx % nz) + nz) % nz) + 1;
  const double rel = wrap_pi(theta - pitch_angle * (tooth - 1));
  return locate_on(wP, tooth, rel >= 0.0 ? Flank::Right : Flank::Left);
}

} // namespace geartopo::gears
