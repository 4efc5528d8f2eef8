// The geartopo program as a user runs it: outputs, exit codes (0 ok, 1 bad input, 2 bad usage), messages.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace {

struct CliResult {
  int code;
  std::string out, err;
};

CliResult run(const std::string& args) {
  const auto dir = std::filesystem::temp_directory_path();
  // Unique per process and call: ctest runs tests in parallel processes.
  static int calls = 0;
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(calls++);
  const auto out = dir / ("geartopo_cli_out_" + tag), err = dir / ("geartopo_cli_err_" + tag);
  const std::string cmd = std::string(GEARTOPO_BINARY) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  CliResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

const std::string kScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

} // namespace

TEST(Cli, GearJsonHasTheDocumentedKeys) {
  const CliResult r = run("gear " + kScene + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"d_mm", "db_mm", "da_mm", "df_mm", "alpha_t_deg", "beta_b_deg", "lead_mm", "pbt_mm", "sn_mm",
                          "k", "Wk_mm", "Wk_upper_mm", "Wk_lower_mm", "A_sne_um", "A_sni_um", "D_M_mm", "MdK_mm",
                          "MdK_upper_mm", "MdK_lower_mm"})
    EXPECT_TRUE(j.contains(key)) << key;
  // The default scene gives no allowance: the band collapses onto the nominal values.
  EXPECT_EQ(j["Wk_upper_mm"].get<double>(), j["Wk_mm"].get<double>());
  EXPECT_EQ(j["MdK_lower_mm"].get<double>(), j["MdK_mm"].get<double>());
  EXPECT_NEAR(j["d_mm"].get<double>(), 565.8033, 1e-4);
  EXPECT_NEAR(j["alpha_t_deg"].get<double>(), 22.7959, 1e-4);
  EXPECT_EQ(j["hand"], "right");
  EXPECT_GT(j["lead_mm"].get<double>(), 0.0);
}

TEST(Cli, GearTableMarksAssumedValues) {
  const CliResult r = run("gear " + kScene);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("face width"), std::string::npos);
  EXPECT_NE(r.out.find("assumed"), std::string::npos);
  EXPECT_NE(r.out.find("W_k"), std::string::npos);
  EXPECT_NE(r.out.find("M_dK"), std::string::npos);
  EXPECT_NE(r.out.find("D_M"), std::string::npos);
}

TEST(Cli, GearMeshIsWritten) {
  const auto mesh = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_cli_gear.off");
  std::filesystem::remove(mesh);
  const CliResult r = run("gear " + kScene + " --json --mesh " + mesh.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::file_size(mesh) > 1000);
  EXPECT_TRUE(nlohmann::json::accept(r.out)); // stdout stays one JSON object
  std::filesystem::remove(mesh);
}

TEST(Cli, BadInputExitsOneWithALocatedMessage) {
  const auto bad = write_temp("geartopo_bad.yaml", "gear:\n  normal_module_mm: 14\n  teeth: 35\n"
                                                   "  normal_pressure_angle_deg: 20\n  helix_angle_deg: 95\n"
                                                   "  profile_shift: 0\n  face_width_mm: 10\n");
  const CliResult r = run("gear " + bad.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(bad.string() + ":5:20: gear.helix_angle_deg: 95 is outside [-45, 45]"), std::string::npos)
      << r.err;
  EXPECT_EQ(run("gear /nonexistent.yaml").code, 1);
  std::filesystem::remove(bad);
}

TEST(Cli, BadUsageExitsTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("gear").code, 2);
  EXPECT_EQ(run("gear " + kScene + " --bogus").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("gear " + kScene + " --mesh /tmp/x.xyz").code, 2);
}

TEST(Cli, HelpExitsZeroForEverySubcommand) {
  const CliResult top = run("--help");
  EXPECT_EQ(top.code, 0);
  EXPECT_NE(top.out.find("gear"), std::string::npos);
  const CliResult gear = run("gear --help");
  EXPECT_EQ(gear.code, 0);
  EXPECT_NE(gear.out.find("--mesh"), std::string::npos);
}

TEST(Cli, SimulateWritesTopologyTracesAndMeshes) {
  const auto out = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_sim");
  const CliResult r = run("simulate " + kScene + " --out " + out.string() + " --teeth 1,18 --method linear --dense 5x6");
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream topo(out / "topology.csv");
  std::string header;
  std::getline(topo, header);
  EXPECT_EQ(header, "tooth,flank,row,col,diameter_mm,z_mm,deviation_um,design_um");
  int lines = 0;
  for (std::string l; std::getline(topo, l);) ++lines;
  EXPECT_EQ(lines, 4 * 63);
  EXPECT_TRUE(std::filesystem::exists(out / "traces.csv"));
  EXPECT_TRUE(std::filesystem::exists(out / "dense.csv"));
  EXPECT_TRUE(std::filesystem::exists(out / "meshes" / "tooth18_right.ply"));
  EXPECT_NE(r.out.find("all flanks:"), std::string::npos);
  std::filesystem::remove_all(out);
  EXPECT_EQ(run("simulate " + kScene + " --out " + out.string() + " --teeth 0").code, 2);
  EXPECT_EQ(run("simulate " + kScene + " --out " + out.string() + " --dense 5").code, 2);
  EXPECT_EQ(run("simulate " + kScene + " --out " + out.string() + " --method fast").code, 2);
  std::filesystem::remove_all(out);
}

// Issue 17/18: re-running into a folder leaves nothing of the earlier run that this run did not write (a stale
// dense.csv or mesh would be mistaken for this run's); the user's own files stay. --quiet is taken after the subcommand.
TEST(Cli, ARerunRemovesWhatOnlyTheEarlierRunWrote) {
  namespace fs = std::filesystem;
  const auto out = fs::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_rerun");
  fs::remove_all(out);
  ASSERT_EQ(run("simulate " + kScene + " --out " + out.string() + " --teeth 1,18 --method linear --dense 5x6").code, 0);
  ASSERT_TRUE(fs::exists(out / "dense.csv"));
  ASSERT_TRUE(fs::exists(out / "meshes" / "tooth18_left.ply"));
  std::ofstream(out / "my_notes.txt") << "mine\n";
  const CliResult again = run("simulate " + kScene + " --out " + out.string() + " --teeth 1 --method linear");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_FALSE(fs::exists(out / "dense.csv"));
  EXPECT_FALSE(fs::exists(out / "meshes" / "tooth18_left.ply"));
  EXPECT_TRUE(fs::exists(out / "meshes" / "tooth01_left.ply"));
  EXPECT_TRUE(fs::exists(out / "my_notes.txt"));
  EXPECT_NE(again.err.find("dense.csv"), std::string::npos) << again.err; // said, not silent
  const CliResult quiet = run("simulate " + kScene + " --out " + out.string() + " --teeth 18 --method linear --quiet");
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_TRUE(quiet.err.empty()) << quiet.err;
  EXPECT_FALSE(fs::exists(out / "meshes" / "tooth01_left.ply"));
  fs::remove_all(out);
}

