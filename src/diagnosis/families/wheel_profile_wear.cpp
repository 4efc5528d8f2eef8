// geartopo diagnosis — hypothesis family: the wheel's profile wearing with every stroke (its edge faster than its
// flanks), not dressed during the gear: the gear's profile slope and crowning growing along the grinding order
// (wheel_profile_wear's two rates per stroke fitted, linear; no dressing interval assumed).
#include "effect_columns.hpp"
#include "family_list.hpp"

#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>

namespace geartopo::diagnosis::families {
namespace {

class WheelProfileWear final : public HypothesisFamily {
public:
  std::string_view name() const override { return "wheel_profile_wear"; }
  std::string_view effect_type() const override { return "wheel_profile_wear"; }
  std::vector<Candidate> enumerate(const ContactStates&, const DiagnoseOptions&) const override {
    Candidate h;
    h.effects.push_back({"wheel_profile_wear", {0.0, 0.0, 0.0}});
    return {h};
  }
  Eigen::MatrixXd columns(const Candidate& h, const ContactStates& states) const override {
    return effect_columns(h.effects.front(), {0, 1}, states);
  }
  Eigen::VectorXd plausible_size(const Candidate&, const ContactStates&, const DiagnoseOptions& o) const override {
    return Eigen::VectorXd::Constant(2, o.plausible_wheel_profile_um);
  }
  Candidate finding(Candidate c, const LinearFit& f, const ContactStates& states, const DiagnoseOptions&) const override {
    auto& values = c.effects.front().values;
    values[0] = f.beta(0), values[1] = f.beta(1);
    const double slope_sd = std::sqrt(f.cov(0, 0)), crowning_sd = std::sqrt(f.cov(1, 1));
    c.parameters.push_back({{"profile_slope_um_per_stroke", f.beta(0), slope_sd, true},
                            {"profile_crowning_um_per_stroke", f.beta(1), crowning_sd, true},
                            {"dressing_interval_strokes", 0.0, 0.0, false}});
    const double strokes = static_cast<double>(states.setup().path().strokes().size());
    c.description = fmt::format(
        "the wheel's profile wears with the strokes: the gear profile slope changes by {} µm and its crowning by {} "
        "µm per stroke ({} µm and {} µm over the {:.0f} strokes)",
        text::with_uncertainty(f.beta(0), slope_sd, true), text::with_uncertainty(f.beta(1), crowning_sd, true),
        text::with_uncertainty(f.beta(0) * strokes, slope_sd * strokes, true),
        text::with_uncertainty(f.beta(1) * strokes, crowning_sd * strokes, true), strokes);
    for (int j = 0; j < 2 && !c.rejection; ++j)
      c.rejection = implausible("wheel_profile_wear", j, f.beta(j), std::sqrt(f.cov(j, j)));
    return c;
  }
  std::string scene_name(const Candidate&) const override { return "wheel_profile_wear"; }
};

} // namespace

std::shared_ptr<const HypothesisFamily> make_wheel_profile_wear() { return std::make_shared<WheelProfileWear>(); }

} // namespace geartopo::diagnosis::families
