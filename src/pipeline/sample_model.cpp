#include "sample_model.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geartopo::pipeline::detail {
namespace {

using random::SplitMix64; // core/random.hpp: one stream per (seed, sample)

SplitMix64 sample_stream(std::uint64_t seed, long long k) {
  SplitMix64 mix{seed};
  const std::uint64_t a = mix.next();
  SplitMix64 per_sample{a ^ static_cast<std::uint64_t>(k) * 0xD1B54A32D192ED03ull};
  (void)per_sample.next(); // decorrelate neighbouring k
  return per_sample;
}

/// The probe's own stream of sample k (MonteCarloOptions::probe_noise_um): seeded by the second number of the seed's
/// SplitMix64 sequence (sample_stream takes the first), so the machine's draws of sample k are the same with or
/// without probe noise.
SplitMix64 probe_stream(std::uint64_t seed, long long k) {
  SplitMix64 mix{seed};
  (void)mix.next();
  const std::uint64_t b = mix.next();
  SplitMix64 per_sample{b ^ static_cast<std::uint64_t>(k) * 0xD1B54A32D192ED03ull};
  (void)per_sample.next();
  return per_sample;
}

std::vector<machine::ErrorSource> full_map(const std::vector<machine::ErrorSource>& given) {
  std::vector<machine::ErrorSource> all;
  all.reserve(machine::kComponentCount);
  for (int k = 0; k < machine::kComponentCount; ++k) all.push_back(machine::ErrorSource::zero(machine::component_at(k)));
  for (const auto& s : given) all[static_cast<size_t>(machine::index(s.id()))] = s;
  return all;
}

/// Lower Cholesky factor of the scene's effect correlation (N × N), empty when the values are independent. A
/// correlation that is not positive definite (rounding of a nearly singular fit) gets a small ridge.
Eigen::MatrixXd correlation_factor(const scene::Scene& s) {
  if (s.effect_correlation.size() == 0) return {};
  Eigen::MatrixXd C = s.effect_correlation;
  for (double ridge = 0.0; ridge < 1.0; ridge = ridge == 0.0 ? 1e-12 : ridge * 10.0) {
    const Eigen::LLT<Eigen::MatrixXd> llt((C + ridge * Eigen::MatrixXd::Identity(C.rows(), C.cols())) / (1.0 + ridge));
    if (llt.info() == Eigen::Success) return llt.matrixL();
  }
  return Eigen::MatrixXd::Identity(C.rows(), C.cols());
}

bool any_uncertain(const std::vector<UncertainEffectValue>& values) {
  return std::any_of(values.begin(), values.end(), [](const UncertainEffectValue& v) { return v.u > 0.0; });
}

} // namespace

