#include "geartopo/compensation/cycle_corrections.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/jacobian.hpp"

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

/// Below this |σ_S| (mm of the chain's stroke axis S per mm of screw along the gear axis, at every row) no linear axis
/// follows the gear axis enough to carry the stroke and take its correction's fold.
constexpr double kMinScrewStroke = 0.1;

/// The chain's axis motions at one row: σ, per mm of the screw along the gear axis — J_twistw_θ(θ)·σ = (0, 0, 1; 0, 0,
/// k), the wheel moved by 1 mm along the gear axis (w's z) and turned about it by k (the setting's Z by 1, C by −k) —
/// and ρ, per mm of centre distance — J_twistw_θ(θ)·ρ = the setting's x column of J_twistw_q (a translation, the
/// same about any origin). The chain's five axes make any small wheel motion away from singularities, so the 6×5
/// systems are consistent (QR solve).
struct AxisMotions {
  machine::Vector5d sigma, rho;
};

AxisMotions axis_motions(const ChainAxes& axes, const machine::AxisPose& theta, double k) {
  const machine::AxisValues values{theta.vector()};
  const auto qr = machine::J_twistw_theta(*axes.chain, values).colPivHouseholderQr();
  machine::Vector6d screw;
  screw << 0.0, 0.0, 1.0, 0.0, 0.0, k;
  const machine::Vector6d centre_distance = machine::J_twistw_q(axes.chain->setting(values)).col(0);
  return {qr.solve(screw), qr.solve(centre_distance)};
}

/// The cycle's linear axes on a chain. The fold Δθ − (δS/σ_S)·σ grinds the same flank to first order for any S with
/// σ_S ≠ 0; it moves the other axes by δS·σ_j/σ_S, least for the largest |σ_S| — the axis that carries the stroke
/// along the gear axis. The grid runs along one S for the whole table, so S is the linear slot whose smallest |σ_S|
/// over the rows is largest. The lead axis (per pose, the CFXZAY's X) is the other linear axis with the larger
/// smallest |ρ| (it sets the centre distance); the set-up axis (the CFXZAY's Y, along the wheel spindle) the third.
void choose_linear_roles(const ChainAxes& axes, const std::vector<CorrectionRow>& rows,
                         const std::vector<AxisMotions>& motions, CycleCorrections& out) {
  Eigen::Array3d least_sigma = Eigen::Array3d::Constant(INFINITY), least_rho = Eigen::Array3d::Constant(INFINITY);
  for (const auto& m : motions) {
    least_sigma = least_sigma.min(m.sigma.head<3>().array().abs());
    least_rho = least_rho.min(m.rho.head<3>().array().abs());
  }
  Eigen::Index best = 0;
  least_sigma.maxCoeff(&best);
  const int stroke = static_cast<int>(best);
  if (!(least_sigma(stroke) >= kMinScrewStroke)) {
    // Name the row where the best candidate follows the gear axis least.
    size_t worst = 0;
    for (size_t i = 0; i < motions.size(); ++i)
      if (std::abs(motions[i].sigma(stroke)) < std::abs(motions[worst].sigma(stroke))) worst = i;
    throw NoStrokeAxis(fmt::format(
        "cycle corrections: no linear axis of the {} chain moves by {} mm or more per mm along the gear axis at every "
        "path sample (the best, {}, moves {:.3g} mm per mm at space {}, stroke position {:.3f} mm): the stroke's "
        "correction cannot be folded into the cycle's axes", axes.chain->name(), kMinScrewStroke,
        axes.axis_name(stroke), motions[worst].sigma(stroke), rows[worst].space,
        rows[worst].z_stroke_mm));
  }
  const int a = (stroke + 1) % 3, b = (stroke + 2) % 3;
  const bool a_leads = least_rho(a) > least_rho(b) || (least_rho(a) == least_rho(b) && a < b);
  out.stroke_slot = stroke;
  out.lead_slot = a_leads ? a : b;
  out.setup_slot = a_leads ? b : a;
}

