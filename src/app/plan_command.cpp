// geartopo plan: what to measure next when the measurement cannot tell two explanations apart (docs/diagnosis.md,
// "Ambiguity and what to measure next"). Runs the diagnosis and prints/writes its measurement plan.
#include "app/commands.hpp"
#include "app/options.hpp"
#include "app/plan_json.hpp"

#include "geartopo/core/atomic_file.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/klingelnberg.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace geartopo::app {

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

nlohmann::json candidate_json(const diagnosis::Candidate& c) {
  nlohmann::json j;
  j["effect"] = c.name();
  nlohmann::json params = nlohmann::json::object();
  for (size_t e = 0; e < c.effects.size(); ++e)
    for (const auto& p : c.parameters[e]) {
      const std::string key = c.effects.size() > 1 ? c.effects[e].type + "." + p.key : p.key;
      params[key] = {{"value", p.value},
                     {"uncertainty", p.fitted ? nlohmann::json(p.uncertainty) : nlohmann::json(nullptr)},
                     {"unit", unit_of_key(p.key)},
                     {"fitted", p.fitted}};
    }
  j["parameters"] = params;
  j["explained_fraction"] = c.explained_fraction;
  j["rejected"] = c.rejected.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.rejected);
  j["rms_before_um"] = c.rms_before_um;
  j["rms_after_um"] = c.rms_after_um;
  j["delta_bic"] = c.delta_bic;
  j["significant"] = c.significant;
  j["explanation"] = c.explanations;
  return j;
}

nlohmann::json measurement_plan_json(const diagnosis::MeasurementPlan& plan) {
  nlohmann::json teeth = nlohmann::json::array();
  for (const auto& t : plan.teeth)
    teeth.push_back({{"tooth", t.tooth},
                     {"separation_sigma", t.separation_sigma},
                     {"max_difference_um", t.max_difference_um},
                     {"at", {{"flank", t.flank == Flank::Left ? "left" : "right"}, {"row", t.row}, {"col", t.col}}}});
  return {{"between", {plan.first, plan.second}},
          {"delta_bic_gap", plan.delta_bic_gap},
          {"noise_um", plan.noise_um},
          {"grid", {{"rows", plan.rows}, {"cols", plan.cols}}},
          {"recommended_teeth", plan.recommended_teeth},
          {"recommended_separation_sigma", plan.recommended_separation_sigma},
          {"row_separation_sigma", plan.row_separation_sigma},
          {"col_separation_sigma", plan.col_separation_sigma},
          {"teeth", teeth}};
}

void register_plan_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, measured, out;
    double noise = 0.0;
    diagnosis::KlingelnbergOptions mka;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("plan", "What to measure next: when explanations of the residual are within the "
                                             "ΔBIC threshold of each other, the teeth that tell them apart");
  cmd->add_option("SCENE", opt->scene, "Model scene (YAML)")->required();
  cmd->add_option("--measured", opt->measured, "Measurement: topology CSV (µm), point cloud or Klingelnberg export")
      ->required();
  cmd->add_option("--out", opt->out, "Output directory: plan.json (default: print only)")->check(non_empty_path());
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ in µm (default: estimated from the residual)")
      ->check(finite_in(0.0, 1000.0));
  add_klingelnberg_options(cmd, opt->mka);
  cmd->callback([&action, opt] {
    action = [opt] {
      const workbench::Workbench wb(opt->scene);
      std::vector<std::string> warnings;
      const auto pts = diagnosis::read_any_measurement(opt->measured, wb.setup, &warnings, opt->mka);
      for (const auto& w : warnings) std::cerr << "geartopo: warning: " << w << "\n";
      diagnosis::DiagnoseOptions o;
      o.noise_um = opt->noise;
      const auto d = diagnosis::diagnose(wb.setup, wb.process(), pts, wb.effect_types(), o);
      nlohmann::json j;
      j["scene"] = opt->scene;
      j["measured"] = opt->measured;
      j["chosen"] = d.chosen ? nlohmann::json(d.chosen->name()) : nlohmann::json(nullptr);
      j["ambiguous"] = !d.rivals.empty();
      j["plan"] = d.plan ? measurement_plan_json(*d.plan) : nlohmann::json(nullptr);
      j["verdict"] = d.verdict;
      if (!d.plan) {
        std::cout << (d.chosen ? fmt::format("Not ambiguous: {} is ahead of every other explanation by more than the "
                                             "ΔBIC threshold; nothing more to measure to decide.\n",
                                             d.chosen->name())
                               : std::string("No effect of the library is significant: nothing to decide between.\n"));
      } else {
        const auto& p = *d.plan;
        std::cout << fmt::format("Ambiguous between {} and {} (ΔBIC gap {:.1f}).\n", p.first, p.second, p.delta_bic_gap);
        std::cout << fmt::format("Measure teeth {} (together {:.1f}σ apart at {:.2f} µm noise, {}×{} grid per flank).\n",
                                 fmt::join(p.recommended_teeth, ","), p.recommended_separation_sigma, p.noise_um,
                                 p.rows, p.cols);
        std::cout << fmt::format("  {:>5} {:>10} {:>12}  {}\n", "tooth", "sep (σ)", "max |Δ| µm", "where");
        for (const auto& t : p.teeth)
          std::cout << fmt::format("  {:>5} {:>10.2f} {:>12.3f}  {} flank, row {}, column {}\n", t.tooth,
                                   t.separation_sigma, t.max_difference_um, t.flank == Flank::Left ? "left" : "right",
                                   t.row, t.col);
      }
      if (!opt->out.empty()) {
        const std::filesystem::path out(opt->out);
        std::filesystem::create_directories(out);
        output::write_text_atomically(out / "plan.json", j.dump(2) + "\n");
        std::cout << "wrote " << (out / "plan.json").string() << "\n";
      }
      return 0;
    };
  });
}

} // namespace geartopo::app
