// The ISG/Beckhoff TF5280 volumetric compensation table ("ISG CSV"): the file is read back by a small reader written
// here from the format's public description (whitespace columns, header naming argument and parameters, `//`
// comments, `#` starting a new block); expected values come from the units of the format (mm, rad; arguments mm and
// deg) and from the sign convention derived in docs/compensation.md, applied by hand to hand-built error tables. The
// flank deviation the table leaves is checked against a machine whose only error is the same rotation about the
// wheel centre (an independent way to produce it), and bounded by rotation × lever arm.
#include "geartopo/compensation/isg_table.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/error_table.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include "../cli_run.hpp"
#include "../grinding/grinding_fixture.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

using namespace geartopo;
using machine::ComponentId;
using machine::ErrorSource;

namespace {

// --- an independent reader of ISG CSV ---------------------------------------------------------------------------

struct IsgReadBlock {
  std::vector<std::string> header;               // argument (if any) and parameter names
  std::vector<std::vector<double>> records;      // one per data line
  std::vector<std::string> comments;             // `//` lines seen in this block
  /// Column of a name in the header; -1 if absent.
  int column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
  double at(const std::string& name, std::size_t record) const { return records.at(record).at(static_cast<std::size_t>(column(name))); }
};

std::vector<IsgReadBlock> read_isg_csv(const std::string& text) {
  std::vector<IsgReadBlock> blocks(1);
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    if (line.compare(first, 2, "//") == 0) {
      blocks.back().comments.push_back(line.substr(first + 2));
      continue;
    }
    if (line[first] == '#') {
      blocks.emplace_back();
      continue;
    }
    std::istringstream fields(line);
    std::string f;
    std::vector<std::string> tokens;
    while (fields >> f) tokens.push_back(f);
    IsgReadBlock& b = blocks.back();
    if (b.header.empty()) {
      b.header = tokens;
      continue;
    }
    std::vector<double> record;
    for (const auto& t : tokens) {
      std::size_t used = 0;
      record.push_back(std::stod(t, &used));
      EXPECT_EQ(used, t.size()) << "not a plain number: " << t;
    }
    EXPECT_EQ(record.size(), b.header.size()) << line;
    b.records.push_back(record);
  }
  return blocks;
}

std::string isg_text(const compensation::IsgTable& t, const compensation::IsgLimits& limits = {}) {
  std::ostringstream out;
  compensation::write_isg_table(out, t, limits);
  return out.str();
}

/// The block whose header starts with `first` ("X", "A", "X0C", …).
const IsgReadBlock& isg_block(const std::vector<IsgReadBlock>& blocks, const std::string& first) {
  for (const auto& b : blocks)
    if (!b.header.empty() && b.header.front() == first) return b;
  throw std::runtime_error("no block " + first);
}

/// Row index whose argument equals `arg` (to 1e-9).
std::size_t isg_row_at(const IsgReadBlock& b, double arg) {
  for (std::size_t r = 0; r < b.records.size(); ++r)
    if (std::abs(b.records[r][0] - arg) < 1e-9) return r;
  throw std::runtime_error("no record at " + std::to_string(arg));
}

void expect_isg_equidistant(const IsgReadBlock& b) {
  ASSERT_GE(b.records.size(), 2u);
  const double h = b.records[1][0] - b.records[0][0];
  EXPECT_GT(h, 0.0);
  for (std::size_t r = 1; r < b.records.size(); ++r) EXPECT_NEAR(b.records[r][0] - b.records[r - 1][0], h, 1e-9) << b.header[0];
}

// The file's resolution: 9 decimals of mm (1 pm) and 12 of rad (1 prad); rounding is half of that.
constexpr double kIsgFileMm = 1e-9;
constexpr double kIsgFileRad = 1e-12;

std::vector<ErrorSource> isg_sources(const std::string& csv) { return machine::parse_error_tables(csv, "hand.csv"); }


} // namespace