/// The row's correction with the stroke axis' part moved along the screw: on the setting's axes (the CFXZAY)
/// (δX, δY, 0, εA, C_eq) as before; on a chain Δθ − (δS/σ_S)·σ, whose S is 0 and which grinds the same flank to first
/// order (on the CAFXZY σ = (0, sin α, cos α, 0, −k): δY − δZ·tan α, εC + k·δZ/cos α).
machine::Vector5d folded(const CorrectionRow& r, const AxisMotions* m, int stroke, double k) {
  machine::Vector5d c = r.correction;
  if (m == nullptr)
    c(4) = c_equivalent(r.correction, k);
  else
    c -= (r.correction(stroke) / m->sigma(stroke)) * m->sigma;
  c(stroke) = 0.0;
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
  const ChainAxes& axes = table.axes();
  std::vector<AxisMotions> motions; // empty on the setting's axes: the CFXZAY's Z, X, Y and fold, as always
  if (!axes.is_setting()) {
    out.chain = axes.chain->name();
    for (int slot = 0; slot < machine::kAxisCount; ++slot) out.axis_names[static_cast<size_t>(slot)] = axes.axis_name(slot);
    motions.reserve(table.rows().size());
    for (const auto& r : table.rows()) motions.push_back(axis_motions(axes, r.machine_axes, k));
    choose_linear_roles(axes, table.rows(), motions, out);
  }
  const int stroke = out.stroke_slot, lead = out.lead_slot, setup = out.setup_slot;

  // Every row's correction folded (the stroke axis' part 0), by row: what the cycle's lead, set-up, swivel and
  // spindle corrections are made of.
  struct Folded {
    const CorrectionRow* row;
    machine::Vector5d c;
  };
  std::vector<Folded> all;
  all.reserve(table.rows().size());
  for (size_t i = 0; i < table.rows().size(); ++i)
    all.push_back({&table.rows()[i], folded(table.rows()[i], motions.empty() ? nullptr : &motions[i], stroke, k)});

  double sum_y = 0.0, sum_a = 0.0;
  for (const auto& f : all) sum_y += f.c(setup), sum_a += f.c(3);
  const double n = static_cast<double>(all.size());
  out.setup_dY_mm = sum_y / n;
  out.setup_dA_rad = sum_a / n;
  for (const auto& f : all) {
    out.y_not_carried_mm = std::max(out.y_not_carried_mm, std::abs(f.c(setup) - out.setup_dY_mm));
    out.a_not_carried_rad = std::max(out.a_not_carried_rad, std::abs(f.c(3) - out.setup_dA_rad));
  }

  // Rows of each space in increasing position of the stroke axis (on the CFXZAY machine Z: the table sorts by gear
  // stroke position, which is machine Z − datum).
  const auto stroke_of = [stroke](const CorrectionRow& r) { return r.machine_axes.vector()(stroke); };
  std::map<int, std::vector<const Folded*>> by_space;
  for (const auto& f : all) by_space[f.row->space].push_back(&f);
  for (auto& [space, rows] : by_space) {
    std::sort(rows.begin(), rows.end(), [&](auto* a, auto* b) { return stroke_of(*a->row) < stroke_of(*b->row); });
    std::vector<double> z, x, c;
    for (const auto* f : rows) {
      z.push_back(stroke_of(*f->row));
      x.push_back(f->c(lead));
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

machine::Vector5d CycleCorrections::at(int space, double stroke_mm) const {
  const auto it = std::find_if(spaces.begin(), spaces.end(), [space](const CycleSpace& s) { return s.space == space; });
  if (it == spaces.end()) return machine::Vector5d::Zero();
  machine::Vector5d c = machine::Vector5d::Zero();
  c(lead_slot) = interpolate(it->z_mm, it->dX_mm, stroke_mm);
  c(setup_slot) = setup_dY_mm;
  c(3) = setup_dA_rad;
  c(4) = it->index_dC_rad + interpolate(it->z_mm, it->dC_rad, stroke_mm);
  return c;
}

machine::Vector5d CycleCorrections::at(const CorrectionRow& row) const {
  return at(row.space, row.machine_axes.vector()(stroke_slot));
}

void CycleCorrections::write_csv(std::ostream& out) const {
  // The chain's letters: on the CFXZAY (and the CAFXZY, CXFZAY) Z, X, Y, A, C.
  const std::string& S = axis_names[static_cast<size_t>(stroke_slot)];
  const std::string& L = axis_names[static_cast<size_t>(lead_slot)];
  const std::string& U = axis_names[static_cast<size_t>(setup_slot)];
  const std::string& A = axis_names[3];
  const std::string& C = axis_names[4];
  out << fmt::format(
      "# geartopo cycle corrections: per tooth space an index correction of {4} and lead corrections {1}({0}), {4}({0}) "
      "on an\n# equidistant grid of machine {0}, to be added to the commanded axes ({4}: index + lead). A {0} correction "
      "is folded\n# into {4} through the gear's twist ({4}_eq = eps_{4} + k*delta_{0}). {2} and {3}: one set-up correction "
      "for the gear.\n# Units: {0}_mm mm (machine {0}); lead_d{1}_um um; index_d{4}_urad, lead_d{4}_urad urad.\n",
      S, L, U, A, C);
  if (!chain.empty())
    out << "# On the " << chain << " chain the fold follows the screw along the gear axis in the chain's own axes:\n"
        << fmt::format("# dtheta - (d{0}/sigma_{0})*sigma, sigma the axes' motion per mm of the screw (setting Z by 1, "
                       "C by -k);\n# {0} is the linear axis that moves most along the gear axis.\n", S);
  out << fmt::format("# setup_d{}_um: {:.4f}\n# setup_d{}_urad: {:.4f}\n", U, units::um_from_mm(setup_dY_mm), A,
                     units::urad_from_rad(setup_dA_rad));
  out << fmt::format("# not_carried_{}_um: {:.4f}\n# not_carried_{}_urad: {:.4f}\n", U,
                     units::um_from_mm(y_not_carried_mm), A, units::urad_from_rad(a_not_carried_rad));
  out << fmt::format("# z_step_mm: {}\n# twist_rad_per_mm: {:.9g}\n", z_step_mm, twist_rad_per_mm);
  out << fmt::format("space,index_d{1}_urad,{0}_mm,lead_d{2}_um,lead_d{1}_urad\n", S, C, L);
  for (const auto& s : spaces)
    for (size_t i = 0; i < s.z_mm.size(); ++i)
      out << fmt::format("{},{:.4f},{:.4f},{:.4f},{:.4f}\n", s.space, units::urad_from_rad(s.index_dC_rad), s.z_mm[i],
                         units::um_from_mm(s.dX_mm[i]), units::urad_from_rad(s.dC_rad[i]));
}

void CycleCorrections::write_csv(const std::filesystem::path& file) const {
  output::write_atomically(file, [this](std::ostream& out) { write_csv(out); });
}

} // namespace geartopo::compensation
