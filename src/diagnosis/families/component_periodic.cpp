// geartopo diagnosis — hypothesis family: one of the C axis' motion components changed periodically in the table's
// turn, k times per revolution, δe(γ) = a cos(kγ − φ) (k = 1: a shifted encoder disc or bearing, an indexing error
// once per turn; k = 2: an elliptic bearing or encoder; higher k: a gear or a worm drive's own periods). Linear in
// (a cos φ, a sin φ): columns the component's sensitivity times cos kγ and sin kγ, γ each point's commanded C angle.
//
// Which orders the measured teeth resolve: T teeth sample the turn T times (and a little along the helix within each
// flank), so orders above T/2 alias lower ones — on teeth evenly spaced exactly, k and T − k give the same samples — and
// only orders 1 … ⌊T/2⌋ (at least 1, at most z/2) are tried. Among those, and above them up to z/2, an order whose
// columns are alike (DiagnoseOptions::alike_share, both ways, set-up terms removed) those of a lower tried order of the
// same component is listed as an alias in that order's equivalence class ("the teeth alias these orders"); the lower
// order stands for it — a lower order is the likelier physics. Orders above ⌊T/2⌋ that alias none are not tried, and
// each hypothesis says up to which order the teeth resolve. Beyond z/2 every order aliases a lower one on any gear of
// z teeth.
#include "component_law.hpp"
#include "family_list.hpp"

