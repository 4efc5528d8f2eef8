// The loop closes (issue 44; docs/tutorial.md §5–6, docs/monte-carlo.md "Checking a prediction"): over drawn truths,
// gear 1 ground on the truth and measured → diagnose → the scene with what it found, written and read back as
// scene_with_effect.yaml → compensate and predict gear 2 → gear 2 ground on the truth with those corrections. Gear 2's
// ISO values must lie inside their predicted 95 % intervals (≥ 90 % of them over the loops that closed) and gear 2 must
// be better than gear 1 (≥ 90 % of the loops). The truths are written here from physics, outside what diagnose knows: the model's map off by a draw of
// its stated uncertainty per component, each stroke's axes off by a draw of the repeatability, and a hidden process
// change the model lacks — a thermal drift of X (library effect), the A axis' zero position creeping (machine
// element) or a workpiece warming while it is ground (the user's own effect, declared in the model's custom_effects;
// the truth is the physics written here as a law of C++, not the user's expression). Units: µm, s, µrad, K as the
// scene keys say.
#include "geartopo/pipeline/monte_carlo.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/identified_effects.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/effects/custom_effect.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/scene/scene.hpp"
#include "small_gear_scene.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <random>
#include <set>
#include <span>

using namespace geartopo;

namespace {

/// The nine ISO 1328-1 values of a gear the prediction gives intervals for.
const std::vector<std::string> kIsoValues{"F_alpha_um", "f_falpha_um", "f_Halpha_um", "F_beta_um", "f_fbeta_um",
                                          "f_Hbeta_um", "f_p_um",      "F_p_um",      "F_r_um"};

double value_of(const pipeline::GearQuantities& g, const std::string& name) {
  for (size_t i = 0; i < g.names.size(); ++i)
    if (g.names[i] == name) return g.values[i];
  ADD_FAILURE() << "no quantity " << name;
  return NAN;
}

/// What one truth's loop gave.
struct LoopOutcome {
  std::string chosen;    ///< what diagnose named (its effects or machine element and its class), "" when none written
  int inside = 0, total = 0;
  double largest1_um = 0.0, largest2_um = 0.0; ///< largest |deviation| of gear 1 and gear 2
  double fp1_um = 0.0, fp2_um = 0.0;           ///< F_p of gear 1 and gear 2
};

/// The machine as it is: the model's constant map, each component off by u·N(0, 1) (u its stated standard uncertainty),
/// as constants of a scene's machine section.
std::string drawn_map(const workbench::Workbench& model, std::mt19937_64& gen) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto& u = model.scene.machine.uncertainty;
  std::string out = "  constants: {";
  for (int k = 0; k < machine::kComponentCount; ++k) {
    const auto id = machine::component_at(k);
    const auto& info = machine::info(id);
    const bool length = info.quantity == machine::Quantity::Length;
    const double v = model.machine.source(id).value(0.0) + u.component_u[static_cast<size_t>(k)] * normal(gen);
    out += fmt::format("{}{}_{}: {}", k ? ", " : "", info.name, length ? "um" : "urad", (length ? 1e3 : 1e6) * v);
  }
  return out + "}\n";
}