TEST(IsgTable, UnitsArgumentsAndCommentsReadBack) {
  // X straightness δ_yx measured every 100 mm: 5 µm at 100 mm; a constant 10 µrad yaw ε_zx; A with a polynomial.
  auto sources = isg_sources("x_mm,delta_yx_um\n0,0\n100,5\n200,3\n300,0\n400,-2\n500,0\n600,1\n700,0\n800,0\n900,0\n");
  sources.push_back(ErrorSource::constant(ComponentId::epsilon_zx, 10.0, "urad"));
  sources.push_back(ErrorSource::polynomial(ComponentId::delta_xa, {0.0, 0.1}, "um", "deg")); // 0.1 µm per degree
  const auto model = test::machine_with(sources);
  const auto text = isg_text(compensation::make_isg_table(model));
  const auto blocks = read_isg_csv(text);

  ASSERT_EQ(blocks.size(), 6u); // X, Y, Z, A, C, constants
  EXPECT_FALSE(blocks.front().comments.empty());
  const auto& x = isg_block(blocks, "X");
  EXPECT_EQ(x.header, (std::vector<std::string>{"X", "EXX", "EYX", "EZX", "EAX", "EBX", "ECX"}));
  ASSERT_EQ(x.records.size(), 10u); // the table's own equidistant knots, not resampled
  expect_isg_equidistant(x);
  EXPECT_NEAR(x.records.front()[0], 0.0, 1e-9);
  EXPECT_NEAR(x.records.back()[0], 900.0, 1e-9);
  EXPECT_NEAR(x.at("EYX", isg_row_at(x, 100.0)), 0.005, kIsgFileMm);   // 5 µm = 0.005 mm
  EXPECT_NEAR(x.at("EYX", isg_row_at(x, 400.0)), -0.002, kIsgFileMm);
  for (std::size_t r = 0; r < x.records.size(); ++r) EXPECT_NEAR(x.at("ECX", r), 1e-5, kIsgFileRad); // 10 µrad = 1e-5 rad

  // A: argument in degrees over the stroke [−45, 45] deg, every degree; δ_xa = 0.1 µm/deg · α = 1e-4 mm/deg · α.
  const auto& a = isg_block(blocks, "A");
  expect_isg_equidistant(a);
  EXPECT_NEAR(a.records.front()[0], -45.0, 1e-9);
  EXPECT_NEAR(a.records.back()[0], 45.0, 1e-9);
  EXPECT_NEAR(a.records[1][0] - a.records[0][0], 1.0, 1e-9);
  EXPECT_NEAR(a.at("EXA", isg_row_at(a, 30.0)), 30.0 * 1e-4, kIsgFileMm);

  // C: nothing given, two records, 0 and 360 deg.
  const auto& c = isg_block(blocks, "C");
  ASSERT_EQ(c.records.size(), 2u);
  EXPECT_NEAR(c.records[0][0], 0.0, 1e-12);
  EXPECT_NEAR(c.records[1][0], 360.0, 1e-12);
  // Constants block: one record, no argument.
  const auto& k = isg_block(blocks, "X0C");
  EXPECT_EQ(k.records.size(), 1u);
}