// Issue 17: an ordinary small gear (m_n 1, β 30°) with no wheel given gets a wheel that fits, said in a note; given
// a 350 mm wheel it is refused with the diameter that would work; an internal gear is refused as such.
TEST(Cli, SmallGearsGetAWheelThatFitsAndInternalGearsAreNamed) {
  const std::string gear = "gear:\n  normal_module_mm: 1\n  teeth: 30\n  normal_pressure_angle_deg: 20\n"
                           "  helix_angle_deg: 30\n  face_width_mm: 10\n  profile_shift: 0\n";
  const auto out = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_small");
  const auto no_wheel = write_temp("small.yaml", gear);
  const CliResult chosen = run("simulate " + no_wheel.string() + " --out " + out.string() + " --teeth 1 --method linear");
  ASSERT_EQ(chosen.code, 0) << chosen.err;
  EXPECT_NE(chosen.err.find("note: wheel.outer_diameter_mm is not given"), std::string::npos) << chosen.err;
  const auto big = write_temp("small350.yaml", gear + "wheel:\n  outer_diameter_mm: 350\n");
  const CliResult refused = run("simulate " + big.string() + " --out " + out.string() + " --teeth 1 --method linear");
  EXPECT_EQ(refused.code, 1);
  EXPECT_NE(refused.err.find("wheel.outer_diameter_mm: 350 mm does not fit this gear"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("mm wheel does"), std::string::npos) << refused.err;
  std::string internal_text = gear;
  internal_text.replace(internal_text.find("teeth: 30"), 9, "teeth: -35");
  const auto internal = write_temp("internal.yaml", internal_text);
  const CliResult inner = run("gear " + internal.string());
  EXPECT_EQ(inner.code, 1);
  EXPECT_NE(inner.err.find("internal gear"), std::string::npos) << inner.err;
  for (const auto& p : {no_wheel, big, internal}) std::filesystem::remove(p);
  std::filesystem::remove_all(out);
}

// Issue 17: synth's --out may be a folder like every other --out (measured.csv inside), or a file as before.
TEST(Cli, SynthWritesIntoAFolderOrAFile) {
  namespace fs = std::filesystem;
  const auto dir = fs::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_synth_dir");
  fs::remove_all(dir);
  const CliResult to_folder = run("synth " + kScene + " --teeth 1 --out " + dir.string() + "/");
  ASSERT_EQ(to_folder.code, 0) << to_folder.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "measured.csv"));
  const CliResult to_file = run("synth " + kScene + " --teeth 1 --out " + (dir / "m.csv").string());
  ASSERT_EQ(to_file.code, 0) << to_file.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "m.csv"));
  fs::remove_all(dir);
}

// Issue 17: --json prints one JSON object on stdout (what the command's main file holds) and nothing else there.
TEST(Cli, JsonSummariesAreOneObjectOnStdout) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_json");
  const std::string measured = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/demo/measured.csv";
  const CliResult cmp = run("compare " + kScene + " --measured " + measured + " --out " + dir.string() + " --json");
  ASSERT_EQ(cmp.code, 0) << cmp.err;
  const auto jc = nlohmann::json::parse(cmp.out); // throws (test fails) on any text beside the object
  std::ifstream file(dir / "compare.json");
  EXPECT_EQ(jc, nlohmann::json::parse(file));
  EXPECT_EQ(jc["overall"]["points"].get<int>(), 252);
  const CliResult comp = run("compensate " + kScene + " --out " + dir.string() + " --samples 2 --json");
  ASSERT_EQ(comp.code, 0) << comp.err;
  const auto jm = nlohmann::json::parse(comp.out);
  EXPECT_TRUE(jm.contains("before") && jm.contains("nominal_after") && jm.contains("prediction") && jm.contains("improvement") &&
              jm.contains("warnings"));
  std::filesystem::remove_all(dir);
}

// Issue 17: run takes the options of the commands it combines, and writes what compare and diagnose write (the
// README says "all of the below"); a subset of teeth gives a report without the pitch figure, not an error.
TEST(Cli, RunOnSomeTeethWritesTheMeasurementFilesAndAReport) {
  namespace fs = std::filesystem;
  const auto dir = fs::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_run_teeth");
  const CliResult r = run("run " + kScene + " --out " + dir.string() + " --teeth 1 --simulation linear --samples 0 --method cycle --step 5");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"compare.json", "residuals.csv", "diagnosis.json", "iso1328.json", "index.html", "topology_before.csv"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_FALSE(fs::exists(dir / "pitch.png"));
  std::ifstream res(dir / "residuals.csv");
  std::string header;
  std::getline(res, header);
  EXPECT_EQ(header, "tooth,flank,row,col,diameter_mm,z_mm,measured_um,model_um,residual_um,source_line,point_id,design_um");
  std::ifstream topo(dir / "topology_before.csv");
  int rows = 0;
  for (std::string l; std::getline(topo, l);) ++rows;
  EXPECT_EQ(rows, 1 + 2 * 63); // header + tooth 1's two 7×9 grids
  EXPECT_EQ(run("run " + kScene + " --out " + dir.string() + " --method fast").code, 2);
  fs::remove_all(dir);
}