SampleModel::SampleModel(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                         const MonteCarloOptions& options, bool prepare_linear)
    : wb_(wb), options_(options), nominal_map_(full_map(wb.scene.machine.sources)),
      applied_(rounded_to_resolution(nominal, wb.scene.machine.uncertainty.resolution)), uncorrected_(nominal) {
  if (!(options.probe_noise_um >= 0.0) || !std::isfinite(options.probe_noise_um))
    throw std::invalid_argument(fmt::format("probe noise {} µm: need a finite σ ≥ 0", options.probe_noise_um));
  std::vector<compensation::CorrectionRow> zero_rows = nominal.rows();
  for (auto& r : zero_rows) r.correction.setZero();
  uncorrected_ = compensation::CorrectionTable(std::move(zero_rows), nominal.axes());
  for (const auto& r : nominal.rows()) spaces_.insert(r.space);
  effect_factor_ = correlation_factor(wb.scene);
  effect_values_ = uncertain_effect_values(wb.scene);
  effects_uncertain_ = any_uncertain(effect_values_) || !wb.scene.effect_draws.empty();

  so_.rows = wb.scene.grid.rows;
  so_.cols = wb.scene.grid.cols;
  so_.profile_points = wb.scene.grid.profile_points;
  so_.helix_points = wb.scene.grid.helix_points;
  so_.teeth = wb.scene.grid.teeth;
  so_.threads = 1; // parallel over samples instead
  plan_ = std::make_unique<grinding::TopologyPlan>(wb.setup, so_); // the points' geometry, computed once for every gear
  if (!prepare_linear) return;

  // Sensitivities of both gears at their nominal states (on all threads: once per run), and the nominal gear 2 with
  // the corrections as computed, not rounded: the rounding's share of the after-state.
  before_ = topology_sensitivities(wb, *plan_, uncorrected_, options.threads);
  after_ = topology_sensitivities(wb, *plan_, applied_, options.threads);
  {
    const compensation::CompensatedProcess unrounded(wb.process(), nominal); // the scene's machine, effects and design
    layout_ = plan_->simulate(unrounded, options.threads);
    after_unrounded_um_ = flatten_deviations(layout_);
  }
  std::map<int, int> slot;
  for (const int s : spaces_) slot.emplace(s, static_cast<int>(slot.size()));
  space_slot_.reserve(before_->space.size());
  for (const int s : before_->space) {
    const auto it = slot.find(s);
    if (it == slot.end()) throw std::invalid_argument(fmt::format("no correction rows for space {}", s));
    space_slot_.push_back(it->second);
  }

  if (effects_uncertain_) {
    std::vector<diagnosis::MeasuredPoint> points;
    for (const auto& ft : layout_) {
      for (const auto& p : ft.grid) points.push_back({ft.tooth, ft.flank, p.row, p.col, p.roll_length_mm, p.diameter_mm, p.z_mm});
      for (const auto* trace : {&ft.profile, &ft.helix})
        for (const auto& p : *trace) points.push_back({ft.tooth, ft.flank, 0, 0, p.roll_length_mm, p.diameter_mm, p.z_mm});
      for (const auto& p : ft.dense) points.push_back({ft.tooth, ft.flank, p.row, p.col, p.roll_length_mm, p.diameter_mm, p.z_mm});
    }
    effect_points_ = std::make_unique<diagnosis::EffectContribution>(wb.setup, points, options.threads);
    std::vector<const effects::Effect*> nominal_effects;
    for (const auto& e : wb.effects) nominal_effects.push_back(e.get());
    effect_nominal_um_ = effect_points_->deviation_um(nominal_effects, options.threads);
  }

  const auto& unc = wb.scene.machine.uncertainty;
  if (!after_->map_um.isZero(0.0)) without_.push_back("map_uncertainty");
  if (!unc.repeatability.isZero(0.0)) without_.push_back("repeatability");
  if ((unc.resolution.array() > 0.0).any()) without_.push_back("resolution_rounding");
  if (effects_uncertain_) without_.push_back("effect_uncertainty");
  if (options.probe_noise_um > 0.0) without_.push_back("probe_noise");
}

SampleDraw SampleModel::draw(long long k) const {
  SplitMix64 rng = sample_stream(options_.seed, k);
  SampleDraw d;
  for (int c = 0; c < machine::kComponentCount; ++c) d.z_map(c) = rng.normal();
  const std::function<double()> standard_normal = [&rng] { return rng.normal(); };
  const auto& rep = wb_.scene.machine.uncertainty.repeatability;
  d.off_before = draw_stroke_offsets(spaces_, rep, standard_normal);
  d.off_after = draw_stroke_offsets(spaces_, rep, standard_normal);
  // Effects with uncertain values: drawn last, jointly with the scene's correlation of them when it has one, and
  // truncated to the allowed ranges by drawing the whole vector again (a time constant stays above its bound, the
  // correlation holds inside the box); held at the bounds only when a thousand draws in a row leave them.
  if (any_uncertain(effect_values_)) {
    d.z_effects.resize(static_cast<Eigen::Index>(effect_values_.size()));
    for (int attempt = 0; attempt < 1000; ++attempt) {
      for (auto& z : d.z_effects) z = rng.normal();
      // The effects' values are correlated as the scene says; the machine changes' sizes after them independently.
      const Eigen::Index m = effect_factor_.rows();
      if (m > 0 && m <= d.z_effects.size()) d.z_effects.head(m) = effect_factor_ * d.z_effects.head(m);
      if (inside_ranges(d.z_effects)) break;
    }
  }
  // One of the scene's equally likely value sets, the same for every effect that has them (they are joint).
  if (!wb_.scene.effect_draws.empty()) {
    Eigen::Index sets = 0;
    for (const auto& m : wb_.scene.effect_draws) sets = std::max(sets, m.rows());
    d.effect_set = static_cast<int>(std::min<Eigen::Index>(static_cast<Eigen::Index>(rng.uniform() * static_cast<double>(sets)), sets - 1));
  }
  return d;
}