TEST(IsgTable, SignsFollowTheDerivedIso230Convention) {
  // Hand-built machine; each expectation is the mapping of docs/compensation.md applied by hand.
  const auto model = test::machine_with({
      ErrorSource::constant(ComponentId::delta_xx, 2.0, "um"),     // EXX = +0.002 mm (carriage further along +x)
      ErrorSource::constant(ComponentId::epsilon_yz, -4.0, "urad"), // EBZ = −4e-6 rad
      ErrorSource::constant(ComponentId::delta_ya, 4.0, "um"),     // A body's +y: (EYA, EZA) = 4 µm (cos α, sin α)
      ErrorSource::constant(ComponentId::epsilon_za, 8.0, "urad"), // A body's +z: (EBA, ECA) = 8 µrad (−sin α, cos α)
      ErrorSource::constant(ComponentId::delta_xc, 5.0, "um"),     // table's +x: (EXC, EYC) = 5 µm (cos γ, sin γ)
      ErrorSource::constant(ComponentId::epsilon_zc, 3.0, "urad"), // ECC = +3e-6 rad (table turned further)
      ErrorSource::constant(ComponentId::S_xy, 12.0, "urad"),      // Y leans to −x: C0Y = +12e-6
      ErrorSource::constant(ComponentId::S_zy, 7.0, "urad"),       // Y leans to −z: A0Y = −7e-6
      ErrorSource::constant(ComponentId::S_xz, 3.0, "urad"),       // Z leans to −x: B0Z = −3e-6
      ErrorSource::constant(ComponentId::E_XOC, 6.0, "um"),        // C axis line at +6 µm x: X0C = 0.006 mm
      ErrorSource::constant(ComponentId::E_BOA, -9.0, "urad"),     // A axis line tilt: B0A = −9e-6
  });
  const auto blocks = read_isg_csv(isg_text(compensation::make_isg_table(model)));
  const auto& x = isg_block(blocks, "X");
  EXPECT_NEAR(x.at("EXX", 0), 0.002, kIsgFileMm);
  EXPECT_NEAR(x.at("EXX", x.records.size() - 1), 0.002, kIsgFileMm);
  EXPECT_NEAR(isg_block(blocks, "Z").at("EBZ", 0), -4e-6, kIsgFileRad);

  const double deg = std::numbers::pi / 180.0;
  const auto& a = isg_block(blocks, "A");
  expect_isg_equidistant(a); // constants across a turning axis are sampled, not two records
  for (const double alpha : {-45.0, -20.0, 0.0, 30.0, 45.0}) {
    const std::size_t r = isg_row_at(a, alpha);
    EXPECT_NEAR(a.at("EYA", r), 0.004 * std::cos(alpha * deg), kIsgFileMm) << alpha;
    EXPECT_NEAR(a.at("EZA", r), 0.004 * std::sin(alpha * deg), kIsgFileMm) << alpha;
    EXPECT_NEAR(a.at("EBA", r), -8e-6 * std::sin(alpha * deg), kIsgFileRad) << alpha;
    EXPECT_NEAR(a.at("ECA", r), 8e-6 * std::cos(alpha * deg), kIsgFileRad) << alpha;
  }
  const auto& c = isg_block(blocks, "C");
  expect_isg_equidistant(c);
  EXPECT_NEAR(c.records.front()[0], 0.0, 1e-12);
  EXPECT_NEAR(c.records.back()[0], 360.0, 1e-9);
  for (const double gamma : {0.0, 90.0, 135.0, 270.0}) {
    const std::size_t r = isg_row_at(c, gamma);
    EXPECT_NEAR(c.at("EXC", r), 0.005 * std::cos(gamma * deg), kIsgFileMm) << gamma;
    EXPECT_NEAR(c.at("EYC", r), 0.005 * std::sin(gamma * deg), kIsgFileMm) << gamma;
    EXPECT_NEAR(c.at("ECC", r), 3e-6, kIsgFileRad) << gamma;
  }
  const auto& k = isg_block(blocks, "X0C");
  EXPECT_NEAR(k.at("X0C", 0), 0.006, kIsgFileMm);
  EXPECT_NEAR(k.at("C0Y", 0), 12e-6, kIsgFileRad);
  EXPECT_NEAR(k.at("A0Y", 0), -7e-6, kIsgFileRad);
  EXPECT_NEAR(k.at("B0Z", 0), -3e-6, kIsgFileRad);
  EXPECT_NEAR(k.at("B0A", 0), -9e-6, kIsgFileRad);
  EXPECT_NEAR(k.at("Y0C", 0), 0.0, kIsgFileMm);
}