TEST(Cli, MachineReportsPoseTwistsAndJacobian) {
  const CliResult r = run("machine " + kScene + " --pose 444,0,350,-30,90 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["ideal"].size(), 4u);
  EXPECT_EQ(j["ideal"][0].size(), 4u);
  EXPECT_EQ(j["twist_exact"].size(), 6u);
  EXPECT_EQ(j["twist_linear"].size(), 6u);
  EXPECT_EQ(j["jacobian"].size(), 6u);
  EXPECT_EQ(j["jacobian"][0].size(), 5u);
  // Eq. 11 at γ = 90°: the first row is (cos γ, cos α sin γ, −sin α sin γ, y cos α sin γ + x cos γ).
  EXPECT_NEAR(j["ideal"][0][1].get<double>(), std::cos(-30 * M_PI / 180), 1e-12);
  EXPECT_NEAR(j["ideal"][0][3].get<double>(), 0.0, 1e-9);
  // Exact and first-order twists agree to a small fraction of their size for µm-size errors.
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(j["twist_exact"][i].get<double>(), j["twist_linear"][i].get<double>(), 0.01);
  EXPECT_EQ(run("machine " + kScene + " --pose 1,2,3").code, 2);
}

TEST(Cli, EvaluateWritesIsoJsonAndMeasuredTracesGiveTheSameAnswer) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_eval");
  const CliResult sim = run("evaluate " + kScene + " --out " + (dir / "sim").string() + " --method linear");
  ASSERT_EQ(sim.code, 0) << sim.err;
  std::ifstream in(dir / "sim" / "iso1328.json");
  const auto j = nlohmann::json::parse(in)["before"];
  ASSERT_EQ(j["flanks"].size(), 70u);
  // Per flank the individual pitch deviations f_pi, F_pi and the ball's radial position (issue 17: "F_p_um"/"F_r_um"
  // held per-tooth values, and F_r_um could be negative); the gear's f_p, F_p, F_r are under "gear".
  for (const char* key : {"F_alpha_um", "f_falpha_um", "f_Halpha_um", "F_beta_um", "f_fbeta_um", "f_Hbeta_um", "f_pi_um",
                          "F_pi_um", "radial_position_um", "classes"})
    EXPECT_TRUE(j["flanks"][0].contains(key)) << key;
  // Class-5 tolerances of the default gear (d = 565.80, m_n = 14, b = 150), from the ISO formulas by hand:
  // f_pT = 0.001 d + 0.4 m_n + 5 = 11.17 → 11; F_pT = 0.002 d + 0.55 √d + 0.7 m_n + 12 = 1.13 + 13.08 + 9.8 + 12
  // = 36.01 → 36.
  EXPECT_DOUBLE_EQ(j["tolerances_class5_um"]["f_pT_um"].get<double>(), 11.0);
  EXPECT_DOUBLE_EQ(j["tolerances_class5_um"]["F_pT_um"].get<double>(), 36.0);
  EXPECT_FALSE(j["classification"]["overall"].is_null());

  // Evaluate the simulation's own traces as if measured: the same numbers come back.
  ASSERT_EQ(run("simulate " + kScene + " --out " + (dir / "s").string() + " --method linear").code, 0);
  const CliResult meas = run("evaluate " + kScene + " --out " + (dir / "m").string() + " --traces " + (dir / "s" / "traces.csv").string());
  ASSERT_EQ(meas.code, 0) << meas.err;
  std::ifstream in2(dir / "m" / "iso1328.json");
  const auto jm = nlohmann::json::parse(in2)["before"];
  ASSERT_EQ(jm["flanks"].size(), 70u);
  for (size_t i = 0; i < 70; ++i)
    for (const char* key : {"F_alpha_um", "f_Hbeta_um", "f_pi_um"})
      EXPECT_NEAR(jm["flanks"][i][key].get<double>(), j["flanks"][i][key].get<double>(), 1e-3) << i << key;
  EXPECT_NEAR(jm["gear"]["F_r_um"].get<double>(), j["gear"]["F_r_um"].get<double>(), 1e-3);

  // A broken traces file: exit 1, located message.
  std::ofstream(dir / "bad.csv") << "tooth,flank,trace,roll_length_mm,diameter_mm,z_mm,deviation_um\n1,left,helix,90,550,1,inf\n";
  const CliResult bad = run("evaluate " + kScene + " --out " + (dir / "b").string() + " --traces " + (dir / "bad.csv").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("bad.csv:2:23: deviation_um: 'inf' is not finite"), std::string::npos) << bad.err;
  std::filesystem::remove_all(dir);
}

// ISO values in the standard's transverse direction by default, the normal one on request (docs/iso1328.md): every
// trace value of the default gear (β = 30°, α_n = 20°) is 1/cos β_b = 1/cos(asin(sin 30° cos 20°)) = 1.1328 times the
// normal one; the JSON says which. A traces CSV goes through compare as a measurement.
TEST(Cli, EvaluateReportsItsIsoDirectionAndCompareTakesTraces) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_isodir");
  ASSERT_EQ(run("simulate " + kScene + " --out " + (dir / "s").string() + " --method linear --teeth 1,18").code, 0);
  const std::string traces = (dir / "s" / "traces.csv").string();
  const CliResult t = run("evaluate " + kScene + " --out " + (dir / "t").string() + " --traces " + traces);
  const CliResult n = run("evaluate " + kScene + " --out " + (dir / "n").string() + " --traces " + traces +
                          " --iso-direction normal");
  ASSERT_EQ(t.code, 0) << t.err;
  ASSERT_EQ(n.code, 0) << n.err;
  EXPECT_NE(t.out.find("transverse direction"), std::string::npos) << t.out;
  EXPECT_NE(n.out.find("normal direction"), std::string::npos) << n.out;
  std::ifstream it(dir / "t" / "iso1328.json"), in(dir / "n" / "iso1328.json");
  const auto jt = nlohmann::json::parse(it), jn = nlohmann::json::parse(in);
  EXPECT_EQ(jt["iso_direction"], "transverse");
  EXPECT_EQ(jn["before"]["iso_direction"], "normal");
  const double pi = std::acos(-1.0), k = 1.0 / std::cos(std::asin(std::sin(pi / 6) * std::cos(pi / 9)));
  ASSERT_EQ(jt["before"]["flanks"].size(), 4u);
  for (size_t i = 0; i < 4; ++i)
    for (const char* key : {"F_alpha_um", "f_Halpha_um", "F_beta_um", "f_Hbeta_um"})
      EXPECT_NEAR(jt["before"]["flanks"][i][key].get<double>(), k * jn["before"]["flanks"][i][key].get<double>(), 1e-9)
          << i << key;
  EXPECT_EQ(run("evaluate " + kScene + " --out " + (dir / "x").string() + " --iso-direction axial").code, 2);

  const CliResult c = run("compare " + kScene + " --measured " + traces + " --out " + (dir / "c").string() + " --noise-um 0.5");
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.out.find("nominal flank at mean allowance +0.00 µm"), std::string::npos) << c.out;
  std::ifstream ic(dir / "c" / "compare.json");
  const auto jc = nlohmann::json::parse(ic);
  EXPECT_GT(jc["points_without_grid_indices"].get<int>(), 0);
  EXPECT_LT(jc["overall"]["rms_um"].get<double>(), 0.05); // linear traces against the exact model: a few nm
  std::filesystem::remove_all(dir);
}

