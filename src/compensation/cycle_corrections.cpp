#include "geartopo/compensation/cycle_corrections.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/machine/chain_kinematics.hpp"

#include <Eigen/QR>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace geartopo::compensation {
namespace {

/// εC + k·δZ: the C correction that acts on the flank like (δZ, εC) (see the header).
double c_equivalent(const machine::Vector5d& c, double k) { return c(4) + k * c(2); }

/// Below this |σ_Z| (mm of the chain's Z per mm of screw along the gear axis) the chain's Z barely follows the gear
/// axis and cannot be folded away: refused.
constexpr double kMinScrewZ = 0.1;

/// The screw along the gear axis in the chain's axes at θ: σ with J_twistw_θ(θ)·σ = (0, 0, 1; 0, 0, k), the wheel
/// moved by 1 mm along the gear axis (w's z) and turned about it by k (the setting's Z by 1, C by −k). The chain's
/// five axes make any small wheel motion away from singularities, so the 6×5 system is consistent (QR solve).
machine::Vector5d screw_in_axes(const ChainAxes& axes, const machine::AxisPose& theta, double k) {
  const machine::Matrix65 J = machine::J_twistw_theta(*axes.chain, machine::AxisValues{theta.vector()});
  machine::Vector6d screw;
  screw << 0.0, 0.0, 1.0, 0.0, 0.0, k;
  return J.colPivHouseholderQr().solve(screw);
}

/// The row's correction with its Z part moved along the screw: on the setting's axes (the CFXZAY) (δX, δY, 0, εA, C_eq)
/// as before; on a chain Δθ − (δZ/σ_Z)·σ, whose Z is 0 and which grinds the same flank to first order (on the CAFXZY
/// σ = (0, sin α, cos α, 0, −k): δY − δZ·tan α, εC + k·δZ/cos α).
machine::Vector5d folded(const ChainAxes& axes, const CorrectionRow& r, double k) {
  machine::Vector5d c = r.correction;
  if (axes.is_setting()) {
    c(4) = c_equivalent(r.correction, k);
  } else {
    const machine::Vector5d sigma = screw_in_axes(axes, r.machine_axes, k);
    if (!(std::abs(sigma(2)) >= kMinScrewZ))
      throw std::invalid_argument(fmt::format(
          "cycle corrections: the {} chain's {} moves {:.3g} mm per mm along the gear axis at space {}, Z = {:.3f} mm "
          "(needs ≥ {}): its Z correction cannot be folded into the cycle's axes", axes.chain->name(),
          axes.axis_name(2), sigma(2), r.space, r.z_stroke_mm, kMinScrewZ));
    c -= (r.correction(2) / sigma(2)) * sigma;
  }
  c(2) = 0.0;
  return c;
}

/// Linear interpolation of ys(xs) at x, held beyond the ends; xs increasing.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  if (x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const size_t hi = static_cast<size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
  const double t = (x - xs[hi - 1]) / (xs[hi] - xs[hi - 1]);
  return (1.0 - t) * ys[hi - 1] + t * ys[hi];
}

} // namespace

