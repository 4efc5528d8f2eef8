// Replays the broken-input corpus (corpus/<folder>/*, made by corpus/make_corpus.py). Every file must be refused by
// the public reader with a clear exception: the expected type, a message that names the file (and the line, where
// <folder>/expected.tsv gives one) and contains the expected fragment. Never a crash, a hang (ctest TIMEOUT) or an
// accepted NaN (a file that loads is a failure).
//
// Readers: scenes → workbench::Workbench (reads the scene, builds and checks the set-up); error_tables → machine::load_error_tables; topology → grinding::read_topology_csv
// (traces_* → grinding::read_traces_csv) and measurement::read_measurement; point_clouds → surfaces::read_point_cloud;
// topology and point clouds also through measurement::read_any_measurement (tells the two apart by the header);
// shards → pipeline::read_run_csv, then pipeline::merge_runs with shards/reference/part_1_of_2.csv (what `geartopo
// merge` does); exports → measurement::read_klingelnberg; predictions → report::read_prediction_json (what `evaluate
// --prediction` reads).
#include "robustness_support.hpp"

#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/machine/error_table.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"
#include "geartopo/surfaces/point_cloud.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>

using namespace geartopo;
using namespace geartopo::robustness;
namespace fs = std::filesystem;

namespace {

constexpr const char* kFolders[] = {"scenes", "error_tables", "topology", "point_clouds", "shards", "exports", "predictions"};

struct CorpusCase {
  std::string folder, file;
  std::string exception; ///< InputError, runtime_error, invalid_argument
  int line = -1;         ///< expected line; 0: the message must not name a line; -1: any
  std::string fragment;  ///< must occur in what()
  std::string note;      ///< printed on failure (e.g. a known finding)
};

std::vector<CorpusCase> read_expected(const std::string& folder) {
  std::vector<CorpusCase> out;
  std::ifstream in(kCorpus / folder / "expected.tsv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, '\t');) f.push_back(x);
    f.resize(5);
    out.push_back({folder, f[0], f[1], std::stoi(f[2]), f[3], f[4]});
  }
  return out;
}

std::vector<CorpusCase> all_cases() {
  std::vector<CorpusCase> out;
  for (const char* folder : kFolders)
    for (auto& c : read_expected(folder)) out.push_back(std::move(c));
  return out;
}

// The line named right after `file:` in a message, 0 if none.
int line_after(const std::string& what, const std::string& file) {
  const auto at = what.find(file + ":");
  if (at == std::string::npos) return 0;
  const auto b = at + file.size() + 1;
  size_t e = b;
  while (e < what.size() && std::isdigit(static_cast<unsigned char>(what[e]))) ++e;
  return e > b ? std::stoi(what.substr(b, e - b)) : 0;
}

struct Caught {
  std::string type, what;
  int line = -1; ///< from the exception object when it carries one
};

// Runs fn and reports what it threw ("" when it returned: the file was accepted).
Caught catch_from(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const geartopo::InputError& e) {
    return {"InputError", e.what(), e.line()};
  } catch (const std::invalid_argument& e) {
    return {"invalid_argument", e.what()};
  } catch (const std::runtime_error& e) {
    return {"runtime_error", e.what()};
  } catch (const std::exception& e) {
    return {std::string("unexpected std::exception: ") + typeid(e).name(), e.what()};
  } catch (...) {
    return {"unexpected non-std exception", ""};
  }
  return {};
}

// Does the message name this file and carry the expected line and fragment?
void check_message(const CorpusCase& c, const Caught& got, const std::string& reader, bool check_type = true) {
  SCOPED_TRACE(reader + " on " + c.folder + "/" + c.file + (c.note.empty() ? "" : "  NOTE: " + c.note));
  ASSERT_FALSE(got.type.empty()) << "accepted: the file loaded without an exception";
  if (check_type) {
    EXPECT_EQ(got.type, c.exception) << got.what;
  } else {
    EXPECT_TRUE(got.type == "InputError" || got.type == "runtime_error" ||
                got.type == "invalid_argument")
        << got.type << ": " << got.what;
  }
  // A scene that refers to a broken table is reported at the table: the fragment names that file.
  const bool names_other = c.folder == "scenes" && c.fragment.size() > 4 && c.fragment.ends_with(".csv");
  const std::string named = names_other ? c.fragment : c.file;
  EXPECT_NE(got.what.find(named), std::string::npos) << "the message does not name " << named << ": " << got.what;
  EXPECT_NE(got.what.find(c.fragment), std::string::npos) << "expected '" << c.fragment << "' in: " << got.what;
  const int line = got.line >= 0 ? got.line : line_after(got.what, named);
  if (c.line > 0 && !names_other) {
    EXPECT_EQ(line, c.line) << got.what;
  }
  if (c.line == 0) {
    EXPECT_EQ(line, 0) << got.what;
  }
}

// Readable parameter in failure messages (instead of a byte dump).
[[maybe_unused]] void PrintTo(const CorpusCase& c, std::ostream* os) { *os << c.folder << "/" << c.file; }

class Corpus : public ::testing::TestWithParam<CorpusCase> {};

} // namespace