TEST(Cli, CompensateWritesCorrectionsAndBeforeAfter) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_comp");
  const CliResult r = run("compensate " + kScene + " --out " + dir.string() + " --method flank --step 5");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"corrections.csv", "topology_before.csv", "topology_after.csv", "iso1328.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::ifstream in(dir / "iso1328.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_TRUE(j.contains("before"));
  // Issue 25: the model corrected by itself (≈ 0 by construction) is never `after`: it is kept as `nominal_after`,
  // and every after-state or improvement a user reads comes from the prediction.
  EXPECT_FALSE(j.contains("after"));
  ASSERT_TRUE(j.contains("nominal_after"));
  EXPECT_EQ(j["nominal_after"]["flanks"].size(), 70u);
  const auto& largest = j["largest_abs_deviation_um"];
  EXPECT_LT(largest["nominal_after"].get<double>(), 0.05 * largest["before"].get<double>());
  EXPECT_EQ(j["compensation"]["rows_outside_strokes"].get<int>(), 0);
  EXPECT_NE(r.out.find("largest |deviation|"), std::string::npos);
  ASSERT_TRUE(j.contains("prediction")) << "compensate predicts by default";
  ASSERT_TRUE(j.contains("improvement"));
  // Truth: the improvement recomputed here from the prediction's own medians and after-interval (its definition,
  // docs/compensation.md); the nominal after (≈ 0) would give ≈ 100 % instead.
  int checked = 0;
  for (const auto& [name, imp] : j["improvement"]["quantities"].items()) {
    const auto& q = j["prediction"]["quantities"][name];
    const double b = q["before"]["median"], a = q["after"]["median"], lo = q["after"]["low"], hi = q["after"]["high"];
    EXPECT_NEAR(imp["improvement_percent"].get<double>(), 100.0 * (b - a) / b, 1e-9) << name;
    EXPECT_NEAR(imp["improvement_low_percent"].get<double>(), 100.0 * (b - hi) / b, 1e-9) << name;
    EXPECT_NEAR(imp["improvement_high_percent"].get<double>(), 100.0 * (b - lo) / b, 1e-9) << name;
    ++checked;
  }
  EXPECT_GE(checked, 10); // nine ISO sizes and the largest |deviation|
  const double nominal_gain = 100.0 * (1.0 - largest["nominal_after"].get<double>() / largest["before"].get<double>());
  EXPECT_GT(nominal_gain, 99.0); // what the nominal would claim …
  EXPECT_LT(j["improvement"]["quantities"]["largest_abs_um"]["improvement_percent"].get<double>(), 90.0); // … and what is predicted
  EXPECT_EQ(r.out.find("100 %"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Predicted improvement"), std::string::npos) << r.out;
  // A coarse command resolution can make the predicted gear a class worse (docs/monte-carlo.md, "On the default
  // scene"). Whenever the medians say worse, it is a warning, on stderr and in iso1328.json, not a silent table.
  if (j.contains("prediction")) {
    const auto& q = j["prediction"]["quantities"]["overall_class"];
    const bool worse = q["after"]["median"].get<double>() > q["before"]["median"].get<double>();
    EXPECT_EQ(worse, r.err.find("the predicted gear is worse after compensation") != std::string::npos) << r.err;
    EXPECT_EQ(worse, j["warnings"].dump().find("predicted gear is worse") != std::string::npos);
  }
  // Without a prediction there is no improvement figure at all, and the nominal values say what they are.
  const CliResult none = run("compensate " + kScene + " --out " + dir.string() + " --method flank --step 5 --samples 0");
  ASSERT_EQ(none.code, 0) << none.err;
  const auto j0 = nlohmann::json::parse(std::ifstream(dir / "iso1328.json"));
  EXPECT_FALSE(j0.contains("improvement"));
  EXPECT_FALSE(j0.contains("after"));
  EXPECT_FALSE(j0.contains("prediction"));
  EXPECT_TRUE(j0.contains("nominal_after"));
  EXPECT_NE(none.out.find("nominal (the model corrected by itself)"), std::string::npos) << none.out;
  EXPECT_EQ(none.out.find("%"), std::string::npos) << "a percentage without a prediction: " << none.out;
  std::filesystem::remove_all(dir);
  EXPECT_EQ(run("compensate " + kScene + " --out " + dir.string() + " --method magic").code, 2);
  EXPECT_EQ(run("compensate " + kScene + " --out " + dir.string() + " --step 0").code, 2);
}

// Issue 15: compensate names the grid the scene asks for (it used to print "7×9 grid" whatever the scene said).
TEST(Cli, CompensateNamesTheScenesGrid) {
  const auto scene = write_temp("grid5x6.yaml", "gear:\n  normal_module_mm: 4\n  teeth: 20\n  normal_pressure_angle_deg: 20\n"
                                                "  helix_angle_deg: 20\n  face_width_mm: 30\n  profile_shift: 0\n"
                                                "machine: {datum_face_z_mm: 300, constants: {delta_xx_um: 3}}\n"
                                                "wheel: {outer_diameter_mm: 300}\n"
                                                "measurement: {rows: 5, cols: 6, profile_points: 15, helix_points: 15}\n");
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_grid");
  const CliResult r = run("compensate " + scene.string() + " --out " + dir.string() + " --step 5 --samples 0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("topology (all teeth, 5×6 grid)"), std::string::npos) << r.out;
  std::filesystem::remove(scene);
  std::filesystem::remove_all(dir);
}

// Issue 44: a user's own scene without machine.tables (an error-free machine) printed a "before" of class 4 [3, 5] and
// an improvement with nothing saying that the spread comes only from the default uncertainties and that the nominal
// deviations and corrections are 0. The console and iso1328.json say so; a scene with a map does not get the note.
TEST(Cli, CompensateSaysWhenTheMachineHasNoErrorMap) {
  const std::string gear = "gear:\n  normal_module_mm: 4\n  teeth: 20\n  normal_pressure_angle_deg: 20\n"
                           "  helix_angle_deg: 20\n  face_width_mm: 30\n  profile_shift: 0\n";
  const std::string rest = "wheel: {outer_diameter_mm: 300}\nmeasurement: {rows: 5, cols: 5, profile_points: 15, helix_points: 15}\n";
  const auto bare = write_temp("bare.yaml", gear + "machine: {datum_face_z_mm: 300}\n" + rest);
  const auto mapped = write_temp("mapped.yaml", gear + "machine: {datum_face_z_mm: 300, constants: {delta_xx_um: 3}}\n" + rest);
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_bare");
  const CliResult r = run("compensate " + bare.string() + " --out " + dir.string() + " --step 5 --samples 4");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string note = "note: the scene's machine has no error map (no machine.tables, constants or polynomials: an "
                           "error-free machine), and no effects: its nominal deviations and its corrections are 0; the "
                           "prediction's spread comes only from the uncertainties";
  EXPECT_NE(r.out.find(note), std::string::npos) << r.out;
  EXPECT_LT(r.out.find(note), r.out.find("before")) << "the note comes before the numbers";
  std::ifstream iso(dir / "iso1328.json");
  const auto j = nlohmann::json::parse(iso);
  ASSERT_TRUE(j.contains("notes"));
  EXPECT_EQ(j["notes"][0].get<std::string>().rfind(note, 0), 0u);
  const CliResult m = run("compensate " + mapped.string() + " --out " + dir.string() + " --step 5 --samples 0");
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(m.out.find("no error map"), std::string::npos) << m.out;
  std::filesystem::remove(bare);
  std::filesystem::remove(mapped);
  std::filesystem::remove_all(dir);
}

// Issue 14: the truth scene's thermal drift at 1.5 µm noise on teeth 1 and 18 cannot be told from wheel wear; `plan`
// says so and names teeth to measure (truth: the ΔBIC gap is within 10, and the plan's teeth are not measured ones).
TEST(Cli, PlanNamesTheTeethThatSeparateAmbiguousExplanations) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_plan");
  std::filesystem::create_directories(dir);
  const std::string truth = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml";
  const std::string measured = (dir / "m.csv").string();
  ASSERT_EQ(run("synth " + truth + " --out " + measured + " --teeth 1,18 --noise-um 1.5 --seed 3").code, 0);
  const CliResult plan = run("plan " + kScene + " --measured " + measured + " --noise-um 1.5 --out " + (dir / "p").string());
  ASSERT_EQ(plan.code, 0) << plan.err;
  std::ifstream pj(dir / "p" / "plan.json");
  const auto p = nlohmann::json::parse(pj);
  ASSERT_TRUE(p["ambiguous"].get<bool>()) << p["verdict"];
  const auto& between = p["plan"]["between"];
  // The X growth on one side: thermal_drift itself, or the X axis drifting that thermal_drift leaves the same field of
  // (the families are tried beside the library's ambiguity: docs/diagnosis.md, "Beyond the library") — named, or in
  // the class of its representative: a drifting S_xz tilts Z's travel with the lever Z = z + z₀ ≈ 400 mm, which hardly
  // changes over the 150 mm face, so it is an X drift by another name.
  const std::string x_drift_said = "the library's thermal_drift can leave the same field";
  const std::string verdict = p["verdict"];
  const auto class_at = verdict.find("one class): ");
  const std::string x_class =
      class_at == std::string::npos ? "" : verdict.substr(class_at, verdict.find('.', class_at) - class_at);
  EXPECT_TRUE(between[0] == "thermal_drift" || between[1] == "thermal_drift" ||
              ((between[0] == "delta_xx linear_in_time" ||
                x_class.find("delta_xx linear_in_time") != std::string::npos) &&
               verdict.find(x_drift_said) != std::string::npos))
      << between << verdict;
  EXPECT_LT(p["plan"]["delta_bic_gap"].get<double>(), 10.0);
  ASSERT_FALSE(p["plan"]["recommended_teeth"].empty());
  for (int tooth : p["plan"]["recommended_teeth"].get<std::vector<int>>()) {
    EXPECT_NE(tooth, 1);
    EXPECT_NE(tooth, 18);
  }
  EXPECT_NE(plan.out.find("Measure teeth"), std::string::npos) << plan.out;
  // The same as traces a measuring machine takes (issue 28): 3 profile and 3 helix traces per flank on the new teeth.
  const CliResult traces =
      run("plan " + kScene + " --measured " + measured + " --noise-um 1.5 --layout traces --out " + (dir / "t").string());
  ASSERT_EQ(traces.code, 0) << traces.err;
  std::ifstream tj(dir / "t" / "plan.json");
  const auto t = nlohmann::json::parse(tj);
  const auto& rec = t["plan"]["recommended"];
  ASSERT_TRUE(rec.contains("traces")) << rec;
  EXPECT_EQ(rec["traces"]["profile_z_mm"].size(), 3u);
  EXPECT_EQ(rec["traces"]["helix_diameter_mm"].size(), 3u);
  EXPECT_EQ(rec["points"].get<int>(), static_cast<int>(rec["teeth"].size()) * 2 * 6 * rec["traces"]["points_per_trace"].get<int>());
  EXPECT_NE(traces.out.find("3 profile traces (z = "), std::string::npos) << traces.out;
  EXPECT_NE(run("plan " + kScene + " --measured " + measured + " --layout dots").code, 0);
  std::filesystem::remove_all(dir);
}

// The story users care about: measure a truth scene with a hidden effect, compare, diagnose, add it, compare again.
TEST(Cli, SynthCompareDiagnoseAndTheErrorFalls) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_story");
  std::filesystem::create_directories(dir);
  const std::string truth = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml";
  const std::string measured = (dir / "m.csv").string();
  // Seed 7, the demo measurement's (scenes/demo/measured.csv). Two teeth do not determine the drift's size (docs/tutorial.md
  // §4): of seeds 1–8 of synth's SplitMix64 noise, 3 and 4 put the amplitude at the end of its range and 2 is ambiguous
  // with a second effect, and diagnose rightly withholds the scene there; the story below needs a realization where it
  // is written.
  ASSERT_EQ(run("synth " + truth + " --out " + measured + " --teeth 1,18 --noise-um 0.5 --seed 7").code, 0);

  const CliResult before = run("compare " + kScene + " --measured " + measured + " --out " + (dir / "c1").string() + " --noise-um 0.5");
  ASSERT_EQ(before.code, 0) << before.err;
  std::ifstream c1(dir / "c1" / "compare.json");
  const double rms_before = nlohmann::json::parse(c1)["overall"]["rms_um"].get<double>();

  const CliResult diag = run("diagnose " + kScene + " --measured " + measured + " --out " + (dir / "d").string() + " --noise-um 0.5");
  ASSERT_EQ(diag.code, 0) << diag.err;
  std::ifstream dj(dir / "d" / "diagnosis.json");
  const auto d = nlohmann::json::parse(dj);
  ASSERT_FALSE(d["candidates"].empty());
  EXPECT_EQ(d["candidates"][0]["effect"], "thermal_drift");
  for (const char* key : {"effect", "parameters", "explained_fraction", "rms_before_um", "rms_after_um"})
    EXPECT_TRUE(d["candidates"][0].contains(key)) << key;
  EXPECT_EQ(d["candidates"][0]["parameters"]["x_growth_um"]["unit"], "um");
  for (const auto& c : d["candidates"]) // the unit is everything from the first unit token: µm per stroke, not "stroke"
    if (c["effect"] == "wheel_wear") {
      EXPECT_EQ(c["parameters"]["wear_um_per_stroke"]["unit"], "um_per_stroke");
    }
  for (const char* key : {"ambiguous", "rivals", "plan", "assumed", "scene_with_effect_withheld"})
    EXPECT_TRUE(d.contains(key)) << key;
  EXPECT_FALSE(d["ambiguous"].get<bool>()) << d["verdict"];
  for (const char* key : {"thickness_um", "thickness_sd_um", "rotation_urad", "rotation_sd_urad", "rotation_identified"})
    EXPECT_TRUE(d["setup"].contains(key)) << key;

  const CliResult after = run("compare " + (dir / "d" / "scene_with_effect.yaml").string() + " --measured " + measured +
                              " --out " + (dir / "c2").string() + " --noise-um 0.5");
  ASSERT_EQ(after.code, 0) << after.err;
  std::ifstream c2(dir / "c2" / "compare.json");
  const double rms_after = nlohmann::json::parse(c2)["overall"]["rms_um"].get<double>();
  EXPECT_GT(rms_before, 1.5 * 0.5);
  EXPECT_LE(rms_after, 1.5 * 0.5);

  // Bad measurement files: exit 1 with the line.
  std::ofstream(dir / "bad.csv") << "tooth,flank,row,col,diameter_mm,z_mm,deviation_um\n1,left,1,1,700,10,0.1\n";
  const CliResult bad = run("compare " + kScene + " --measured " + (dir / "bad.csv").string() + " --out " + (dir / "b").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("bad.csv:2: diameter_mm"), std::string::npos) << bad.err;
  std::filesystem::remove_all(dir);
}

