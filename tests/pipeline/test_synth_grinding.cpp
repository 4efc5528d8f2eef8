// `geartopo synth` grinding as the real machine would (docs/monte-carlo.md, "Gear 1 and gear 2 from the command line"):
// per-stroke scatter drawn from machine.repeatability, and the corrections of a compensate run rounded to
// machine.resolution. Truths: the synthesis without either option (the same machine), r_b cos β_b s_C for a C-only
// scatter (ISO 21771 geometry written here) with χ² bounds on its sample RMS, and the rounding bound Σ_a |g_a|
// over the axes from the first-order stroke sensitivities (diagnosis::stroke_sensitivity, another model) at half the
// resolution.
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/statistics.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sys/wait.h>
#include <unistd.h>

using namespace geartopo;

namespace {

// A small helical gear, 60 teeth (60 strokes: a sample of 60 scatter draws), `machine` as its machine section.
std::string synth_scene_text(int teeth, double module_mm, const std::string& machine) {
  return "gear:\n"
         "  normal_module_mm: " + std::to_string(module_mm) + "\n"
         "  teeth: " + std::to_string(teeth) + "\n"
         "  normal_pressure_angle_deg: 20\n"
         "  helix_angle_deg: 20\n"
         "  profile_shift: 0\n"
         "  face_width_mm: 20\n"
         "machine:\n"
         "  datum_face_z_mm: 300\n" + machine +
         "wheel: {outer_diameter_mm: 300}\n"
         "measurement: {rows: 3, cols: 3, profile_points: 15, helix_points: 15}\n";
}

const std::string kExactMachine =
    "  uncertainty: {linear_axis_um: 0, linear_axis_urad: 0, rotary_axis_um: 0, rotary_axis_urad: 0,\n"
    "                squareness_urad: 0, location_um: 0, location_urad: 0}\n";

struct SynthDir {
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("geartopo_synth_" + std::to_string(::getpid()));
  SynthDir() { std::filesystem::create_directories(dir); }
  ~SynthDir() { std::filesystem::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
  std::string read(const std::string& name) const {
    std::ifstream in(dir / name, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  /// Runs geartopo with `args`; stdout and stderr in log.txt.
  int run(const std::string& args) const {
    const int status = std::system((std::string(GEARTOPO_BINARY) + " " + args + " >" + (dir / "log.txt").string() + " 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

// Per (tooth, flank): the grid deviations of a topology CSV, µm.
std::map<std::pair<int, int>, std::vector<double>> synth_flanks(const std::string& file, int teeth) {
  std::map<std::pair<int, int>, std::vector<double>> out;
  for (const auto& r : grinding::read_topology_csv(file, teeth))
    out[{r.tooth, static_cast<int>(r.flank)}].push_back(r.deviation_um);
  return out;
}

} // namespace

// Zero repeatability: the scatter option grinds the very same gear (the same bytes).
TEST(SynthGrinding, ZeroRepeatabilityScatterChangesNothing) {
  const SynthDir d;
  const auto scene = d.write("scene.yaml", synth_scene_text(20, 4, kExactMachine +
      "  constants: {S_xz_urad: 30, E_XOC_um: 5}\n  repeatability: {x_um: 0, y_um: 0, z_um: 0, a_mdeg: 0, c_mdeg: 0}\n"));
  ASSERT_EQ(d.run("synth " + scene + " --out " + d.path("plain.csv") + " --teeth all"), 0) << d.read("log.txt");
  ASSERT_EQ(d.run("synth " + scene + " --out " + d.path("scatter.csv") + " --teeth all --stroke-scatter"), 0) << d.read("log.txt");
  EXPECT_NE(d.read("log.txt").find("stroke scatter"), std::string::npos) << d.read("log.txt");
  EXPECT_FALSE(d.read("plain.csv").empty());
  EXPECT_EQ(d.read("plain.csv"), d.read("scatter.csv"));
}

// C-only scatter, s_C = R/4 = 1 mdeg: each stroke turns its space by δC_s ~ N(0, s_C²), which moves both flanks it
// grinds uniformly by r_b cos β_b δC_s along the normal. Over the 60 strokes Σ δ²/σ² is χ²(60): its sample RMS lies
// within √(χ²_{0.9995}/60)..√(χ²_{0.0005}/60) of σ = r_b cos β_b s_C but for a 1-in-1000 draw.
TEST(SynthGrinding, StrokeScatterPerFlankRmsIsRbCosBetaBTimesTheCRepeatability) {
  const SynthDir d;
  const int z = 60;
  const double module = 2.0;
  const auto scene = d.write("scene.yaml", synth_scene_text(z, module, kExactMachine +
      "  repeatability: {x_um: 0, y_um: 0, z_um: 0, a_mdeg: 0, c_mdeg: 4}\n"));
  const std::string common = " --teeth all --noise-um 0 --seed 7";
  ASSERT_EQ(d.run("synth " + scene + " --out " + d.path("plain.csv") + common), 0) << d.read("log.txt");
  ASSERT_EQ(d.run("synth " + scene + " --out " + d.path("scatter.csv") + common + " --stroke-scatter"), 0) << d.read("log.txt");
  const double beta = 20.0 * units::kRadPerDeg, alpha_n = 20.0 * units::kRadPerDeg;
  const double rb = 0.5 * z * module / std::cos(beta) * std::cos(std::atan(std::tan(alpha_n) / std::cos(beta)));
  const double beta_b = std::asin(std::sin(beta) * std::cos(alpha_n));
  const double sigma_um = rb * std::cos(beta_b) * units::rad_from_deg(1e-3) * units::kUmPerMm;

  const auto plain = synth_flanks(d.path("plain.csv"), z), scatter = synth_flanks(d.path("scatter.csv"), z);
  ASSERT_EQ(plain.size(), static_cast<size_t>(2 * z));
  double sum_sq = 0.0;
  for (const auto& [flank, dev] : scatter) {
    const auto& base = plain.at(flank);
    ASSERT_EQ(base.size(), dev.size());
    const double shift = dev.front() - base.front();
    for (size_t i = 0; i < dev.size(); ++i) // a rigid turn: the same shift everywhere on the flank
      EXPECT_NEAR(dev[i] - base[i], shift, 1e-3 + 0.01 * sigma_um) << flank.first << " " << i;
    sum_sq += shift * shift;
  }
  const double rms = std::sqrt(sum_sq / static_cast<double>(scatter.size()));
  std::cout << "per-flank RMS " << rms << " µm, σ = r_b cos β_b s_C = " << sigma_um << " µm\n";
  EXPECT_GT(rms, sigma_um * std::sqrt(chi_squared_upper_quantile(0.9995, z) / z)) << "σ " << sigma_um;
  EXPECT_LT(rms, sigma_um * std::sqrt(chi_squared_upper_quantile(0.0005, z) / z)) << "σ " << sigma_um;
}

// Corrections of a compensate run on the same scene (no map uncertainty, no scatter): the gear ground with them, rounded
// to 1 µm / 1 mdeg, deviates at each point by at most the rounding's worst case Σ_a |g_a| (g_a the first-order
// deviation there for half a resolution step of axis a) plus what the nominal correction leaves — where without them
// it carries the whole map error.
TEST(SynthGrinding, CorrectionsOfTheSameSceneLeaveOnlyTheRounding) {
  const SynthDir d;
  const std::string machine = kExactMachine +
      "  constants: {S_xz_urad: 30, E_XOC_um: 5, delta_xx_um: 4, epsilon_zx_urad: 40, E_YOC_um: 6}\n"
      "  repeatability: {x_um: 0, y_um: 0, z_um: 0, a_mdeg: 0, c_mdeg: 0}\n"
      "  resolution: {x_um: 1, y_um: 1, z_um: 1, a_mdeg: 1, c_mdeg: 1}\n";
  const auto scene = d.write("scene.yaml", synth_scene_text(20, 4, machine));
  ASSERT_EQ(d.run("compensate " + scene + " --out " + d.path("comp") + " --samples 0 --step 2"), 0) << d.read("log.txt");
  const std::string common = " --teeth 1,2,11 --noise-um 0";
  ASSERT_EQ(d.run("synth " + scene + " --out " + d.path("plain.csv") + common), 0) << d.read("log.txt");
  ASSERT_EQ(d.run("synth " + scene + " --out " + d.path("gear2.csv") + common + " --corrections " +
                  d.path("comp/corrections.csv")), 0)
      << d.read("log.txt");

  const workbench::Workbench wb(scene::load_scene(scene));
  const auto rows = grinding::read_topology_csv(d.path("gear2.csv"), 20);
  const auto pts = measurement::measured_points(rows, wb.setup.geometry(), "gear2");
  const auto& res = wb.scene.machine.uncertainty.resolution;
  const Eigen::MatrixXd g = diagnosis::stroke_sensitivity(wb.setup, wb.process(), pts, 0.5 * res); // n × 5, µm
  double nominal_after = 0.0; // what the corrections leave on the model itself (compensate's topology_after.csv)
  for (const auto& r : grinding::read_topology_csv(d.path("comp/topology_after.csv"), 20))
    nominal_after = std::max(nominal_after, std::abs(r.deviation_um));
  double largest_bound = 0.0, largest_corrected = 0.0;
  for (size_t i = 0; i < rows.size(); ++i) {
    largest_corrected = std::max(largest_corrected, std::abs(rows[i].deviation_um));
    const double bound = g.row(static_cast<Eigen::Index>(i)).cwiseAbs().sum() + nominal_after + 0.005; // 0.005: file digits
    largest_bound = std::max(largest_bound, bound);
    EXPECT_LE(std::abs(rows[i].deviation_um), bound) << "tooth " << rows[i].tooth << " row " << rows[i].row;
  }
  double largest_plain = 0.0;
  for (const auto& r : grinding::read_topology_csv(d.path("plain.csv"), 20))
    largest_plain = std::max(largest_plain, std::abs(r.deviation_um));
  EXPECT_GT(largest_plain, 3.0 * largest_bound) << "the uncorrected gear must carry more than the rounding";
  std::cout << "largest |dev| uncorrected " << largest_plain << " µm, corrected " << largest_corrected
            << " µm; rounding bound up to " << largest_bound << " µm\n";
}

// Bad input: a missing corrections file (1), one of another gear (1), a broken row located at its line and column (1),
// an unknown format (2).
TEST(SynthGrinding, BadCorrectionsAndFlagsAreRefused) {
  const SynthDir d;
  const auto scene = d.write("scene.yaml", synth_scene_text(20, 4, kExactMachine));
  const auto other = d.write("other.yaml", synth_scene_text(21, 4, kExactMachine));
  ASSERT_EQ(d.run("compensate " + other + " --out " + d.path("comp") + " --samples 0 --step 10"), 0) << d.read("log.txt");
  const std::string out = " --out " + d.path("m.csv");
  EXPECT_EQ(d.run("synth " + scene + out + " --corrections " + d.path("none.csv")), 1);
  EXPECT_NE(d.read("log.txt").find("none.csv"), std::string::npos) << d.read("log.txt");
  EXPECT_EQ(d.run("synth " + scene + out + " --corrections " + d.path("comp/corrections.csv")), 1);
  EXPECT_NE(d.read("log.txt").find("the truth scene's gear has 20 teeth"), std::string::npos) << d.read("log.txt");
  std::string table = d.read("comp/corrections.csv");
  table.replace(table.find('\n') + 1, 1, "x"); // the first data row's space
  const auto broken = d.write("broken.csv", table);
  EXPECT_EQ(d.run("synth " + scene + out + " --corrections " + broken), 1);
  EXPECT_NE(d.read("log.txt").find("broken.csv:2:1: space: "), std::string::npos) << d.read("log.txt");
  EXPECT_EQ(d.run("synth " + scene + out + " --format gde"), 2);
  EXPECT_FALSE(std::filesystem::exists(d.path("m.csv")));
}

// evaluate --prediction: each measured quantity beside the predicted band, inside when low ≤ value ≤ high (the ends
// belong to the interval, JCGM 101 §7.7's [y_(r), y_(r+q)]); what the measurement cannot give (largest |deviation|
// without a grid) and classes are left out. The bands here are written by hand.
TEST(EvaluateAgainstPrediction, InsideOutsideAndWhatIsLeftOut) {
  pipeline::MonteCarloSummary p;
  p.samples = 40;
  p.names = {"F_alpha_um", "f_p_um", "largest_abs_um", "F_alpha_class"};
  p.before = {{1.0, 0.5, 9.0}, {2.0, 1.0, 3.0}, {5.0, 4.0, 6.0}, {3, 2, 4}};
  p.after = {{1.5, 1.0, 2.0}, {3.0, 1.0, 4.9}, {5.0, 4.0, 6.0}, {3, 2, 4}};
  pipeline::GearQuantities m;
  m.names = {"F_alpha_um", "F_alpha_class", "f_p_um", "largest_abs_um", "F_beta_um"};
  m.values = {2.0, 3.0, 5.0, 9.0, 1.0}; // F_beta: not predicted, left out
  const auto after = report::check_against_prediction(m, p, "after", false);
  ASSERT_EQ(after.size(), 2u); // F_α, f_p
  EXPECT_EQ(after[0].name, "F_alpha_um");
  EXPECT_TRUE(after[0].inside); // 2.0 at the high end
  EXPECT_EQ(after[1].name, "f_p_um");
  EXPECT_FALSE(after[1].inside); // 5.0 above 4.9
  const auto lines = report::prediction_check_lines(after, p, "after");
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_NE(lines[2].find("outside (above)"), std::string::npos) << lines[2];
  EXPECT_EQ(lines[3], "1 of 2 inside their 95 % intervals");
  const auto json = report::prediction_check_json(after, p, "after");
  EXPECT_EQ(json["outside"], 1);
  EXPECT_EQ(json["quantities"]["f_p_um"]["high"], 4.9);
  const auto before = report::check_against_prediction(m, p, "before", true);
  ASSERT_EQ(before.size(), 3u); // with largest |deviation|
  EXPECT_FALSE(before[1].inside); // f_p 5 > 3
  EXPECT_EQ(before[2].name, "largest_abs_um");
  EXPECT_FALSE(before[2].inside); // 9 > 6

  // prediction.json as compensate writes it is read back; a broken band is refused by name, and the command stops
  // before it writes anything.
  const SynthDir d;
  const auto file = d.write("prediction.json", report::prediction_json(p).dump(2));
  const auto back = report::read_prediction_json(file);
  EXPECT_EQ(back.samples, 40);
  ASSERT_EQ(back.names.size(), p.names.size());
  for (size_t i = 0; i < p.names.size(); ++i) {
    const int k = back.find(p.names[i]);
    ASSERT_GE(k, 0) << p.names[i];
    EXPECT_EQ(back.after[static_cast<size_t>(k)].high, p.after[i].high);
    EXPECT_EQ(back.before[static_cast<size_t>(k)].low, p.before[i].low);
  }
  auto j = report::prediction_json(p);
  j["quantities"]["f_p_um"]["after"]["low"] = 3.5;
  const auto broken = d.write("broken.json", j.dump());
  try {
    report::read_prediction_json(broken);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("quantities.f_p_um.after: low 3.5 ≤ median 3 ≤ high 4.9 does not hold"),
              std::string::npos) << e.what();
  }
  const auto scene = d.write("scene.yaml", synth_scene_text(20, 4, kExactMachine));
  ASSERT_EQ(d.run("synth " + scene + " --out " + d.path("t.csv") + " --format traces --teeth all"), 0) << d.read("log.txt");
  EXPECT_EQ(d.run("evaluate " + scene + " --traces " + d.path("t.csv") + " --out " + d.path("e") + " --prediction " + broken), 1);
  EXPECT_NE(d.read("log.txt").find("broken.json"), std::string::npos) << d.read("log.txt");
  EXPECT_FALSE(std::filesystem::exists(d.path("e")));
  EXPECT_EQ(d.run("evaluate " + scene + " --traces " + d.path("t.csv") + " --out " + d.path("e") + " --prediction " + file +
                  " --prediction-side middle"), 2);
}
