// geartopo tests — measured traces written as a gear measuring machine exports them, from the documented structure of
// the Klingelnberg-style export (docs/measurement-formats.md), not by `geartopo synth`: header lines 21/22 and the
// measuring ranges da/de, ba/be; per flank "Profil:" traces at axial heights z= and "Flankenlinie:" traces at diameters
// d=, each with its values evenly spaced over the measuring range (profile: in roll length from da to de; helix: in z
// from ba to be); transverse values in the raw sign (DIN sign × −1 for left profiles and for every helix trace);
// −2147483.648 for a value not measured. The gear is the default scene's with an ideal machine (no error tables), so
// the model is the design and the residual is what the file says, along the normal.
// Units: mm, µm, rad.
#pragma once

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace trace_fixture {

using namespace geartopo;

inline const std::string kDefaultScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

/// The default scene's text without the machine's error tables and constants (an ideal machine grinds the design),
/// with extra_gear_keys (indented YAML lines) added to its gear.
inline std::string ideal_scene_text(const std::string& extra_gear_keys = "") {
  std::ifstream in(kDefaultScene);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  text = std::regex_replace(text, std::regex("  tables: \\[[^\\]]*\\]\\n"), "");
  text = std::regex_replace(text, std::regex("  constants:[^\\n]*\\n(    [^\\n]*\\n)+"), "");
  text = std::regex_replace(text, std::regex("  measured: demo/measured.csv\\n"), "");
  text.insert(text.find("gear:\n") + 6, extra_gear_keys);
  return text;
}

inline const workbench::Workbench& ideal_workbench() {
  static const workbench::Workbench wb(scene::parse_scene(ideal_scene_text(), kDefaultScene));
  return wb;
}

/// What is measured: lines per flank and their positions.
struct Layout {
  std::vector<int> teeth{1, 18};
  std::vector<double> profile_z_mm;     ///< one profile trace per entry
  std::vector<double> helix_d_mm;       ///< one helix trace per entry (diameter)
  int profile_points = 200, helix_points = 300;
  std::set<std::pair<std::size_t, int>> undefined; ///< (trace number in the file, value index): not measured
};

/// Normal deviation (µm, DIN sign: plus material positive) at (flank, tooth, ξ, z).
using Truth = std::function<double(Flank, int tooth, double xi_mm, double z_mm)>;

struct Export {
  std::string text;
  std::size_t values = 0, undefined = 0; ///< values written, of them undefined
};

/// The export text. Profile range da = d_Ff … de = d_a, helix range 0 … b: both beyond the evaluation ranges.
inline Export write_export(const gears::GearGeometry& g, const Layout& l, const Truth& truth) {
  Export e;
  const double da = g.root_form_diameter_mm(), de = g.tip_diameter_mm(), b = g.spec().face_width_mm;
  const double xa = g.roll_length_at(da), xe = g.roll_length_at(de), cos_bb = std::cos(g.base_helix_angle());
  std::string& t = e.text;
  t += "HEADER KS.MK.FILE\n";
  t += fmt::format("  21 :Normalmodul mn [mm]...............: {:.4f}\n", g.spec().normal_module_mm);
  t += fmt::format("  22 :Zähnezahl z.......................: {}\n", g.spec().teeth);
  t += fmt::format("  41 :Start Messbereich.....da [mm].....: {:.6f} {:.6f}\n", da, da);
  t += fmt::format("  44 :Ende der Messstrecke..de [mm].....: {:.6f} {:.6f}\n", de, de);
  t += fmt::format("  61 :Messanfang............ba [mm].....: {:.6f} {:.6f}\n", 0.0, 0.0);
  t += fmt::format("  64 :Messende..............be [mm].....: {:.6f} {:.6f}\n", b, b);
  std::size_t trace = 0;
  const auto values = [&](int n, const std::function<double(int)>& normal_um, double raw_sign) {
    for (int i = 0; i < n; ++i) {
      const bool missing = l.undefined.count({trace, i}) > 0;
      const double v = missing ? -2147483.648 : raw_sign * normal_um(i) / cos_bb;
      t += fmt::format(" {:.4f}{}", v, (i + 1) % 10 == 0 || i + 1 == n ? "\n" : "");
      ++e.values;
      e.undefined += missing;
    }
    ++trace;
  };
  for (const int tooth : l.teeth)
    for (const Flank side : {Flank::Left, Flank::Right}) {
      const char* name = side == Flank::Left ? "links" : "rechts";
      for (const double z : l.profile_z_mm) {
        t += fmt::format("Profil:  Zahn-Nr.: {} {} / {} Werte / z= {:.4f}\n", tooth, name, l.profile_points, z);
        const int n = l.profile_points;
        values(n, [&](int i) { return truth(side, tooth, xa + (xe - xa) * i / (n - 1), z); }, side == Flank::Left ? -1.0 : 1.0);
      }
      for (std::size_t k = 0; k < l.helix_d_mm.size(); ++k) {
        const double d = l.helix_d_mm[k], xi = g.roll_length_at(d);
        t += fmt::format("Flankenlinie: Zahn-Nr.: {} {} / {} Werte / d= {:.4f}\n", tooth, name, l.helix_points, d);
        const int n = l.helix_points;
        values(n, [&](int i) { return truth(side, tooth, xi, b * i / (n - 1)); }, -1.0);
      }
    }
  return e;
}

/// A file in a fresh temporary folder (removed with the object).
struct TempFile {
  std::filesystem::path dir, path;
  TempFile(const std::string& name, const std::string& text) {
    static int counter = 0;
    dir = std::filesystem::temp_directory_path() / fmt::format("geartopo_trace_fixture_{}_{}", ::getpid(), counter++);
    std::filesystem::create_directories(dir);
    path = dir / name;
    std::ofstream(path) << text;
  }
  TempFile(const TempFile&) = delete; // one owner removes the folder
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() { std::filesystem::remove_all(dir); }
};

} // namespace trace_fixture