TEST(IsgTable, NonEquidistantSourceIsResampledAndSaidSo) {
  // Knots at 0, 100, 250, 900 mm: not equidistant. The block is resampled every 10 mm from the table's spline
  // (a straight line here: 2 knots would be a line too; 4 knots on a line give the line exactly).
  const auto model = test::machine_with(isg_sources("x_mm,delta_xx_um\n0,0\n100,1\n250,2.5\n900,9\n"));
  const auto blocks = read_isg_csv(isg_text(compensation::make_isg_table(model)));
  const auto& x = isg_block(blocks, "X");
  expect_isg_equidistant(x);
  EXPECT_EQ(x.records.size(), 91u);
  EXPECT_NEAR(x.at("EXX", isg_row_at(x, 370.0)), 0.0037, kIsgFileMm); // 0.01 µm/mm · 370 mm
  const bool said = std::any_of(x.comments.begin(), x.comments.end(),
                                [](const std::string& c) { return c.find("RESAMPLED") != std::string::npos; });
  EXPECT_TRUE(said);
}

TEST(IsgTable, RefusesNonEquidistantAndTooLongTables) {
  compensation::IsgTable t;
  compensation::IsgBlock b;
  b.argument = "X";
  b.parameters = {"EXX"};
  b.arguments = {0.0, 10.0, 25.0};
  b.values = {{0.0}, {0.001}, {0.002}};
  t.blocks.push_back(b);
  std::ostringstream out;
  try {
    compensation::write_isg_table(out, t, {});
    FAIL() << "a non-equidistant block was written";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("block 1 'X EXX'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not equidistant"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(out.str().empty()); // nothing half-written

  t.blocks[0].arguments = {0.0, 10.0, 20.0};
  compensation::IsgLimits two;
  two.max_records = 2;
  try {
    compensation::write_isg_table(out, t, two);
    FAIL() << "3 records were written under max_records = 2";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_records = 2"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(compensation::write_isg_table(out, t, {}));

  // Sampling finer than the limit allows is refused before anything is sampled (0.001 mm over the 900 mm X stroke).
  compensation::IsgOptions fine;
  fine.linear_step_mm = 0.001;
  try {
    (void)compensation::make_isg_table(test::machine_with({ErrorSource::polynomial(ComponentId::delta_xx, {0.0, 0.01}, "um", "mm")}), fine);
    FAIL() << "900001 records were accepted under max_records = 2000";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_records = 2000"), std::string::npos) << e.what();
  }

  // A source table whose own equidistant grid is longer than the limit is refused at its file and column.
  std::string csv = "x_mm,delta_xx_um\n";
  for (int i = 0; i <= 90; ++i) csv += std::to_string(10 * i) + ",0.5\n";
  compensation::IsgOptions small;
  small.limits.max_records = 50;
  try {
    (void)compensation::make_isg_table(test::machine_with(isg_sources(csv)), small);
    FAIL() << "a 91-record table was accepted under max_records = 50";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "hand.csv");
    EXPECT_EQ(e.field(), "delta_xx_um"); // the column header
    EXPECT_NE(std::string(e.what()).find("max_records = 50"), std::string::npos) << e.what();
  }
}

TEST(IsgTable, PositionOnlyTableLeavesTheOrientationErrorsFlankDeviation) {
  // What a position-only table leaves, on the paper's gear (teeth 1 and 18).
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero(); // TCP at the wheel centre
  const auto left_after = [&](const machine::MachineModel& m) {
    const grinding::MachineProcess p(m, test::kDatumZ);
    const compensation::PositionCompensatedProcess left(p, centre);
    return grinding::largest_abs_deviation_um(test::simulate(left, grinding::Method::Exact));
  };
  const auto full = [&](const machine::MachineModel& m) {
    return grinding::largest_abs_deviation_um(test::simulate(grinding::MachineProcess(m, test::kDatumZ), grinding::Method::Exact));
  };

  // EXX-type: a pure translation. Without compensation the gear is off; after a position-only table nothing is left.
  const auto exx = test::machine_with({ErrorSource::polynomial(ComponentId::delta_xx, {8.0, 0.01}, "um", "mm")});
  EXPECT_GT(full(exx), 1.0);
  EXPECT_LT(left_after(exx), 0.01);

  // EBX-type: ε_yx = 20 µrad turns the X carriage about F's y through (x, 0, 0). The table moves the wheel centre back;
  // what remains is the same rotation about the wheel centre. Independently: Y's angular errors turn the wheel about
  // the A body's axes through the wheel centre, and F's y in the A body's axes is (0, cos α, −sin α) (A constant).
  const double eps_urad = 20.0;
  const auto ebx = test::machine_with({ErrorSource::constant(ComponentId::epsilon_yx, eps_urad, "urad")});
  const double alpha = test::paper_setup().path().point(1, 0.0).q.a;
  const auto about_centre = test::machine_with({ErrorSource::constant(ComponentId::epsilon_yy, eps_urad * std::cos(alpha), "urad"),
                                                ErrorSource::constant(ComponentId::epsilon_zy, -eps_urad * std::sin(alpha), "urad")});
  const double left = left_after(ebx);
  std::cout << "[ measured ] 20 µrad EBX-type left after the position-only table: " << left << " µm\n";
  EXPECT_NEAR(left, full(about_centre), 0.01);
  // Lever arm: no wheel point is farther from the centre than √(r_max² + v_max²); a rotation ε moves it by ≤ ε·that.
  const auto& w = test::paper_setup().wheel();
  const double r_max = *std::max_element(w.profile_r().begin(), w.profile_r().end());
  const double v_max = std::max(std::abs(w.v_min()), std::abs(w.v_max()));
  EXPECT_LE(left, eps_urad * 1e-6 * std::hypot(r_max, v_max) * 1e3 + 0.01);
  EXPECT_GT(left, 0.1); // and it is not nothing: the orientation error is not carried
}


TEST(IsgTable, CompensateWritesTheTableAndReportsWhatItLeaves) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_isg_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string scene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

  const auto ok = test::run_geartopo("compensate " + scene + " --out " + (dir / "comp").string() + " --isg-table", dir);
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.out.find("left after the table"), std::string::npos) << ok.out;
  std::ifstream in(dir / "comp" / "isg_compensation.csv");
  std::stringstream text;
  text << in.rdbuf();
  const auto blocks = read_isg_csv(text.str());
  ASSERT_EQ(blocks.size(), 6u);
  std::size_t records = 0;
  for (const auto& b : blocks) {
    records += b.records.size();
    if (b.header.front().size() == 1) expect_isg_equidistant(b);
  }
  EXPECT_LE(records, 2000u);
  const auto j = nlohmann::json::parse(std::ifstream(dir / "comp" / "iso1328.json"));
  EXPECT_EQ(j["isg_table"]["records"].get<std::size_t>(), records);
  const double left = j["isg_table"]["nominal_left_after_table"]["largest_abs_deviation_um"].get<double>();
  const double before = j["largest_abs_deviation_um"]["before"].get<double>();
  EXPECT_GT(left, 0.0); // the scene's machine has orientation errors
  EXPECT_LT(left, before);

  // A controller limit the table does not fit: refused, named, and nothing written.
  const auto refused = test::run_geartopo(
      "compensate " + scene + " --out " + (dir / "refused").string() + " --isg-table --isg-max-records 50", dir);
  EXPECT_EQ(refused.code, 1);
  EXPECT_NE(refused.err.find("max_records = 50"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "refused"));
  std::filesystem::remove_all(dir);
}