bool SampleModel::inside_ranges(const Eigen::VectorXd& z) const {
  for (size_t j = 0; j < effect_values_.size(); ++j) {
    const auto& v = effect_values_[j];
    if (!(v.u > 0.0)) continue;
    double value = 0.0;
    if (v.change) {
      const auto& ch = wb_.scene.machine_changes[v.effect];
      value = ch.size * machine::file_per_internal(ch.law, machine::info(ch.component).quantity);
    } else {
      value = wb_.scene.effects[v.effect].values[v.value];
    }
    const double drawn = value + v.u * z(static_cast<Eigen::Index>(j));
    if (!(drawn >= v.lo && drawn <= v.hi)) return false;
  }
  return true;
}

std::vector<std::unique_ptr<effects::Effect>> SampleModel::drawn_effects(const SampleDraw& d) const {
  if (!d.effects_drawn()) return {};
  std::vector<scene::EffectSpec> specs = wb_.scene.effects;
  std::vector<machine::ComponentChange> changes = wb_.scene.machine_changes;
  // The sample's value set of every effect that has sets (Scene::effect_draws: row j of each belongs together).
  for (size_t e = 0; d.effect_set >= 0 && e < specs.size() && e < wb_.scene.effect_draws.size(); ++e) {
    const auto& sets = wb_.scene.effect_draws[e];
    if (d.effect_set >= sets.rows()) continue;
    for (size_t v = 0; v < specs[e].values.size(); ++v)
      specs[e].values[v] = sets(d.effect_set, static_cast<Eigen::Index>(v));
  }
  // Each uncertain value within its standard uncertainty (draw() kept it inside the effect's range; the clamp holds
  // the rare draw that a thousand attempts did not bring inside).
  for (size_t j = 0; j < effect_values_.size() && d.z_effects.size() > 0; ++j) {
    const auto& v = effect_values_[j];
    const double z = d.z_effects(static_cast<Eigen::Index>(j));
    if (v.change) { // file units of the change's key, held inside what the scene reader accepts
      auto& ch = changes[v.effect];
      const double scale = machine::file_per_internal(ch.law, machine::info(ch.component).quantity);
      ch.size = std::clamp(ch.size * scale + v.u * z, v.lo, v.hi) / scale;
      continue;
    }
    auto& value = specs[v.effect].values[v.value];
    value = std::clamp(value + v.u * z, v.lo, v.hi);
  }
  return workbench::make_effects(specs, changes, wb_.setup, wb_.scene.machine.chain, wb_.scene.machine.datum_face_z_mm);
}

SampleGears SampleModel::exact(const SampleDraw& d) const {
  const auto& unc = wb_.scene.machine.uncertainty;
  std::vector<machine::ErrorSource> truth;
  truth.reserve(nominal_map_.size());
  // Each: + z·u, u the scene's constant, or z·u(p) from the component's table column (ErrorSource::drawn).
  for (size_t c = 0; c < nominal_map_.size(); ++c)
    truth.push_back(nominal_map_[c].drawn(d.z_map(static_cast<Eigen::Index>(c)), unc.component_u[c]));
  const auto drawn = drawn_effects(d);
  const auto& sample_effects = d.effects_drawn() ? drawn : wb_.effects;

  const machine::MachineModel model(wb_.machine.strokes(), std::move(truth));
  const auto machine_process =
      workbench::make_machine_process(*wb_.scene.machine.chain, model, wb_.scene.machine.datum_face_z_mm);
  std::unique_ptr<effects::EffectsProcess> with_effects;
  if (!sample_effects.empty())
    with_effects = std::make_unique<effects::EffectsProcess>(*machine_process, sample_effects, wb_.scene.machine.chain,
                                                             wb_.scene.machine.datum_face_z_mm);
  const workbench::WithDesignMotion true_machine(
      wb_, with_effects ? static_cast<const grinding::GrindingProcess&>(*with_effects) : *machine_process);

  const auto table_before = with_stroke_offsets(uncorrected_, d.off_before);
  const auto table_after = with_stroke_offsets(applied_, d.off_after);
  const compensation::CompensatedProcess gear1(true_machine.process(), table_before),
      gear2(true_machine.process(), table_after);
  SampleGears g;
  g.before = plan_->simulate(gear1, so_.threads);
  g.after = plan_->simulate(gear2, so_.threads);
  return g;
}

