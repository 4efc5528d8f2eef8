// geartopo tests — the small gear the kinematic-chain tests grind (m_n 4 mm, z 31, β 15° right, b 40 mm), what they
// ask of a workbench built from a scene text (the input error it refuses with, or the grid deviations it grinds), and
// a shipped scene's text with a line inserted or its constants replaced.
// Shared by tests/scene/test_scene_chain.cpp, tests/workbench/test_{chain_names,workbench_chain}.cpp and
// tests/app/test_cli_chain.cpp.
// Units: mm, µm, deg (as the scene keys say).
#pragma once

#include "geartopo/core/input_error.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace geartopo::chain_fixture {

/// The gear block of the scene (no wheel, no machine).
inline const std::string kGear = R"(gear:
  normal_module_mm: 4
  teeth: 31
  normal_pressure_angle_deg: 20
  helix_angle_deg: 15
  hand: right
  profile_shift: 0
  face_width_mm: 40
)";

/// kGear with a 300 mm wheel: a complete scene on the default (CFXZAY) chain.
inline const std::string kGearAndWheel = kGear + "wheel:\n  outer_diameter_mm: 300\n";

/// The InputError message a workbench built from `text` refuses with, or "(no error)".
inline std::string workbench_error_of(const std::string& text, const std::string& source = "scenes/x.yaml") {
  try {
    const workbench::Workbench wb(scene::parse_scene(text, source));
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

/// The grid deviations of teeth 1 and 16, both flanks (exact method, 5×5 grid), in order (µm).
inline std::vector<double> grid_deviations(const workbench::Workbench& wb) {
  grinding::SimulationOptions so;
  so.teeth = {1, 16};
  so.rows = 5, so.cols = 5, so.profile_points = 2, so.helix_points = 2;
  std::vector<double> out;
  for (const auto& flank : grinding::simulate_topology(wb.setup, wb.process(), so))
    for (const auto& p : flank.grid) out.push_back(p.deviation_um);
  return out;
}

/// The text of a file (a shipped scene); empty if it cannot be read.
inline std::string text_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

enum class Where { Before, After };

/// `text` with `line` (ending in a newline) inserted just before or just after the first `anchor`; empty when `text`
/// has no `anchor` (the caller's ASSERT then says so).
inline std::string with_line(const std::string& text, const std::string& anchor, const std::string& line, Where where) {
  const auto at = text.find(anchor);
  if (at == std::string::npos) return {};
  const auto cut = where == Where::Before ? at : at + anchor.size();
  return text.substr(0, cut) + line + text.substr(cut);
}

/// A scene's text with its `machine.constants` map replaced by `constants` (a YAML flow map); empty when it has none
/// (the map must be followed by the `wheel:` block, as in the shipped scenes).
inline std::string with_constants(const std::string& text, const std::string& constants) {
  const auto from = text.find("  constants:");
  const auto to = text.find("\nwheel:");
  if (from == std::string::npos || to == std::string::npos || to < from) return {};
  return text.substr(0, from) + "  constants: " + constants + "\n" + text.substr(to);
}

} // namespace geartopo::chain_fixture
