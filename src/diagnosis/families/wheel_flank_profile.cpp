// geartopo diagnosis — hypothesis family: a profile error of one wheel flank (the other flank true): the gear flanks
// it grinds get its slope and crowning (µm), the others nothing — a dressing error on one side of the wheel. The
// wheel_flank_profile effect with the two parameters of one side fitted (both linear, zero by default).
#include "effect_columns.hpp"
#include "family_list.hpp"

#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>

namespace geartopo::diagnosis::families {
namespace {

/// The effect's parameters of a side: left_slope_um, left_crowning_um (0, 1) or right_… (2, 3).
std::vector<int> profile_parameters(Flank side) { return side == Flank::Left ? std::vector<int>{0, 1} : std::vector<int>{2, 3}; }

class WheelFlankProfile final : public HypothesisFamily {
public:
  std::string_view name() const override { return "wheel_flank_profile"; }
  std::string_view effect_type() const override { return "wheel_flank_profile"; }
  std::vector<Candidate> enumerate(const ContactStates&, const DiagnoseOptions&) const override {
    std::vector<Candidate> out;
    for (Flank side : {Flank::Left, Flank::Right}) {
      Candidate h;
      h.effects.push_back({"wheel_flank_profile", std::vector<double>(4, 0.0)});
      h.wheel_flank = side;
      out.push_back(std::move(h));
    }
    return out;
  }
  Eigen::MatrixXd columns(const Candidate& h, const ContactStates& states) const override {
    return effect_columns(h.effects.front(), profile_parameters(*h.wheel_flank), states);
  }
  Eigen::VectorXd plausible_size(const Candidate&, const ContactStates&, const DiagnoseOptions& o) const override {
    return Eigen::VectorXd::Constant(2, o.plausible_wheel_profile_um);
  }
  Candidate finding(Candidate c, const LinearFit& f, const ContactStates&, const DiagnoseOptions&) const override {
    const auto idx = profile_parameters(*c.wheel_flank);
    auto& values = c.effects.front().values;
    values[static_cast<size_t>(idx[0])] = f.beta(0), values[static_cast<size_t>(idx[1])] = f.beta(1);
    const std::string side = side_word(*c.wheel_flank);
    const double slope_sd = std::sqrt(f.cov(0, 0)), crowning_sd = std::sqrt(f.cov(1, 1));
    c.parameters.push_back({{side + "_slope_um", f.beta(0), slope_sd, true},
                            {side + "_crowning_um", f.beta(1), crowning_sd, true}});
    c.description = fmt::format("the wheel flank that grinds the {} flanks has a profile error: slope {} µm, crowning {} "
                                "µm on those flanks (the other wheel flank none)",
                                side, text::with_uncertainty(f.beta(0), slope_sd, true),
                                text::with_uncertainty(f.beta(1), crowning_sd, true));
    for (int j = 0; j < 2 && !c.rejection; ++j)
      c.rejection = implausible("wheel_flank_profile", idx[static_cast<size_t>(j)], f.beta(j), std::sqrt(f.cov(j, j)));
    return c;
  }
  std::string scene_name(const Candidate&) const override { return "wheel_flank_profile"; }
};

} // namespace

std::shared_ptr<const HypothesisFamily> make_wheel_flank_profile() { return std::make_shared<WheelFlankProfile>(); }

} // namespace geartopo::diagnosis::families
