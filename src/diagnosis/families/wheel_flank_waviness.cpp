// geartopo diagnosis — hypothesis family: one wheel flank's profile waviness (the other flank smooth), a·cos(2π n t − φ)
// over the active profile (t its roll fraction from the root): a wheel dressed with a wavy diamond roll on one side,
// MASTA's wheel waviness per flank. Cos and sin parts fitted (wheel_flank_waviness' linear parameters of that side);
// the wave count n on a grid of 1.5 … 12 waves, charged ln n like a parameter, the best count of a side kept.
#include "effect_columns.hpp"
#include "family_list.hpp"

#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace geartopo::diagnosis::families {
namespace {

/// The effect's parameters of a side: left_cos_um, left_sin_um (0, 1) or right_… (2, 3); 4 is the wave count.
std::vector<int> waviness_parameters(Flank side) { return side == Flank::Left ? std::vector<int>{0, 1} : std::vector<int>{2, 3}; }

class WheelFlankWaviness final : public HypothesisFamily {
public:
  std::string_view name() const override { return "wheel_flank_waviness"; }
  std::string_view effect_type() const override { return "wheel_flank_waviness"; }
  int grid_parameters() const override { return 1; } // the wave count
  std::vector<Candidate> enumerate(const ContactStates&, const DiagnoseOptions&) const override {
    std::vector<Candidate> out;
    for (Flank side : {Flank::Left, Flank::Right})
      for (const double cycles : {1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0}) {
        Candidate h;
        h.effects.push_back({"wheel_flank_waviness", {0.0, 0.0, 0.0, 0.0, cycles}});
        h.wheel_flank = side;
        out.push_back(std::move(h));
      }
    return out;
  }
  Eigen::MatrixXd columns(const Candidate& h, const ContactStates& states) const override {
    return effect_columns(h.effects.front(), waviness_parameters(*h.wheel_flank), states);
  }
  Eigen::VectorXd plausible_size(const Candidate&, const ContactStates&, const DiagnoseOptions& o) const override {
    return Eigen::VectorXd::Constant(2, o.plausible_wheel_profile_um);
  }
  Candidate finding(Candidate c, const LinearFit& f, const ContactStates&, const DiagnoseOptions& o) const override {
    const auto idx = waviness_parameters(*c.wheel_flank);
    auto& values = c.effects.front().values;
    values[static_cast<size_t>(idx[0])] = f.beta(0), values[static_cast<size_t>(idx[1])] = f.beta(1);
    const std::string side = side_word(*c.wheel_flank);
    // amplitude a = |β| and its σ to first order along β (as a change per revolution)
    const double a = f.beta.norm();
    const Eigen::Vector2d g = a > 0.0 ? Eigen::Vector2d(f.beta / a) : Eigen::Vector2d(1.0, 0.0);
    const double a_sd = std::sqrt(g.dot(f.cov * g));
    // a·cos(2π n t − φ): φ = atan2(b, a_cos), its σ to first order across β (h ⟂ g), in degrees
    const Eigen::Vector2d h(-g(1), g(0));
    const double phase_deg = std::atan2(f.beta(1), f.beta(0)) * 180.0 / std::numbers::pi;
    const double phase_sd_deg = a > 0.0 ? std::sqrt(h.dot(f.cov * h)) / a * 180.0 / std::numbers::pi : 180.0;
    c.parameters.push_back({{side + "_cos_um", f.beta(0), std::sqrt(f.cov(0, 0)), true},
                            {side + "_sin_um", f.beta(1), std::sqrt(f.cov(1, 1)), true},
                            {"cycles", values[4], 0.0, true}});
    c.description = fmt::format("the wheel flank that grinds the {} flanks is wavy: amplitude {} µm, {:g} waves over "
                                "the active profile, phase {}° at its root (the other wheel flank smooth)",
                                side, text::with_uncertainty(a, a_sd), values[4],
                                text::with_uncertainty(phase_deg, phase_sd_deg));
    if (a - 2.0 * a_sd > o.plausible_wave_um)
      c.rejection = Decision{Reason::implausible_wave, c.name(), {}, {{"amplitude_um", a}, {"limit_um", o.plausible_wave_um}}};
    return c;
  }
  /// Only the best wave count of each side (the first of equals).
  std::vector<Candidate> select(std::vector<Candidate> mine, const std::vector<Candidate>&,
                                const DiagnoseOptions&) const override {
    std::vector<Candidate> kept;
    for (size_t a = 0; a < mine.size(); ++a) {
      bool best = true;
      for (size_t b = 0; b < mine.size() && best; ++b)
        best = b == a || mine[b].wheel_flank != mine[a].wheel_flank || mine[b].delta_bic > mine[a].delta_bic ||
               (mine[b].delta_bic == mine[a].delta_bic && b > a);
      if (best) kept.push_back(std::move(mine[a]));
    }
    return kept;
  }
  std::string scene_name(const Candidate&) const override { return "wheel_flank_waviness"; }
};

} // namespace

std::shared_ptr<const HypothesisFamily> make_wheel_flank_waviness() { return std::make_shared<WheelFlankWaviness>(); }

} // namespace geartopo::diagnosis::families