// A Klingelnberg export from synth is recognised by its content and compared like the topology CSV of the same data.
TEST(Cli, CompareReadsAKlingelnbergExport) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_mka");
  std::filesystem::create_directories(dir);
  const std::string truth = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml";
  const std::string mka = (dir / "m.mka").string(), csv = (dir / "m.csv").string();
  ASSERT_EQ(run("synth " + truth + " --out " + mka + " --format klingelnberg --noise-um 0.5 --seed 3").code, 0);
  ASSERT_EQ(run("synth " + truth + " --out " + csv + " --noise-um 0.5 --seed 3").code, 0);
  const CliResult a = run("compare " + kScene + " --measured " + mka + " --out " + (dir / "a").string() + " --noise-um 0.5");
  ASSERT_EQ(a.code, 0) << a.err;
  const CliResult b = run("compare " + kScene + " --measured " + csv + " --out " + (dir / "b").string() + " --noise-um 0.5");
  ASSERT_EQ(b.code, 0) << b.err;
  std::ifstream ja(dir / "a" / "compare.json"), jb(dir / "b" / "compare.json");
  // The export prints deviations to 0.001 µm (transverse): the RMS agrees to that.
  EXPECT_NEAR(nlohmann::json::parse(ja)["overall"]["rms_um"].get<double>(),
              nlohmann::json::parse(jb)["overall"]["rms_um"].get<double>(), 1e-3);
  EXPECT_EQ(run("synth " + truth + " --out " + mka + " --format xml").code, 2);
  // The reader's options are flags: read with the DIN sign, the raw left profiles come back inverted.
  const CliResult din = run("compare " + kScene + " --measured " + mka + " --out " + (dir / "d").string() +
                            " --noise-um 0.5 --mka-signs din --mka-direction transverse --mka-spacing roll-length");
  ASSERT_EQ(din.code, 0) << din.err;
  std::ifstream jd(dir / "d" / "compare.json"), jb2(dir / "b" / "compare.json");
  EXPECT_GT(nlohmann::json::parse(jd)["overall"]["rms_um"].get<double>(),
            nlohmann::json::parse(jb2)["overall"]["rms_um"].get<double>() + 0.1);
  EXPECT_EQ(run("compare " + kScene + " --measured " + mka + " --out " + (dir / "e").string() + " --mka-signs plus").code, 2);
  std::filesystem::remove_all(dir);
}