LinearGears SampleModel::linear(const SampleDraw& d, bool decompose) const {
  if (!before_ || !after_) throw std::logic_error("linear samples of a model prepared for exact ones");
  const auto n = before_->nominal_um.size();
  // Each source's first-order share of both gears (N).
  const Eigen::VectorXd map_b = before_->map_um * d.z_map, map_a = after_->map_um * d.z_map;
  Eigen::Matrix<double, 5, Eigen::Dynamic> off_b(5, static_cast<Eigen::Index>(spaces_.size())), off_a = off_b;
  {
    Eigen::Index c = 0;
    for (const int s : spaces_) off_b.col(c) = d.off_before.at(s), off_a.col(c++) = d.off_after.at(s);
  }
  Eigen::VectorXd stroke_b(n), stroke_a(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int slot = space_slot_[static_cast<size_t>(i)];
    stroke_b(i) = before_->stroke_um.row(i).dot(off_b.col(slot));
    stroke_a(i) = after_->stroke_um.row(i).dot(off_a.col(slot));
  }
  // The effects at the drawn values less at the scene's: exact in the values (a time constant is not linear in its
  // draw), first order in the µm they move the wheel; the same at both gears' points (µm of correction do not change
  // where and when a point is ground).
  Eigen::VectorXd eff = Eigen::VectorXd::Zero(n);
  if (d.effects_drawn() && effect_points_) {
    const auto drawn = drawn_effects(d);
    std::vector<const effects::Effect*> ptrs;
    for (const auto& e : drawn) ptrs.push_back(e.get());
    eff = effect_points_->deviation_um(ptrs, 1) - effect_nominal_um_;
  }
  const Eigen::VectorXd& eff_b = eff;
  const Eigen::VectorXd& eff_a = eff;
  LinearGears g;
  g.before = before_->nominal_um + map_b + stroke_b + eff_b;
  g.after = after_->nominal_um + map_a + stroke_a + eff_a;
  if (!decompose) return g;
  for (const auto& source : without_) {
    Eigen::VectorXd v = g.after;
    if (source == "map_uncertainty") v -= map_a;
    else if (source == "repeatability") v -= stroke_a;
    else if (source == "resolution_rounding") v += after_unrounded_um_ - after_->nominal_um;
    else if (source == "effect_uncertainty") v -= eff_a;
    // probe_noise: the same gear, measured without noise (add_probe_noise leaves it as it is)
    g.after_without.push_back(std::move(v));
  }
  return g;
}

void SampleModel::add_probe_noise(SampleGears& g, long long k) const {
  if (options_.probe_noise_um <= 0.0) return;
  // Both gears measured, gear 1 first, from the probe's own stream of (seed, k).
  SplitMix64 probe = probe_stream(options_.seed, k);
  const std::function<double()> probe_normal = [&probe] { return probe.normal(); };
  diagnosis::add_probe_noise(g.before, options_.probe_noise_um, probe_normal);
  diagnosis::add_probe_noise(g.after, options_.probe_noise_um, probe_normal);
}

void SampleModel::add_probe_noise(LinearGears& g, long long k) const {
  if (options_.probe_noise_um <= 0.0) return;
  // The same deviates at the same points as for exact samples: drawn onto a zero topology in add_probe_noise's order.
  SplitMix64 probe = probe_stream(options_.seed, k);
  const std::function<double()> probe_normal = [&probe] { return probe.normal(); };
  std::vector<grinding::FlankTopology> noise = layout_;
  const auto draw = [&] {
    set_deviations(noise, Eigen::VectorXd::Zero(g.after.size()));
    diagnosis::add_probe_noise(noise, options_.probe_noise_um, probe_normal);
    return flatten_deviations(noise);
  };
  g.before += draw();
  const Eigen::VectorXd on_gear2 = draw();
  g.after += on_gear2;
  for (size_t s = 0; s < without_.size() && s < g.after_without.size(); ++s)
    if (without_[s] != "probe_noise") g.after_without[s] += on_gear2;
}

} // namespace geartopo::pipeline::detail
