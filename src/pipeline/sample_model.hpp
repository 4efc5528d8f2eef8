// geartopo — what one Monte Carlo sample is (private to pipeline; docs/monte-carlo.md): its draws from the streams of
// (seed, k), and its two gears, computed exactly (the drawn machine simulated) or to first order (the nominal gears
// plus the sensitivities times the draw, topology_sensitivities.hpp; the effects' drawn values exactly in the values,
// to first order in the µm they move the wheel: diagnosis::EffectContribution). Prepared once per run: the plan, the
// nominal corrections (rounded and not), and for linear samples the sensitivities of both gears.
#pragma once

#include "geartopo/core/random.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/pipeline/topology_sensitivities.hpp"

#include <map>
#include <memory>
#include <optional>
#include <set>

namespace geartopo::pipeline::detail {

/// Everything sample k draws, in the order it draws it from sample_stream(seed, k): 43 map deviates, 5 axes per space
/// for gear 1, 5 per space for gear 2, then the effects' deviates (correlated by the scene's factor; the whole vector
/// drawn again while a value leaves its allowed range), then the index of the effects' value set.
struct SampleDraw {
  machine::ErrorVector z_map;
  std::map<int, machine::Vector5d> off_before, off_after;
  Eigen::VectorXd z_effects;
  int effect_set = -1; ///< row of Scene::effect_draws this sample grinds with; −1: the scene has no value sets
  bool effects_drawn() const { return z_effects.size() > 0 || effect_set >= 0; }
};

/// Both gears of a sample as topologies (exact samples).
struct SampleGears {
  std::vector<grinding::FlankTopology> before, after;
};

/// Both gears of a linear sample as deviations (µm, flattened: topology_sensitivities.hpp), and with `decompose` the
/// after-gear with each source of SampleModel::without() switched off.
struct LinearGears {
  Eigen::VectorXd before, after;
  std::vector<Eigen::VectorXd> after_without;
};

class SampleModel {
public:
  /// Throws std::invalid_argument for bad options. `prepare_linear`: compute the sensitivities (Sampling::Exact needs
  /// none).
  SampleModel(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal, const MonteCarloOptions& options,
              bool prepare_linear);

  SampleDraw draw(long long k) const;
  /// The drawn machine simulated (the exact envelope), no probe noise.
  SampleGears exact(const SampleDraw& d) const;
  /// Nominal + sensitivities × draw; with `decompose`, also the after-gear without each source of without().
  LinearGears linear(const SampleDraw& d, bool decompose) const;
  /// Both gears measured with the probe noise of sample k, from its own stream (gear 1 first; every trace, then grid
  /// point of each flank: diagnosis::add_probe_noise); the variants of gear 2 with gear 2's noise, except the one
  /// without probe noise.
  void add_probe_noise(SampleGears& g, long long k) const;
  void add_probe_noise(LinearGears& g, long long k) const;
  /// The topology layout of linear samples (the nominal after-gear; set_deviations fills in a sample's values).
  const std::vector<grinding::FlankTopology>& layout() const { return layout_; }
  /// The sources a linear sample can switch off on this scene (limit_sources names: only those present).
  const std::vector<std::string>& without() const { return without_; }

  const grinding::TopologyPlan& plan() const { return *plan_; }

private:
  const workbench::Workbench& wb_;
  MonteCarloOptions options_;
  std::vector<machine::ErrorSource> nominal_map_;
  compensation::CorrectionTable applied_, uncorrected_;
  std::set<int> spaces_;
  Eigen::MatrixXd effect_factor_;
  std::vector<UncertainEffectValue> effect_values_;
  bool effects_uncertain_ = false; ///< some effect value is drawn: Gaussian (effect_values_) or from value sets
  /// Whether z (the correlated deviates of effect_values_) keeps every drawn value inside its allowed range.
  bool inside_ranges(const Eigen::VectorXd& z) const;
  grinding::SimulationOptions so_;
  std::unique_ptr<grinding::TopologyPlan> plan_;
  // Linear samples: the sensitivities of gear 1 (uncorrected) and gear 2 (rounded corrections); the nominal gear 2
  // with the corrections not rounded (the "without rounding" variant); the topologies whose values they overwrite.
  std::optional<TopologySensitivities> before_, after_;
  Eigen::VectorXd after_unrounded_um_;
  std::vector<grinding::FlankTopology> layout_;
  /// The effects with sample d's drawn values: its value set, its Gaussian values (inside their ranges).
  std::vector<std::unique_ptr<effects::Effect>> drawn_effects(const SampleDraw& d) const;
  std::vector<int> space_slot_; // per point: index of its space in spaces_
  // Uncertain effects: their first-order deviation at the points for any values (a sample's drawn ones), and at the
  // scene's values (what d₀ holds already).
  std::unique_ptr<diagnosis::EffectContribution> effect_points_;
  Eigen::VectorXd effect_nominal_um_;
  std::vector<std::string> without_;
};

} // namespace geartopo::pipeline::detail