/// One truth's loop. `hidden` is the scene text the truth has beyond the model (appended to it).
LoopOutcome close_the_loop(const std::string& model_text, const std::string& hidden, std::uint64_t seed) {
  const workbench::Workbench model(scene::parse_scene(model_text, "model.yaml"));
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const std::string truth_text = test::small_gear_scene_text(drawn_map(model, gen)) + hidden;
  const workbench::Workbench truth(scene::parse_scene(truth_text, "truth.yaml"));
  const auto& u = model.scene.machine.uncertainty;
  const auto with_repeatability = [&](const compensation::CorrectionTable& t) {
    std::set<int> spaces;
    for (const auto& r : t.rows()) spaces.insert(r.space);
    return pipeline::with_stroke_offsets(t, pipeline::draw_stroke_offsets(spaces, u.repeatability, [&] { return normal(gen); }));
  };
  std::vector<compensation::CorrectionRow> zero_rows = test::nominal_corrections(model).rows();
  for (auto& r : zero_rows) r.correction.setZero();
  // CompensatedProcess keeps a reference to its table: the tables live as long as the processes.
  const auto gear1_table = with_repeatability(compensation::CorrectionTable(zero_rows));
  const compensation::CompensatedProcess gear1_process(truth.process(), gear1_table);

  // Gear 1 measured on ten teeth, 5 × 5 grids, probe noise 0.3 µm; diagnosed with the scatter and map uncertainty the
  // scene declares (generalised least squares, docs/diagnosis.md).
  diagnosis::SynthOptions so;
  so.teeth = {1, 3, 5, 7, 9, 11, 13, 15, 17, 19};
  so.rows = 5;
  so.cols = 5;
  so.noise_um = 0.3;
  so.seed = seed;
  const auto points = measurement::measured_points(diagnosis::synthesize(truth.setup, gear1_process, so),
                                                   model.setup.geometry(), "gear1.csv");
  diagnosis::DiagnoseOptions dopt;
  dopt.noise_um = so.noise_um;
  dopt.stroke_repeatability_sd = u.repeatability;
  dopt.model_uncertainty_um = diagnosis::map_sensitivity(model, points);
  dopt.own_effects = model.scene.custom_effects; // as geartopo diagnose does (commands/measured.cpp)
  const auto d = diagnosis::diagnose(model.setup, model.diagnosis_model(), points, model.effect_types(), dopt);

  LoopOutcome out;
  const auto& g = truth.setup.geometry();
  const auto topo1 = grinding::simulate_topology(truth.setup, gear1_process, test::grid_of(truth));
  const auto gear1 = pipeline::gear_quantities(workbench::evaluate_iso(g, truth.setup.ranges(), topo1), topo1);
  out.largest1_um = value_of(gear1, "largest_abs_um");
  out.fp1_um = value_of(gear1, "F_p_um");
  if (!d.chosen || d.withheld) {
    std::cout << "seed " << seed << ": no scene written: " << d.verdict << "\n";
    out.total = static_cast<int>(kIsoValues.size());
    return out;
  }
  out.chosen = d.chosen->name();
  for (const auto& e : d.chosen->equivalent) out.chosen += " | " + e; // a machine element's class (one field)

  // scene_with_effect.yaml as diagnose writes it (values, the fit's σ and correlation, or the posterior's value sets;
  // machine elements with their σ), read back by the scene reader.
  const auto found = diagnosis::identified_effects(d, *d.chosen);
  const std::string completed = diagnosis::scene_text_with_effects(
      model_text, ".", ".", found.effects, diagnosis::identification_comments(*d.chosen, "gear1.csv"), found.uncertainties,
      found.correlation, d.chosen->changes, d.chosen->change_sd,
      diagnosis::change_identification_comments(*d.chosen, "gear1.csv"), found.draws);
  const workbench::Workbench wb(scene::parse_scene(completed, "scene_with_effect.yaml"));
  const auto table = test::nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 100;
  o.seed = seed;
  o.threads = 1;
  const auto predicted = pipeline::summarise(pipeline::run_monte_carlo(wb, table, o));

  // Gear 2: the truth ground with the corrections as the controller takes them, its own stroke scatter.
  const auto gear2_table = with_repeatability(pipeline::rounded_to_resolution(table, wb.scene.machine.uncertainty.resolution));
  const compensation::CompensatedProcess gear2_process(truth.process(), gear2_table);
  const auto topo2 = grinding::simulate_topology(truth.setup, gear2_process, test::grid_of(truth));
  const auto gear2 = pipeline::gear_quantities(workbench::evaluate_iso(g, truth.setup.ranges(), topo2), topo2);
  out.largest2_um = value_of(gear2, "largest_abs_um");
  out.fp2_um = value_of(gear2, "F_p_um");
  std::string line = fmt::format("seed {}: {}; gear 1 largest {:.2f} F_p {:.2f}, gear 2 largest {:.2f} F_p {:.2f} µm;",
                                 seed, out.chosen, out.largest1_um, out.fp1_um, out.largest2_um, out.fp2_um);
  for (const auto& name : kIsoValues) {
    const int i = predicted.find(name);
    if (i < 0) {
      ADD_FAILURE() << "no prediction of " << name;
      continue;
    }
    const auto& band = predicted.after[static_cast<size_t>(i)];
    const double v = value_of(gear2, name);
    const bool in = v >= band.low && v <= band.high;
    out.inside += in ? 1 : 0;
    ++out.total;
    if (!in) line += fmt::format(" {} {:.2f} outside [{:.2f}, {:.2f}]", name, v, band.low, band.high);
  }
  std::cout << line << "\n";
  return out;
}