// --- another chain: the controller's view of the table, with 4×4 transforms written here ---------------------------

namespace {

using Htm = Eigen::Matrix4d;

Htm shift(const Eigen::Vector3d& p) {
  Htm m = Htm::Identity();
  m.block<3, 1>(0, 3) = p;
  return m;
}
Htm turn(int about, double t) {
  Htm m = Htm::Identity();
  m.block<3, 3>(0, 0) = Eigen::AngleAxisd(t, Eigen::Vector3d::Unit(about)).toRotationMatrix();
  return m;
}
/// The error motion of an ISO 230-1 parameter set: T(EX, EY, EZ)·Rx(EA)·Ry(EB)·Rz(EC).
Htm error_motion(const double e[6]) {
  return shift({e[0], e[1], e[2]}) * turn(0, e[3]) * turn(1, e[4]) * turn(2, e[5]);
}

/// A parameter of the table read as the controller reads it: linear interpolation in the block's argument (the
/// constants block: its one record); 0 when the table has no such parameter.
double parameter(const std::vector<IsgReadBlock>& blocks, const std::string& name, double argument) {
  for (const auto& b : blocks) {
    const int col = b.column(name);
    if (col < 0 || b.records.empty()) continue;
    if (b.records.size() == 1) return b.records[0][static_cast<std::size_t>(col)]; // the constants block
    const auto& r = b.records;
    std::size_t i = 0;
    while (i + 2 < r.size() && r[i + 1][0] <= argument) ++i;
    const double t = (argument - r[i][0]) / (r[i + 1][0] - r[i][0]);
    EXPECT_GE(t, -1e-9) << name << " at " << argument;
    EXPECT_LE(t, 1.0 + 1e-9) << name << " at " << argument;
    return (1.0 - t) * r[i][static_cast<std::size_t>(col)] + t * r[i + 1][static_cast<std::size_t>(col)];
  }
  return 0.0;
}

/// The wheel pose of `chain` at axis positions θ (pose order; mm, rad) as a controller builds it from the ISG table
/// (ISO 230-1/-7; the conventions of the table's comments): per axis from the workpiece, in its carrier's axes,
///   linear  M = T(o)·T(θ·d' + E_pos)·R(E_rot),  d' = d + ω × d, ω = (A0k, B0k, C0k) the line's orientation error
///   rotary  M = T(o)·S·T(E_pos)·R(E_rot)·R_d(θ + R0R)·S⁻¹ (E in the carrier's fixed axes; S the axis line's
///           offsets X0R… and tilts A0R…; the spindle that carries the gear without S⁻¹: the gear sits on its line)
/// and wMg = Π M_workpiece⁻¹ · Π M_tool. Only what the description (spec) and the table say.
Htm controller_wMg(const machine::KinematicChain& chain, const std::vector<IsgReadBlock>& blocks,
                   const machine::AxisValues& theta) {
  const auto& spec = chain.spec();
  Htm workpiece = Htm::Identity(), tool = Htm::Identity();
  const std::size_t n = spec.workpiece.size() + spec.tool.size();
  for (std::size_t i = 0; i < n; ++i) {
    const bool on_workpiece = i < spec.workpiece.size();
    const machine::AxisSpec& a = on_workpiece ? spec.workpiece[i] : spec.tool[i - spec.workpiece.size()];
    const machine::Axis slot = *chain.axis_named(a.name);
    const std::string& L = a.name;
    const bool rotary = a.kind == machine::AxisKind::Rotary;
    const double position = theta[slot];
    // Arguments in mm and deg; the spindle's block runs over [0, 360] deg, a swivel's over its stroke.
    const double deg = position * 180.0 / std::numbers::pi;
    const double arg = !rotary ? position : a.stroke ? deg : std::fmod(deg + 720.0, 360.0);
    double e[6];
    const char* dirs = "XYZABC";
    for (int k = 0; k < 6; ++k) e[k] = parameter(blocks, std::string("E") + dirs[k] + L, arg);
    Eigen::Index about = 0;
    a.direction.cwiseAbs().maxCoeff(&about);
    const double sign = a.direction(about) > 0 ? 1.0 : -1.0;
    Htm M;
    if (!rotary) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d(about) = sign;
      const Eigen::Vector3d omega(parameter(blocks, "A0" + L, 0), parameter(blocks, "B0" + L, 0),
                                  parameter(blocks, "C0" + L, 0));
      M = shift(a.offset_mm) * shift(position * (d + omega.cross(d))) * error_motion(e);
    } else {
      // The line's tilts about the two machine axes across it, in x, y, z order; the parameter about its own axis
      // (A0A, C0C) is its zero.
      double tilt[3] = {0.0, 0.0, 0.0};
      for (int c = 0; c < 3; ++c)
        if (c != about) tilt[c] = parameter(blocks, std::string(1, "ABC"[c]) + "0" + L, 0);
      const double zero = parameter(blocks, std::string(1, "ABC"[about]) + "0" + L, 0);
      const Htm S = shift({parameter(blocks, "X0" + L, 0), parameter(blocks, "Y0" + L, 0), parameter(blocks, "Z0" + L, 0)}) *
                    turn(0, tilt[0]) * turn(1, tilt[1]) * turn(2, tilt[2]);
      const bool carries_gear = on_workpiece && i == 0;
      M = shift(a.offset_mm) * S * error_motion(e) * turn(static_cast<int>(about), sign * (position + zero)) *
          (carries_gear ? Htm::Identity() : Htm(S.inverse()));
    }
    if (on_workpiece) workpiece = workpiece * M.inverse();
    else tool = tool * M;
  }
  return workpiece * tool;
}