// run and report read measurements through the same options as compare (add_measurement_options): a Klingelnberg
// export read by `run --mka-signs din` gives the residual `compare --mka-signs din` gives, and not the one of the raw
// signs (which the DIN reading of a raw export spoils by more than 0.1 µm RMS: CompareReadsAKlingelnbergExport).
TEST(Cli, RunReadsAKlingelnbergExportWithTheMkaOptions) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_run_mka");
  std::filesystem::create_directories(dir);
  // A small gear (two teeth simulated) so that run's whole job stays short, measured as the model grinds it: read with
  // the right signs the residual is the probe noise, with the wrong ones twice the flipped deviations. The machine
  // errors make the flanks deviate (against a perfect model a sign flip would not change the residual's RMS).
  const std::string gear = "gear: {normal_module_mm: 4, teeth: 20, normal_pressure_angle_deg: 20, helix_angle_deg: 20, "
                           "profile_shift: 0, face_width_mm: 30}\n"
                           "machine: {datum_face_z_mm: 300, constants: {S_xz_urad: 30, E_XOC_um: 5, epsilon_zx_urad: 40}}\n"
                           "wheel: {outer_diameter_mm: 300}\n"
                           "measurement: {rows: 5, cols: 5, profile_points: 15, helix_points: 15, teeth: [1, 11]}\n";
  std::ofstream(dir / "model.yaml") << gear;
  const std::string model = (dir / "model.yaml").string(), mka = (dir / "m.mka").string();
  ASSERT_EQ(run("synth " + model + " --out " + mka + " --format klingelnberg --teeth 1,11 "
                "--noise-um 0.3 --seed 5").code, 0);
  const auto rms_of = [&](const std::filesystem::path& json) {
    return nlohmann::json::parse(std::ifstream(json))["overall"]["rms_um"].get<double>();
  };
  const CliResult raw = run("compare " + model + " --measured " + mka + " --noise-um 0.3 --out " + (dir / "raw").string());
  ASSERT_EQ(raw.code, 0) << raw.err;
  const CliResult din = run("compare " + model + " --measured " + mka + " --noise-um 0.3 --mka-signs din --out " + (dir / "din").string());
  ASSERT_EQ(din.code, 0) << din.err;
  const CliResult r = run("run " + model + " --measured " + mka + " --noise-um 0.3 --mka-signs din --samples 0 --out " +
                          (dir / "run").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(rms_of(dir / "run" / "compare.json"), rms_of(dir / "din" / "compare.json"), 1e-9);
  EXPECT_GT(std::abs(rms_of(dir / "run" / "compare.json") - rms_of(dir / "raw" / "compare.json")), 0.1);
  // report takes the same flags (the same code adds them to both).
  const CliResult help = run("report --help");
  for (const char* flag : {"--mka-spacing", "--mka-direction", "--mka-signs"})
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag;
  std::filesystem::remove_all(dir);
}