#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace geartopo::diagnosis::families {
namespace {

using machine::ChangeLaw;

/// cos kγ and sin kγ times a component's sensitivity column (n × 2).
Eigen::MatrixXd periodic_columns(const Eigen::VectorXd& sensitivity, const Eigen::VectorXd& gamma, int order) {
  Eigen::MatrixXd X(sensitivity.size(), 2);
  X.col(0) = sensitivity.cwiseProduct(Eigen::VectorXd((order * gamma.array()).cos()));
  X.col(1) = sensitivity.cwiseProduct(Eigen::VectorXd((order * gamma.array()).sin()));
  return X;
}

/// The share of block a's columns in the span of block b's (0 … 1), from the Gram matrix G of all blocks' judged
/// columns (2 per block): ‖P_b A‖_F / ‖A‖_F with ‖P_b A‖_F² = tr(AᵀB (BᵀB)⁻¹ BᵀA).
double share_in_span(const Eigen::MatrixXd& G, int a, int b) {
  const Eigen::MatrixXd AB = G.block(2 * a, 2 * b, 2, 2), BB = G.block(2 * b, 2 * b, 2, 2);
  const double AA = G.block(2 * a, 2 * a, 2, 2).trace();
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(BB);
  if (!(AA > 0.0) || lu.rank() < 2) return 0.0;
  return std::sqrt(std::max(0.0, (AB * lu.solve(AB.transpose())).trace() / AA));
}

class ComponentPeriodic final : public HypothesisFamily {
public:
  std::string_view name() const override { return "component_periodic"; }
  std::vector<Candidate> enumerate(const ContactStates& states, const DiagnoseOptions& o) const override {
    std::vector<Candidate> out;
    const int listed = std::max(1, states.setup().geometry().teeth() / 2);
    const int tried = std::min(listed, states.teeth_measured() > 0 ? std::max(1, states.teeth_measured() / 2) : listed);
    for (int k : visible_components(states)) {
      const auto& info = machine::info(machine::component_at(k));
      if (info.axis != machine::Axis::C || !info.position_dependent) continue;
      // Every order's judged columns, side by side (n × 2K), and their Gram matrix (2K × 2K).
      Eigen::MatrixXd X(static_cast<Eigen::Index>(states.size()), 2 * listed);
      for (int m = 1; m <= listed; ++m)
        X.middleCols(2 * (m - 1), 2) = periodic_columns(states.component_sensitivity_um().col(k), states.c_rad(), m);
      const Eigen::MatrixXd J = states.judged(X);
      const Eigen::MatrixXd G = J.transpose() * J;
      std::vector<size_t> standing; // indices in `out` of this component's tried orders
      for (int m = 1; m <= listed; ++m) {
        Candidate h = component_hypothesis(o.chain, k, ChangeLaw::PerRevolution, 0.0, m);
        Candidate* alias_of = nullptr;
        for (size_t i : standing) {
          const int r = out[i].changes.front().order;
          if (std::min(share_in_span(G, m - 1, r - 1), share_in_span(G, r - 1, m - 1)) >= o.alike_share) {
            alias_of = &out[i];
            break;
          }
        }
        if (alias_of) {
          alias_of->equivalent.push_back(h.name()); // named in its representative's equivalence class
        } else if (m <= tried) {
          if (states.teeth_measured() > 0)
            h.description = fmt::format("the {} measured teeth resolve orders up to {}", states.teeth_measured(), tried);
          standing.push_back(out.size());
          out.push_back(std::move(h));
        }
      }
    }
    return out;
  }
  Eigen::MatrixXd columns(const Candidate& h, const ContactStates& states) const override {
    const auto& ch = h.changes.front();
    return periodic_columns(states.component_sensitivity_um().col(machine::index(ch.component)), states.c_rad(),
                            ch.order);
  }
  Eigen::VectorXd plausible_size(const Candidate& h, const ContactStates&, const DiagnoseOptions& o) const override {
    return Eigen::VectorXd::Constant(2, plausible_change(h.changes.front(), o));
  }
  Candidate finding(Candidate c, const LinearFit& f, const ContactStates&, const DiagnoseOptions& o) const override {
    auto& ch = c.changes.front();
    const auto q = machine::info(ch.component).quantity;
    // a·cos(kγ − φ) = a cos φ · cos kγ + a sin φ · sin kγ: a = |β|, φ = atan2(β₁, β₀); to first order
    // δa = gᵀδβ and δφ = hᵀδβ / a with g = (cos φ, sin φ), h = (−sin φ, cos φ).
    const double a = f.beta.norm();
    ch.size = a, ch.phase_rad = std::atan2(f.beta(1), f.beta(0));
    const Eigen::Vector2d g(std::cos(ch.phase_rad), std::sin(ch.phase_rad)), h(-g(1), g(0));
    const double sd = std::sqrt(g.dot(f.cov * g));
    const double phase_sd_deg = a > 0.0 ? std::sqrt(h.dot(f.cov * h)) / a * 180.0 / std::numbers::pi : 180.0;
    const double phase_deg = ch.phase_rad * 180.0 / std::numbers::pi;
    c.change_sd.push_back(sd);
    const double scale = machine::file_per_internal(ch.law, q);
    c.parameters.push_back({{machine::size_key(ch.law, q), a * scale, sd * scale, true},
                            {"phase_deg", phase_deg, phase_sd_deg, true}});
    // The enumeration's note on the orders the teeth resolve, said after what was found.
    const std::string resolved = c.description.empty() ? std::string() : " (" + c.description + ")";
    c.description = machine::describe(ch, text::with_uncertainty(a * scale, sd * scale, true),
                                      text::with_uncertainty(phase_deg, phase_sd_deg), c.chain) +
                    resolved;
    const double limit = plausible_change(ch, o);
    if (a - 2.0 * sd > limit) {
      const double file = q == machine::Quantity::Length ? 1e3 : 1e6;
      Decision d{Reason::implausible_change, std::string(machine::info(c.chain, ch.component).name), {},
                 {{"reach", a * file}, {"limit", limit * file}}};
      d.unit = unit_of(q);
      c.rejection = std::move(d);
    }
    return c;
  }
};

} // namespace

std::shared_ptr<const HypothesisFamily> make_component_periodic() { return std::make_shared<ComponentPeriodic>(); }

} // namespace geartopo::diagnosis::families