/// Every component of `chain` that belongs to the axis in `slot` set to a constant of 1 … 3 µm or µrad (signs and sizes
/// varying), the rest zero: as a machine model and as the chain's error vector (mm, rad).
std::pair<machine::MachineModel, machine::ErrorVector> constant_errors_of_axis(const machine::KinematicChain& chain,
                                                                               machine::Axis slot) {
  std::vector<ErrorSource> sources;
  machine::ErrorVector e = machine::ErrorVector::Zero();
  int n = 0;
  for (int i = 0; i < machine::kComponentCount; ++i) {
    const auto& info = chain.info(machine::component_at(i));
    if (info.axis != slot) continue;
    const double v = (n % 2 == 0 ? 1.0 : -1.0) * (1.0 + 0.4 * (n % 6)); // µm or µrad
    ++n;
    const bool angle = info.quantity == machine::Quantity::Angle;
    sources.push_back(ErrorSource::constant(info.id, v, angle ? "urad" : "um"));
    e(i) = v * 1e-3 * (angle ? 1e-3 : 1.0);
  }
  EXPECT_GE(n, 6);
  return {test::machine_with(sources), e};
}

/// For every axis of `chain` alone with constant errors: the table written and read back; at a few settings (on the
/// tables' grid of whole degrees) the TCP (wheel centre) position error of the controller's model from the table equals
/// the chain's exact one to 1e-4 µm, and is more than 0.5 µm somewhere (else agreement proves nothing).
void expect_table_gives_the_chains_tcp_error(const machine::KinematicChain& chain) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  for (const machine::Axis slot : machine::kAxes) {
    const auto [model, e] = constant_errors_of_axis(chain, slot);
    const auto blocks = read_isg_csv(isg_text(compensation::make_isg_table(model, chain)));
    double largest_um = 0.0;
    for (const double gamma_deg : {17.0, 123.0, 250.0}) {
      const machine::AxisPose q{350.0 + gamma_deg / 10.0, 0.0, 300.0 + gamma_deg, 30.0 * kDeg, gamma_deg * kDeg};
      const machine::AxisValues theta = chain.axes(q);
      const Htm ideal = controller_wMg(chain, {}, theta);
      const Htm ctrl = controller_wMg(chain, blocks, theta);
      const Eigen::Vector3d controller_error = ctrl.block<3, 1>(0, 3) - ideal.block<3, 1>(0, 3);
      const Eigen::Vector3d chain_error =
          machine::actual_wMg(chain, e, theta).translation() - chain.ideal_wMg(theta).translation();
      EXPECT_LT((ideal.block<3, 1>(0, 3) - chain.ideal_wMg(theta).translation()).norm(), 1e-9) << "the ideal chains";
      EXPECT_LT((controller_error - chain_error).norm(), 1e-7)
          << chain.name() << " axis " << chain.axis(slot).name << " at γ " << gamma_deg << "°: controller "
          << 1e3 * controller_error.transpose() << " µm, chain " << 1e3 * chain_error.transpose() << " µm";
      largest_um = std::max(largest_um, 1e3 * chain_error.norm());
    }
    EXPECT_GT(largest_um, 0.5) << chain.name() << " axis " << chain.axis(slot).name;
  }
}

} // namespace