TEST_P(Corpus, IsRefusedWithAClearMessage) {
  const CorpusCase& c = GetParam();
  const fs::path path = kCorpus / c.folder / c.file;
  ASSERT_TRUE(fs::exists(path)) << path;
  if (c.folder == "scenes") {
    check_message(c, catch_from([&] { const workbench::Workbench wb(path); }), "workbench::Workbench");
  } else if (c.folder == "error_tables") {
    if (c.file == "x_short.csv") { // valid on its own; the scene refuses it for not covering the X stroke
      EXPECT_NO_THROW((void)machine::load_error_tables(path));
      return;
    }
    check_message(c, catch_from([&] { (void)machine::load_error_tables(path); }), "machine::load_error_tables");
  } else if (c.folder == "topology") {
    const auto& g = default_scene().setup.geometry();
    if (c.file.starts_with("traces_")) {
      check_message(c, catch_from([&] { (void)grinding::read_traces_csv(path, g.teeth()); }), "grinding::read_traces_csv");
      return;
    }
    if (c.file != "off_the_flank.csv")
      check_message(c, catch_from([&] { (void)grinding::read_topology_csv(path, g.teeth()); }),
                    "grinding::read_topology_csv");
    check_message(c, catch_from([&] { (void)measurement::read_measurement(path.string(), g); }),
                  "measurement::read_measurement");
    check_message(c, catch_from([&] { (void)measurement::read_any_measurement(path.string(), default_scene().setup); }),
                  "measurement::read_any_measurement", false);
  } else if (c.folder == "point_clouds") {
    check_message(c, catch_from([&] { (void)surfaces::read_point_cloud(path); }), "surfaces::read_point_cloud");
    // Through the measurement front end the header decides the format; the file must still be refused clearly.
    const Caught any = catch_from([&] { (void)measurement::read_any_measurement(path.string(), default_scene().setup); });
    SCOPED_TRACE("measurement::read_any_measurement");
    ASSERT_FALSE(any.type.empty()) << "accepted";
    EXPECT_NE(any.what.find(c.file), std::string::npos) << any.what;
  } else if (c.folder == "shards") {
    // Refused by the reader, or else by the merge with shard 1 of the same run: either way naming the file.
    check_message(c, catch_from([&] {
                    std::vector<pipeline::MonteCarloRun> parts;
                    parts.push_back(pipeline::read_run_csv(kCorpus / "shards/reference/part_1_of_2.csv"));
                    parts.push_back(pipeline::read_run_csv(path));
                    (void)pipeline::summarise(pipeline::merge_runs(std::move(parts)));
                  }),
                  "pipeline::read_run_csv + merge_runs");
  } else if (c.folder == "exports") {
    check_message(c, catch_from([&] { (void)measurement::read_klingelnberg(path.string()); }), "measurement::read_klingelnberg");
  } else if (c.folder == "predictions") {
    check_message(c, catch_from([&] { (void)report::read_prediction_json(path); }), "report::read_prediction_json");
  } else {
    FAIL() << "unknown corpus folder " << c.folder;
  }
}

INSTANTIATE_TEST_SUITE_P(Files, Corpus, ::testing::ValuesIn(all_cases()), [](const auto& info) {
  std::string name = info.param.folder + "_" + info.param.file;
  std::replace_if(name.begin(), name.end(), [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)); }, '_');
  return name;
});

// The valid twins the shard and export cases are made from are read and merged: a case is refused for what it
// changes, not because its reference is broken.
TEST(CorpusReferences, AreAccepted) {
  auto first = pipeline::read_run_csv(kCorpus / "shards/reference/part_1_of_2.csv");
  EXPECT_EQ(first.scene_fingerprint, "0123456789abcdef");
  pipeline::MonteCarloRun second = first;
  for (auto& s : second.samples) s.index += 2;
  const auto file = temp_path("part_2_of_2.csv");
  pipeline::write_run_csv(file, second);
  std::vector<pipeline::MonteCarloRun> parts{first, pipeline::read_run_csv(file)};
  const auto merged = pipeline::merge_runs(std::move(parts));
  EXPECT_EQ(merged.samples.size(), 4u);
  EXPECT_EQ(merged.scene_fingerprint, "0123456789abcdef");
  EXPECT_NO_THROW((void)pipeline::summarise(merged));
  fs::remove(file);
  const auto k = measurement::read_klingelnberg((kCorpus / "exports/reference/good.mka").string());
  EXPECT_EQ(k.traces.size(), 3u);
  const auto p = report::read_prediction_json(kCorpus / "predictions/reference/good.json");
  ASSERT_EQ(p.names.size(), 2u);
  ASSERT_GE(p.find("F_alpha_um"), 0);
  EXPECT_EQ(p.after[static_cast<size_t>(p.find("F_alpha_um"))].median, 3.25);
  EXPECT_EQ(p.gear, pipeline::gear_record(default_scene().setup.geometry().spec())); // the default scene's gear
  EXPECT_NO_THROW((void)report::read_prediction_json(kCorpus / "predictions/reference/other_gear.json"));
}

// Every corpus file has a row in expected.tsv (and every row a file): a new file cannot slip in untested.
TEST(CorpusIndex, EveryFileHasAnExpectation) {
  for (const char* folder : kFolders) {
    std::set<std::string> listed, present;
    for (const auto& c : read_expected(folder)) EXPECT_TRUE(listed.insert(c.file).second) << folder << "/" << c.file << " listed twice";
    for (const auto& e : fs::directory_iterator(kCorpus / folder)) // sub-folders hold valid inputs the cases refer to
      if (e.is_regular_file() && e.path().filename() != "expected.tsv") present.insert(e.path().filename().string());
    EXPECT_EQ(listed, present) << folder;
    EXPECT_GE(present.size(), 15u) << folder;
  }
}