/// Runs the loop over `truths` truths, `hidden(gen)` drawing each one's hidden change, and checks the outcome. A loop
/// closes when diagnose writes a scene (an ambiguous verdict writes none: it asks for more teeth first); at least 90 % of
/// the loops must close, name one of `expected_names` (the hidden physics or an element that leaves the same field),
/// hold ≥ 90 % of their gear 2's ISO values inside the predicted 95 % intervals, and give a gear 2 with a smaller largest
/// |deviation| than gear 1's.
/// `declared`: what the model's scene adds to the small gear and its map (the user's custom_effects, or nothing).
void expect_the_loop_closes(int truths, const std::function<std::string(std::mt19937_64&)>& hidden,
                            const std::vector<std::string>& expected_names, const std::string& declared = "") {
  const std::string model_text = test::small_gear_scene_text(test::kSmallGearMapErrors) + declared;
  std::mt19937_64 truth_gen(44);
  int inside = 0, total = 0, closed = 0, named = 0, better = 0;
  for (int t = 0; t < truths; ++t) {
    const auto o = close_the_loop(model_text, hidden(truth_gen), 1000 + static_cast<std::uint64_t>(t));
    if (o.chosen.empty()) continue;
    ++closed;
    inside += o.inside;
    total += o.total;
    for (const auto& n : expected_names)
      if (o.chosen.find(n) != std::string::npos) {
        ++named;
        break;
      }
    better += o.largest2_um < o.largest1_um ? 1 : 0;
  }
  std::cout << expected_names.front() << ": " << closed << " of " << truths << " loops closed; " << inside << " of "
            << total << " ISO values inside their 95 % intervals; named in " << named << "; gear 2 better in " << better
            << "\n";
  EXPECT_GE(closed, 0.9 * truths) << "diagnose wrote too few scenes";
  EXPECT_GE(inside, 0.9 * total) << "the predicted 95 % intervals hold for too few values";
  EXPECT_GE(named, 0.9 * closed) << "the hidden change was not found";
  EXPECT_GE(better, 0.9 * closed) << "gear 2 not better than gear 1 (largest |deviation|)";
}

} // namespace

// The model's own small gear and map (m_n 4 mm, z 20; constant map errors of a few µm and tens of µrad, the default
// uncertainties, repeatability R↑ 3 µm / 1 mdeg, resolution 1 µm / 1 mdeg). Hidden: X grows by x_∞ ~ U[15, 35] µm
// towards its steady state with τ ~ log-U[60, 300] s while the gear (≈ 5 min) is ground — a spindle head warming up.
TEST(ClosedLoop, AThermalDriftFoundOnGear1MakesGear2BetterAndPredicted) {
  expect_the_loop_closes(
      20,
      [](std::mt19937_64& gen) {
        std::uniform_real_distribution<double> x(15.0, 35.0), log_tau(std::log(60.0), std::log(300.0));
        const double x_um = x(gen), tau_s = std::exp(log_tau(gen));
        return fmt::format("effects:\n  - {{type: thermal_drift, x_growth_um: {:.3f}, time_constant_s: {:.1f}}}\n", x_um, tau_s);
      },
      // X drifting linearly or towards a steady state is the same field as a thermal X growth (docs/diagnosis.md,
      // "Beyond the library"): the library's name or the X axis' own.
      {"thermal_drift", "delta_xx", "E_XOC"});
}

namespace {

/// A steel workpiece warmed by the grinding: its temperature rises towards ΔT∞ with the time constant τ of its heat
/// balance, ΔT(t) = ΔT∞ (1 − e^(−t/τ)), and it grows isotropically by α ΔT(t) per unit length (α = 11.5·10⁻⁶ /K,
/// steel) about where it is held: the axis at the datum face, the gear frame's origin (z from the datum face). The
/// wheel grinds the warm flank to the nominal; cooled, the material ground at t has moved by −α ΔT(t) (x, y, z) — that displacement
/// on the outward flank normal is the deviation (µm, plus material). Registered once, as a function law (the way
/// Python's geartopo.custom_effect registers one) under a name the model never sees; the truth's scene lists it with
/// its values (warming_truth_entry).
const char* warming_physics_law() {
  static const char* name = [] {
    constexpr double kAlphaPerK = 11.5e-6;
    auto fn = std::make_shared<const effects::BatchLaw>(
        [](const std::vector<double>& v, std::span<const effects::ContactVariables> at, std::span<double> out) {
          const double dT_inf_K = v[0], tau_s = v[1];
          for (size_t i = 0; i < at.size(); ++i) {
            const auto& c = at[i];
            const double dT_K = dT_inf_K * (1.0 - std::exp(-c.t_s / tau_s));
            const Eigen::Vector3d displacement_um = -1e3 * kAlphaPerK * dT_K * Eigen::Vector3d(c.x_mm, c.y_mm, c.z_mm);
            out[i] = displacement_um.dot(Eigen::Vector3d(c.nx, c.ny, c.nz));
          }
        });
    effects::register_custom_law(std::make_shared<const effects::CustomLaw>(
        "closed_loop_warming_truth",
        std::vector<effects::CustomParameter>{{"dT_inf_K", 0.0, 0.0, 100.0, "K"}, {"tau_s", 100.0, 1.0, 1e5, "s"}}, fn,
        "test_closed_loop.warming_physics"));
    return "closed_loop_warming_truth";
  }();
  return name;
}

/// The truth's custom_effects entry of the warming (the law registered by warming_physics_law).
std::string warming_truth_entry(double dT_inf_K, double tau_s) {
  return fmt::format("custom_effects:\n  - name: {}\n    parameters:\n"
                     "      dT_inf_K: {{value: {:.3f}, min: 0, max: 100, unit: K}}\n"
                     "      tau_s: {{value: {:.1f}, min: 1, max: 100000, unit: s}}\n"
                     "    python: test_closed_loop.warming_physics\n",
                     warming_physics_law(), dT_inf_K, tau_s);
}

} // namespace