// A constant error of each axis of the CAFXZY (w → C → A → F → X → Z → Y → g: the C table on an A tilting table)
// written to its ISG table — the blocks in the chain's letters, the C and A errors turned into their carriers' fixed
// axes, the A line's location and the squareness named for its axes — and read back by the controller's model above
// puts the wheel centre where the chain's exact errors put it, to 1e-4 µm.
TEST(IsgTable, OnTheCafxzyTheTableGivesTheChainsTcpPositionError) {
  const auto& chain = *machine::chain_preset("CAFXZY");
  expect_table_gives_the_chains_tcp_error(chain);
  const auto [model, e] = constant_errors_of_axis(chain, machine::Axis::A);
  const auto text = isg_text(compensation::make_isg_table(model, chain));
  EXPECT_NE(text.find("chain CAXZY"), std::string::npos) << text.substr(0, 2000);
  EXPECT_NE(text.find("workpiece_axes 2"), std::string::npos);
}

// The same on the CXFZAY (w → C → X → F → Z → A → Y → g: the C table on a radial X slide moving along −x).
TEST(IsgTable, OnTheCxfzayTheTableGivesTheChainsTcpPositionError) {
  const auto& chain = *machine::chain_preset("CXFZAY");
  expect_table_gives_the_chains_tcp_error(chain);
  const auto [model, e] = constant_errors_of_axis(chain, machine::Axis::X);
  const auto text = isg_text(compensation::make_isg_table(model, chain));
  EXPECT_NE(text.find("chain CXZAY"), std::string::npos) << text.substr(0, 2000);
}