CycleCorrections make_cycle_corrections(const CorrectionTable& table, double k, double z_step_mm) {
  if (table.rows().empty()) throw std::invalid_argument("cycle corrections: the correction table is empty");
  if (!(z_step_mm > 0.0) || !std::isfinite(z_step_mm))
    throw std::invalid_argument(fmt::format("cycle corrections: Z step {} mm is not positive", z_step_mm));
  CycleCorrections out;
  out.z_step_mm = z_step_mm;
  out.twist_rad_per_mm = k;
  if (!table.axes().is_setting()) out.chain = table.axes().chain->name();

  // Every row's correction folded (δZ = 0), by row: what the cycle's X, C, Y and A are made of.
  struct Folded {
    const CorrectionRow* row;
    machine::Vector5d c;
  };
  std::vector<Folded> all;
  all.reserve(table.rows().size());
  for (const auto& r : table.rows()) all.push_back({&r, folded(table.axes(), r, k)});

  double sum_y = 0.0, sum_a = 0.0;
  for (const auto& f : all) sum_y += f.c(1), sum_a += f.c(3);
  const double n = static_cast<double>(all.size());
  out.setup_dY_mm = sum_y / n;
  out.setup_dA_rad = sum_a / n;
  for (const auto& f : all) {
    out.y_not_carried_mm = std::max(out.y_not_carried_mm, std::abs(f.c(1) - out.setup_dY_mm));
    out.a_not_carried_rad = std::max(out.a_not_carried_rad, std::abs(f.c(3) - out.setup_dA_rad));
  }

  // Rows of each space in increasing machine Z (the table sorts by gear stroke position, which is machine Z − datum).
  std::map<int, std::vector<const Folded*>> by_space;
  for (const auto& f : all) by_space[f.row->space].push_back(&f);
  for (auto& [space, rows] : by_space) {
    std::sort(rows.begin(), rows.end(),
              [](auto* a, auto* b) { return a->row->machine_axes.z < b->row->machine_axes.z; });
    std::vector<double> z, x, c;
    for (const auto* f : rows) {
      z.push_back(f->row->machine_axes.z);
      x.push_back(f->c(0));
      c.push_back(f->c(4));
    }
    CycleSpace s;
    s.space = space;
    const double z0 = z.front(), z1 = z.back();
    const int steps = std::max(1, static_cast<int>(std::ceil((z1 - z0) / z_step_mm - 1e-9)));
    for (int i = 0; i <= steps; ++i) {
      const double zi = z0 + (z1 - z0) * i / steps;
      s.z_mm.push_back(zi);
      s.dX_mm.push_back(interpolate(z, x, zi));
      s.dC_rad.push_back(interpolate(z, c, zi));
    }
    // Index correction: the mean of C_eq over the stroke (trapezoid rule on the equidistant grid); what varies along
    // the stroke stays in the lead table.
    double mean = 0.0;
    for (size_t i = 0; i < s.dC_rad.size(); ++i)
      mean += (i == 0 || i + 1 == s.dC_rad.size() ? 0.5 : 1.0) * s.dC_rad[i];
    s.index_dC_rad = mean / steps;
    for (double& v : s.dC_rad) v -= s.index_dC_rad;
    out.spaces.push_back(std::move(s));
  }
  return out;
}

machine::Vector5d CycleCorrections::at(int space, double machine_z_mm) const {
  const auto it = std::find_if(spaces.begin(), spaces.end(), [space](const CycleSpace& s) { return s.space == space; });
  if (it == spaces.end()) return machine::Vector5d::Zero();
  machine::Vector5d c;
  c << interpolate(it->z_mm, it->dX_mm, machine_z_mm), setup_dY_mm, 0.0, setup_dA_rad,
      it->index_dC_rad + interpolate(it->z_mm, it->dC_rad, machine_z_mm);
  return c;
}

void CycleCorrections::write_csv(std::ostream& out) const {
  out << "# geartopo cycle corrections: per tooth space an index correction of C and lead corrections X(Z), C(Z) on an\n"
         "# equidistant grid of machine Z, to be added to the commanded axes (C: index + lead). A Z correction is folded\n"
         "# into C through the gear's twist (C_eq = eps_C + k*delta_Z). Y and A: one set-up correction for the gear.\n"
         "# Units: Z_mm mm (machine Z); lead_dX_um um; index_dC_urad, lead_dC_urad urad.\n";
  if (!chain.empty())
    out << "# On the " << chain << " chain the fold follows the screw along the gear axis in the chain's own axes:\n"
        << "# dtheta - (dZ/sigma_Z)*sigma, sigma the axes' motion per mm of the screw (setting Z by 1, C by -k).\n";
  out << fmt::format("# setup_dY_um: {:.4f}\n# setup_dA_urad: {:.4f}\n", units::um_from_mm(setup_dY_mm),
                     units::urad_from_rad(setup_dA_rad));
  out << fmt::format("# not_carried_Y_um: {:.4f}\n# not_carried_A_urad: {:.4f}\n", units::um_from_mm(y_not_carried_mm),
                     units::urad_from_rad(a_not_carried_rad));
  out << fmt::format("# z_step_mm: {}\n# twist_rad_per_mm: {:.9g}\n", z_step_mm, twist_rad_per_mm);
  out << "space,index_dC_urad,Z_mm,lead_dX_um,lead_dC_urad\n";
  for (const auto& s : spaces)
    for (size_t i = 0; i < s.z_mm.size(); ++i)
      out << fmt::format("{},{:.4f},{:.4f},{:.4f},{:.4f}\n", s.space, units::urad_from_rad(s.index_dC_rad), s.z_mm[i],
                         units::um_from_mm(s.dX_mm[i]), units::urad_from_rad(s.dC_rad[i]));
}

void CycleCorrections::write_csv(const std::filesystem::path& file) const {
  output::write_atomically(file, [this](std::ostream& out) { write_csv(out); });
}

} // namespace geartopo::compensation