// The user's own effect (issue 40 through issue 44's loop): the model's scene declares a warming workpiece as the
// user would write it — a shrink k·(x, y, z) growing as 1 − e^(−t/τ), on the normal — at k = 0 (told the law, not its
// values); the truth's workpiece warms by ΔT∞ ~ U[10, 25] K with τ ~ log-U[60, 300] s while the gear (≈ 3 min) is
// ground: k = α ΔT∞ = 0.12 … 0.29 µm per mm, 1.4 … 3.5 µm radially at the pitch circle (r 42.6 mm) and 1.7 … 4.3 µm
// axially across the 30 mm face. (Radially alone it is what a thermal X growth does, to a profile slope of ±6 %: on
// these ten teeth diagnose then rightly finds the two ambiguous and writes no scene.) Diagnose must name the user's
// law and scene_with_effect.yaml write it back into the user's entry; gear 2 must be predicted and better.
TEST(ClosedLoop, AUsersOwnWarmingFoundOnGear1MakesGear2BetterAndPredicted) {
  const std::string declared = R"yaml(custom_effects:
  - name: workpiece_warming
    parameters:
      shrink_um_per_mm: {value: 0.0, min: -1, max: 1, unit: um_per_mm}
      tau_s: {value: 300, min: 30, max: 20000, unit: s}
    deviation_um: "-shrink_um_per_mm * (x_mm*nx + y_mm*ny + z_mm*nz) * (1 - exp(-t_s / tau_s))"
)yaml";
  expect_the_loop_closes(
      20,
      [](std::mt19937_64& gen) {
        std::uniform_real_distribution<double> dT(10.0, 25.0), log_tau(std::log(60.0), std::log(300.0));
        const double dT_K = dT(gen), tau_s = std::exp(log_tau(gen));
        return warming_truth_entry(dT_K, tau_s);
      },
      {"workpiece_warming"}, declared);
}

// Hidden: the A axis' zero position E_AOA creeping linearly in time by r ~ U[20, 40] µrad/min (the swivel head's
// clamping; ≈ 60 … 120 µrad over the 3-min gear) — no library effect, a machine element. With the map's uncertainty
// in the covariance the drift hid, in 10 of 20 truths, in the χ² of what the library leaves (511 … 605 against the
// limit 608 on 498 degrees of freedom) while its own fit reached ΔBIC −18 … −53 in 9 of them (−8.4 in the tenth):
// the families are now tried whenever the library names
// nothing, or nothing for certain (docs/diagnosis.md, "Beyond the library"). The element is named in its class
// (E_AOA, ε_xa, ε_xy, ε_xz drifting all turn the head about x; a wheel profile wearing in slope and crowning per stroke
// leaves the same field on these ten teeth). Measured 2026-11-27: 18 of 20 loops closed (17 name the class, one
// thermal_drift), 146 of 162 ISO values inside, gear 2 better in all 18; 42–47 s beside another test on the 2 shared
// cores (ctest label closed_loop).
TEST(ClosedLoop, AnAAxisDriftFoundOnGear1MakesGear2BetterAndPredicted) {
  expect_the_loop_closes(
      20,
      [](std::mt19937_64& gen) {
        std::uniform_real_distribution<double> rate(20.0, 40.0);
        return fmt::format("machine_changes:\n  - {{component: E_AOA, law: linear_in_time, rate_urad_per_min: {:.2f}}}\n",
                           rate(gen));
      },
      {"E_AOA", "epsilon_xa"}); // both turn the head about the same line (docs/diagnosis.md)
}