// ISG's model names its axes X, Y, Z, A, B, C (P-VOLC-00007): the CFXZAY's geometry with the radial slide called U
// (pose order Y, Z, U, B, C) cannot be written, and the refusal names the chain and the letter.
TEST(IsgTable, AChainLetterIsgHasNoNameForIsRefused) {
  using machine::AxisKind;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  constexpr double deg = std::numbers::pi / 180.0;
  const auto& chain = machine::make_chain(
      {"CFUZBY",
       {{"C", AxisKind::Rotary, z, Eigen::Vector3d::Zero(), std::nullopt}},
       {{"U", AxisKind::Linear, x, Eigen::Vector3d::Zero(), machine::Interval{0.0, 900.0}},
        {"Z", AxisKind::Linear, z, Eigen::Vector3d::Zero(), machine::Interval{0.0, 800.0}},
        {"B", AxisKind::Rotary, x, Eigen::Vector3d::Zero(), machine::Interval{-45 * deg, 45 * deg}},
        {"Y", AxisKind::Linear, y, Eigen::Vector3d::Zero(), machine::Interval{-200.0, 200.0}}}});
  try {
    compensation::make_isg_table(test::machine_with({}), chain);
    ADD_FAILURE() << "a chain with a U axis must be refused";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("CFUZBY"), std::string::npos) << what;
    EXPECT_NE(what.find("'U'"), std::string::npos) << what;
  }
}