// The gear as drawn (issue 26): a crowned gear measured against its design. A gear ground to the drawing on the
// scene's machine reads as the model (nothing missing), where the bare-involute scene reads its crowning as a fault;
// a hidden thermal drift on the crowned gear is still found as thermal drift.
TEST(Cli, ACrownedGearIsMeasuredAgainstItsDesign) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_crowned");
  std::filesystem::create_directories(dir);
  const std::string crowned = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35-crowned.yaml";
  const std::string as_drawn = (dir / "as_drawn.csv").string();
  ASSERT_EQ(run("synth " + crowned + " --out " + as_drawn + " --teeth 1,18 --noise-um 0.5 --seed 4").code, 0);
  const auto diagnose = [&](const std::string& scene, const std::string& measured, const std::string& name) {
    const CliResult r = run("diagnose " + scene + " --measured " + measured + " --out " + (dir / name).string() + " --noise-um 0.5");
    EXPECT_EQ(r.code, 0) << r.err;
    std::ifstream in(dir / name / "diagnosis.json");
    return nlohmann::json::parse(in);
  };
  const auto same = diagnose(crowned, as_drawn, "same");
  EXPECT_TRUE(same["chosen"].is_null()) << same["verdict"];
  // The bare scene sees the drawing's 4 µm profile and 6 µm helix crowning as a deviation far above the noise.
  const CliResult bare = run("compare " + kScene + " --measured " + as_drawn + " --out " + (dir / "bare").string() + " --noise-um 0.5");
  ASSERT_EQ(bare.code, 0) << bare.err;
  std::ifstream bare_json(dir / "bare" / "compare.json");
  EXPECT_GT(nlohmann::json::parse(bare_json)["overall"]["rms_um"].get<double>(), 4 * 0.5);

  std::ifstream in(crowned);
  std::stringstream read;
  read << in.rdbuf();
  std::string text = read.str(); // the tables by absolute path: the truth is written elsewhere
  const std::string tables = "machine/", absolute = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/machine/";
  for (size_t at = text.find("tables: ["); (at = text.find(tables, at)) != std::string::npos && text[at - 1] != '/';)
    text.replace(at, tables.size(), absolute), at += absolute.size();
  text += "effects:\n  - {type: thermal_drift, x_growth_um: 9, z_growth_um: 0, time_constant_s: 600}\n";
  const auto truth = write_temp("crowned_truth.yaml", text);
  const std::string drifted = (dir / "drifted.csv").string();
  ASSERT_EQ(run("synth " + truth.string() + " --out " + drifted + " --teeth 1,18 --noise-um 0.5 --seed 4").code, 0);
  const auto found = diagnose(crowned, drifted, "drifted");
  ASSERT_FALSE(found["candidates"].empty());
  EXPECT_EQ(found["candidates"][0]["effect"], "thermal_drift") << found["verdict"];
  std::filesystem::remove_all(dir);
}

namespace {

/// `from` (a topology or traces CSV of geartopo's, design_um last) written to `to` without its design_um column: the
/// same deviations from the design, as a measuring machine that evaluates against the drawing writes them.
void copy_without_design_column(const std::string& from, const std::string& to) {
  std::ifstream in(from);
  std::ofstream out(to);
  for (std::string line; std::getline(in, line);)
    out << (line.empty() || line[0] == '#' ? line : line.substr(0, line.rfind(','))) << "\n";
}

} // namespace

// A measuring machine that evaluates against the drawing writes deviations from the design; written without a design_um
// column, the file is read as against the bare involute and its residual is minus the drawing (issue 39: "Unexplained
// … profile crowning −10.40 µm"). diagnose says so first, with the numbers and how to declare it; with
// --measured-against design the same file diagnoses as the file with its design column ("nothing missing", the same
// residual); declared involute, the doubt is not raised; declared for a file that has the column, refused.
TEST(Cli, AFileEvaluatedAgainstTheDrawingWithoutItsDesignColumnIsRecognised) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_against_drawing");
  std::filesystem::create_directories(dir);
  const std::string crowned = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35-crowned.yaml";
  const std::string with_column = (dir / "with_column.csv").string(), without = (dir / "without.csv").string();
  ASSERT_EQ(run("synth " + crowned + " --out " + with_column + " --teeth 1,18 --noise-um 0.5 --seed 4").code, 0);
  copy_without_design_column(with_column, without);
  const auto diagnose = [&](const std::string& measured, const std::string& flags, const std::string& name) {
    const CliResult r = run("diagnose " + crowned + " --measured " + measured + " --out " + (dir / name).string() +
                            " --noise-um 0.5 " + flags);
    EXPECT_EQ(r.code, 0) << r.err;
    std::ifstream in(dir / name / "diagnosis.json");
    return nlohmann::json::parse(in);
  };
  const auto doubt = [](const nlohmann::json& j) {
    for (const auto& d : j["decisions"])
      if (d["reason"] == "reference_in_doubt") return d;
    return nlohmann::json(nullptr);
  };
  const auto reference = diagnose(with_column, "", "with_column");
  EXPECT_TRUE(reference["chosen"].is_null()) << reference["verdict"];
  EXPECT_TRUE(doubt(reference).is_null());

  const auto undeclared = diagnose(without, "", "undeclared");
  const auto d = doubt(undeclared);
  ASSERT_FALSE(d.is_null()) << undeclared["verdict"];
  const std::string verdict = undeclared["verdict"];
  EXPECT_EQ(verdict.rfind("The measurement looks evaluated against the drawing", 0), 0u) << verdict;
  EXPECT_NE(verdict.find("--measured-against design"), std::string::npos) << verdict;
  // The drawing (C_α 4, tip relief 8, C_β 6 µm) is far above the noise; against it, what is left is the noise.
  EXPECT_GT(d["numbers"]["design_rms_um"].get<double>(), 4 * 0.5);
  EXPECT_GT(d["numbers"]["residual_rms_um"].get<double>(), 4 * 0.5);
  EXPECT_LT(d["numbers"]["against_drawing_rms_um"].get<double>(), 0.6);
  EXPECT_NEAR(d["numbers"]["against_drawing_rms_um"].get<double>(), reference["rms_before_setup_removed_um"].get<double>(), 1e-3);

  const auto declared = diagnose(without, "--measured-against design", "declared");
  EXPECT_TRUE(doubt(declared).is_null()) << declared["verdict"];
  EXPECT_TRUE(declared["chosen"].is_null()) << declared["verdict"];
  EXPECT_NEAR(declared["rms_before_um"].get<double>(), reference["rms_before_um"].get<double>(), 1e-4); // file's digits
  EXPECT_EQ(declared["verdict"].get<std::string>().rfind("Set-up", 0), 0u) << declared["verdict"];

  EXPECT_TRUE(doubt(diagnose(without, "--measured-against involute", "involute")).is_null());
  // compare says it too, first, with diagnose's numbers; not once declared.
  for (const auto& [flags, name, in_doubt] : {std::tuple{"", "compare_undeclared", true},
                                               std::tuple{"--measured-against design", "compare_declared", false}}) {
    const CliResult r = run("compare " + crowned + " --measured " + without + " --out " + (dir / name).string() +
                            " --noise-um 0.5 " + flags);
    ASSERT_EQ(r.code, 0) << r.err;
    std::ifstream in(dir / name / "compare.json");
    const auto c = nlohmann::json::parse(in);
    EXPECT_EQ(!c["reference_in_doubt"].is_null(), in_doubt) << name;
    EXPECT_EQ(r.out.find("Warning: The measurement looks evaluated against the drawing") != std::string::npos, in_doubt)
        << r.out;
    if (in_doubt) {
      EXPECT_NEAR(c["reference_in_doubt"]["numbers"]["design_rms_um"].get<double>(),
                  d["numbers"]["design_rms_um"].get<double>(), 1e-9);
    }
  }
  const CliResult twice = run("diagnose " + crowned + " --measured " + with_column + " --measured-against design --out " +
                              (dir / "twice").string() + " --noise-um 0.5");
  EXPECT_EQ(twice.code, 1);
  EXPECT_NE(twice.err.find("design_um"), std::string::npos) << twice.err;
  EXPECT_NE(twice.err.find(with_column), std::string::npos) << twice.err;
  std::filesystem::remove_all(dir);
}

