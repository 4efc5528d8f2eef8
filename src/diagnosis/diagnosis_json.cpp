// geartopo diagnosis — diagnosis.json and plan.json (diagnosis_json.hpp).
#include "geartopo/diagnosis/diagnosis_json.hpp"

#include "geartopo/diagnosis/hypothesis_family.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/machine/error_component.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <sstream>
#include <vector>

namespace geartopo::diagnosis {

std::string unit_of_key(const std::string& key) {
  static const char* const units[] = {"um", "urad", "rad", "mm", "s", "ms", "hz", "deg", "strokes"};
  std::vector<std::string> tokens;
  std::stringstream in(key);
  for (std::string t; std::getline(in, t, '_');) tokens.push_back(t);
  for (size_t k = 1; k < tokens.size(); ++k) // the first token is the quantity's name, never its unit
    for (const char* u : units)
      if (tokens[k] == u) {
        std::string out = tokens[k];
        for (size_t m = k + 1; m < tokens.size(); ++m) out += "_" + tokens[m];
        return out;
      }
  return "";
}

nlohmann::json decision_json(const Decision& d) {
  nlohmann::json numbers = nlohmann::json::object();
  for (const auto& [key, value] : d.numbers) {
    if (!numbers.contains(key)) numbers[key] = nlohmann::json::array();
    numbers[key].push_back(value);
  }
  // A number named once is a number, one named for each part (parts_cancel's part_rms_um) a list.
  for (auto& [key, value] : numbers.items())
    if (value.size() == 1 && d.reason != Reason::parts_cancel) value = value.front();
  nlohmann::json j{{"reason", to_string(d.reason)}, {"subject", d.subject}, {"names", d.names}, {"numbers", numbers},
                   {"text", to_text(d)}};
  if (!d.unit.empty()) j["unit"] = d.unit;
  if (!d.test.empty()) j["test"] = d.test;
  return j;
}

namespace {

nlohmann::json residual_pattern_json(const ResidualPattern& p) {
  nlohmann::json largest = nlohmann::json::array(), teeth = nlohmann::json::array();
  for (const auto& s : p.largest)
    largest.push_back({{"pattern", s.pattern}, {"mean_um", s.mean_um}, {"lo_um", s.lo_um}, {"hi_um", s.hi_um}});
  for (const auto& [tooth, rms] : p.tooth_rms_um) teeth.push_back({{"tooth", tooth}, {"rms_um", rms}});
  return {{"largest", largest}, {"flanks", p.flanks}, {"tooth_rms", teeth}};
}

} // namespace

nlohmann::json candidate_json(const Candidate& c) {
  nlohmann::json j;
  j["effect"] = c.name();
  nlohmann::json params = nlohmann::json::object();
  for (size_t e = 0; e < c.effects.size(); ++e)
    for (const auto& p : c.parameters[e]) {
      const std::string key = c.effects.size() > 1 ? c.effects[e].type + "." + p.key : p.key;
      params[key] = {{"value", p.value},
                     {"uncertainty", p.fitted ? nlohmann::json(p.uncertainty) : nlohmann::json(nullptr)},
                     {"unit", unit_of_key(p.key)},
                     {"fitted", p.fitted},
                     {"determined", p.determined}};
    }
  // A machine change's fitted values (its size under its law's key, the phase or τ) stand where an effect's do.
  if (c.effects.empty() && !c.parameters.empty())
    for (const auto& p : c.parameters.front())
      params[p.key] = {{"value", p.value}, {"uncertainty", p.uncertainty}, {"unit", unit_of_key(p.key)},
                       {"fitted", p.fitted}, {"determined", p.determined}};
  j["parameters"] = params;
  if (!c.changes.empty()) {
    // Beyond the library: the changed component, its law and size in file units (docs/scene-format.md,
    // machine_changes), and the hypotheses these flanks cannot tell from it.
    nlohmann::json changes = nlohmann::json::array();
    for (size_t k = 0; k < c.changes.size(); ++k) {
      const auto& ch = c.changes[k];
      const auto q = machine::info(ch.component).quantity;
      const double scale = machine::file_per_internal(ch.law, q);
      nlohmann::json cj{{"component", machine::info(c.chain, ch.component).name},
                        {"meaning", machine::info(c.chain, ch.component).meaning},
                        {"law", ch.law_name()},
                        {machine::size_key(ch.law, q), ch.size * scale},
                        {"uncertainty", k < c.change_sd.size() ? c.change_sd[k] * scale : 0.0}};
      if (ch.law == machine::ChangeLaw::SteadyState) cj["time_constant_s"] = ch.time_constant_s;
      if (ch.law == machine::ChangeLaw::PerRevolution) {
        cj["phase_deg"] = ch.phase_rad * 180.0 / 3.141592653589793;
        cj["order"] = ch.order;
      }
      changes.push_back(cj);
    }
    j["machine_changes"] = changes;
  }
  if (!c.description.empty()) j["description"] = c.description;
  if (!c.equivalent.empty()) j["equivalent"] = c.equivalent;
  if (!c.library_equivalent.empty()) j["library_equivalent"] = c.library_equivalent;
  if (!c.look_alikes.empty()) {
    nlohmann::json alike = nlohmann::json::array();
    for (const auto& [name, rho] : c.look_alikes) alike.push_back({{"name", name}, {"abs_rho", rho}});
    j["look_alikes"] = alike;
  }
  j["explained_fraction"] = c.explained_fraction;
  j["rejected"] = c.rejection ? nlohmann::json(to_text(*c.rejection)) : nlohmann::json(nullptr);
  j["rejection"] = c.rejection ? decision_json(*c.rejection) : nlohmann::json(nullptr);
  if (c.family) j["family"] = c.family->name();
  j["rms_before_um"] = c.rms_before_um;
  j["rms_after_um"] = c.rms_after_um;
  j["delta_bic"] = c.delta_bic;
  j["significant"] = c.significant;
  j["explanation"] = c.explanations;
  return j;
}

nlohmann::json measurement_plan_json(const MeasurementPlan& plan) {
  nlohmann::json teeth = nlohmann::json::array();
  for (const auto& t : plan.teeth)
    teeth.push_back({{"tooth", t.tooth},
                     {"separation_sigma", t.separation_sigma},
                     {"max_difference_um", t.max_difference_um},
                     {"at", {{"flank", t.flank == Flank::Left ? "left" : "right"}, {"row", t.row}, {"col", t.col}}}});
  // A measurement option: new teeth, grid, and the ΔBIC gap expected after both explanations are refitted.
  const auto option_json = [](const MeasurementOption& m) {
    if (m.traces)
      return nlohmann::json{{"teeth", m.teeth},
                            {"traces", {{"profile_z_mm", m.profile_z_mm},
                                        {"helix_diameter_mm", m.helix_diameter_mm},
                                        {"points_per_trace", m.points_per_trace}}},
                            {"points", m.points},
                            {"separation_before_refit_sigma", m.separation_before_refit_sigma},
                            {"expected_delta_bic_if_first", m.delta_bic_if_first},
                            {"expected_delta_bic_if_second", m.delta_bic_if_second},
                            {"resolves", m.resolves}};
    return nlohmann::json{{"teeth", m.teeth},
                          {"grid", {{"rows", m.rows}, {"cols", m.cols}}},
                          {"points", m.points},
                          {"separation_before_refit_sigma", m.separation_before_refit_sigma},
                          {"expected_delta_bic_if_first", m.delta_bic_if_first},
                          {"expected_delta_bic_if_second", m.delta_bic_if_second},
                          {"resolves", m.resolves}};
  };
  nlohmann::json options = nlohmann::json::array();
  for (const auto& m : plan.options) options.push_back(option_json(m));
  return {{"between", {plan.first, plan.second}},
          {"delta_bic_gap", plan.delta_bic_gap},
          {"noise_um", plan.noise_um},
          {"grid", {{"rows", plan.rows}, {"cols", plan.cols}}},
          {"recommended_teeth", plan.recommended.teeth},
          {"recommended", option_json(plan.recommended)},
          {"options", options},
          {"row_separation_sigma", plan.row_separation_sigma},
          {"col_separation_sigma", plan.col_separation_sigma},
          {"teeth", teeth}};
}

nlohmann::json diagnosis_json(const std::string& scene, const std::string& measured, const Diagnosis& d,
                              double allowance_offset_um) {
  nlohmann::json j;
  j["scene"] = scene;
  j["measured"] = measured;
  j["points"] = d.points;
  j["nominal_offset_at_mean_allowance_um"] = allowance_offset_um;
  j["noise_um"] = d.noise_um;
  j["noise_estimated"] = d.noise_estimated;
  j["rms_before_um"] = d.rms_before_um;
  j["rms_before_setup_removed_um"] = d.rms_before_setup_um;
  // Not process physics: fitted alongside every explanation (docs/diagnosis.md, "Set-up terms").
  j["setup"] = {{"thickness_um", d.setup.thickness_um},
                {"thickness_sd_um", d.setup.thickness_sd_um},
                {"rotation_urad", d.setup.rotation_identified ? nlohmann::json(d.setup.rotation_urad) : nlohmann::json(nullptr)},
                {"rotation_sd_urad", d.setup.rotation_identified ? nlohmann::json(d.setup.rotation_sd_urad) : nlohmann::json(nullptr)},
                {"rotation_identified", d.setup.rotation_identified}};
  nlohmann::json cands = nlohmann::json::array();
  for (const auto& c : d.ranked) cands.push_back(candidate_json(c));
  j["candidates"] = cands;
  j["combination"] = d.combination ? candidate_json(*d.combination) : nlohmann::json(nullptr);
  j["chosen"] = d.chosen ? candidate_json(*d.chosen) : nlohmann::json(nullptr);
  // Within the ΔBIC threshold of the chosen one: the verdict says "ambiguous" and the plan what to measure next.
  j["ambiguous"] = !d.rivals.empty();
  nlohmann::json rivals = nlohmann::json::array();
  for (const auto& r : d.rivals) rivals.push_back(candidate_json(r));
  j["rivals"] = rivals;
  j["plan"] = d.plan ? measurement_plan_json(*d.plan) : nlohmann::json(nullptr);
  j["equivalent_plan"] = d.equivalent_plan ? measurement_plan_json(*d.equivalent_plan) : nlohmann::json(nullptr);
  // Beyond the library: tried when nothing in it explains the residual (docs/diagnosis.md).
  nlohmann::json hyps = nlohmann::json::array();
  for (const auto& h : d.hypotheses) hyps.push_back(candidate_json(h));
  j["beyond_library"] = {{"tried", !d.hypotheses.empty()}, {"chosen", d.beyond_library}, {"hypotheses", hyps}};
  // Nothing chosen: what came closest and why it is no explanation; "unexplained" when what is left is not noise.
  j["unexplained"] = d.unexplained;
  if (d.nearest) {
    j["nearest"] = candidate_json(*d.nearest);
    j["nearest"]["rejected_because"] = d.nearest_rejection ? to_text(*d.nearest_rejection) : std::string();
  } else {
    j["nearest"] = nullptr;
  }
  // The "more than noise" test's numbers: Σ r²/σ² of what is left (whitened when the stroke scatter is declared) and
  // its degrees of freedom (unit-free; docs/diagnosis.md, "Stroke-to-stroke scatter and the map's uncertainty").
  j["residual_chi2"] = d.chi2_after;
  j["residual_chi2_dof"] = d.chi2_dof;
  j["residual_pattern"] = d.residual_pattern ? nlohmann::json(to_text(*d.residual_pattern)) : nlohmann::json(nullptr);
  j["residual_pattern_record"] = d.residual_pattern ? residual_pattern_json(*d.residual_pattern) : nlohmann::json(nullptr);
  // Set-up values not fitted and not given (the effect's default), and what the data do fix when single values are
  // "not determined": the sentences, and the records they are made of.
  nlohmann::json assumed = nlohmann::json::array(), assumed_records = nlohmann::json::array();
  for (const auto& a : d.assumed) {
    assumed.push_back(to_text(a));
    assumed_records.push_back({{"effect", a.effect}, {"key", a.key}, {"value", a.value}, {"unit", unit_of_key(a.key)}});
  }
  j["assumed"] = assumed;
  j["assumed_records"] = assumed_records;
  nlohmann::json fixed = nlohmann::json::array(), fixed_records = nlohmann::json::array();
  for (const auto& g : d.determined) {
    fixed.push_back(to_text(g));
    fixed_records.push_back({{"axis", g.axis}, {"growth_um", g.value_um}, {"growth_sd_um", g.sd_um},
                             {"from_s", g.from_s}, {"to_s", g.to_s}});
  }
  j["determined_by_the_data"] = fixed;
  j["determined_records"] = fixed_records;
  // scene_with_effect.yaml is written only for an accepted explanation; otherwise why not.
  j["scene_with_effect_withheld"] = d.withheld ? nlohmann::json(to_text(*d.withheld)) : nlohmann::json(nullptr);
  j["rms_after_um"] = d.rms_after_um;
  // What the data determine when the chosen explanation's single values are open: its posterior as value sets, per
  // effect {"type", "values": {key: [draw 1, draw 2, …]}} (docs/diagnosis.md, "What the data determine").
  if (d.draws && d.chosen) {
    nlohmann::json effects = nlohmann::json::array();
    for (size_t e = 0; e < d.draws->values.size() && e < d.chosen->effects.size(); ++e) {
      const auto& m = d.draws->values[e];
      nlohmann::json values = nlohmann::json::object();
      const auto params = effects::make_effect(d.chosen->effects[e].type)->parameters();
      for (Eigen::Index c = 0; c < m.cols() && c < static_cast<Eigen::Index>(params.size()); ++c)
        values[params[static_cast<size_t>(c)].key] = std::vector<double>(m.col(c).data(), m.col(c).data() + m.rows());
      effects.push_back({{"type", d.chosen->effects[e].type}, {"values", values}});
    }
    j["posterior_draws"] = {{"draws", d.draws->values.empty() ? 0 : d.draws->values.front().rows()},
                            {"grid_points", d.draws->grid_points},
                            {"effects", effects}};
  } else {
    j["posterior_draws"] = nullptr;
  }
  // Every decision of the pipeline as a record (docs/diagnosis.md, "The verdict as data").
  nlohmann::json decisions = nlohmann::json::array();
  for (const auto& r : d.decisions()) decisions.push_back(decision_json(r));
  j["decisions"] = decisions;
  j["verdict"] = d.verdict;

  return j;
}

nlohmann::json plan_json(const std::string& scene, const std::string& measured, const Diagnosis& d) {
  nlohmann::json j;
  j["scene"] = scene;
  j["measured"] = measured;
  j["chosen"] = d.chosen ? nlohmann::json(d.chosen->name()) : nlohmann::json(nullptr);
  j["ambiguous"] = !d.rivals.empty();
  j["plan"] = d.plan ? measurement_plan_json(*d.plan) : nlohmann::json(nullptr);
  j["equivalent_plan"] = d.equivalent_plan ? measurement_plan_json(*d.equivalent_plan) : nlohmann::json(nullptr);
  j["verdict"] = d.verdict;
  return j;
}

} // namespace geartopo::diagnosis