// evaluate --traces reads measured traces as diagnose reads a measurement: a file of deviations from the drawing
// without its design_um column is evaluated like the file with it once declared (--measured-against design), is
// warned about when not (on a designed gear its F_α holds the drawing's profile crowning), and a declaration for a
// file with the column, or without --traces, is refused.
TEST(Cli, EvaluateTracesMeasuredAgainstTheDrawingWithoutTheColumn) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_traces_against");
  std::filesystem::create_directories(dir);
  const std::string crowned = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35-crowned.yaml";
  const std::string with_column = (dir / "with_column.csv").string(), without = (dir / "without.csv").string();
  ASSERT_EQ(run("synth " + crowned + " --out " + with_column + " --format traces --teeth all --noise-um 0 --seed 4").code, 0);
  copy_without_design_column(with_column, without);
  const auto evaluate = [&](const std::string& traces, const std::string& flags, const std::string& name) {
    const CliResult r = run("evaluate " + crowned + " --traces " + traces + " --out " + (dir / name).string() + " " + flags);
    EXPECT_EQ(r.code, 0) << r.err;
    std::ifstream in(dir / name / "iso1328.json");
    return std::pair{nlohmann::json::parse(in), r.err};
  };
  const auto [reference, reference_err] = evaluate(with_column, "", "with_column");
  const auto [declared, declared_err] = evaluate(without, "--measured-against design", "declared");
  const auto [undeclared, undeclared_err] = evaluate(without, "", "undeclared");
  EXPECT_EQ(reference_err.find("no design_um column"), std::string::npos) << reference_err;
  EXPECT_EQ(declared_err.find("no design_um column"), std::string::npos) << declared_err;
  EXPECT_NE(undeclared_err.find("no design_um column"), std::string::npos) << undeclared_err;
  EXPECT_NE(undeclared_err.find("--measured-against design"), std::string::npos) << undeclared_err;
  // Per tooth and flank: equal to the file's 4 decimals when declared; the drawing's C_α 4 µm + tip relief 8 µm in
  // F_α when not.
  const auto& ref_flanks = reference["before"]["flanks"];
  ASSERT_EQ(ref_flanks.size(), 70u);
  for (std::size_t i = 0; i < ref_flanks.size(); ++i) {
    for (const char* q : {"F_alpha_um", "f_falpha_um", "f_Halpha_um", "F_beta_um", "f_fbeta_um", "f_Hbeta_um"}) {
      const double ref = ref_flanks[i][q], dec = declared["before"]["flanks"][i][q];
      EXPECT_NEAR(dec, ref, 0.02) << i << " " << q;
    }
    const double undeclared_F_alpha = undeclared["before"]["flanks"][i]["F_alpha_um"];
    EXPECT_GT(undeclared_F_alpha - ref_flanks[i]["F_alpha_um"].get<double>(), 4.0) << i;
  }
  EXPECT_NEAR(declared["before"]["gear"]["F_r_um"].get<double>(), reference["before"]["gear"]["F_r_um"].get<double>(), 0.02);
  const CliResult twice = run("evaluate " + crowned + " --traces " + with_column + " --measured-against design --out " +
                              (dir / "twice").string());
  EXPECT_EQ(twice.code, 1);
  EXPECT_NE(twice.err.find(with_column + ":1: design_um"), std::string::npos) << twice.err;
  const CliResult no_traces = run("evaluate " + crowned + " --measured-against design --out " + (dir / "sim").string());
  EXPECT_EQ(no_traces.code, 2);
  EXPECT_NE(no_traces.err.find("--measured-against: needs --traces"), std::string::npos) << no_traces.err;
  std::filesystem::remove_all(dir);
}

// An unknown command is an error whatever flags follow it (issue 39: `geartopo series --help`, before `series`
// existed, printed the main help and exited 0); a command's own --help still answers.
TEST(Cli, AnUnknownCommandIsAnErrorEvenWithHelp) {
  for (const char* args : {"grind --help", "grind", "--quiet grind --help", "grind --version"}) {
    const CliResult r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find("'grind' is not a command"), std::string::npos) << args << ": " << r.err;
    EXPECT_NE(r.err.find("diagnose"), std::string::npos) << r.err; // the commands there are
  }
  const CliResult help = run("diagnose --help");
  EXPECT_EQ(help.code, 0) << help.err;
  EXPECT_NE(help.out.find("--measured-against"), std::string::npos) << help.out;
  EXPECT_EQ(run("--help").code, 0);
}

// The paper method drives the wheel to its nominal pose and would grind away the drawing's helix crowning: refused on
// a scene that has one (docs/modifications.md); the flank method keeps it.
TEST(Cli, ThePaperMethodIsRefusedOnADesignedHelix) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_paper_crowned");
  const std::string crowned = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35-crowned.yaml";
  const CliResult paper = run("compensate " + crowned + " --method paper --samples 0 --out " + dir.string());
  EXPECT_EQ(paper.code, 2) << paper.err;
  EXPECT_NE(paper.err.find("--method"), std::string::npos) << paper.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "corrections.csv"));
  EXPECT_EQ(run("compensate " + crowned + " --method flank --samples 0 --out " + dir.string()).code, 0);
  std::filesystem::remove_all(dir);
}
