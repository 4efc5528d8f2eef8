// libFuzzer target: scene::parse_scene on arbitrary text. Documented: throws geartopo::InputError only; an accepted scene has
// finite numbers. Inputs naming table files are skipped (a table path could name /dev/zero or a FIFO: the error
// tables have their own target).
#include "fuzz_common.hpp"

#include "geartopo/scene/scene.hpp"

#include <cstdint>
#include <string>

using namespace geartopo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (text.find("tables") != std::string::npos) return -1; // not added to the corpus
  fuzz::run_expecting<geartopo::InputError>([&] {
    const scene::Scene s = scene::parse_scene(text, "/nonexistent/fuzz.yaml");
    fuzz::require_finite(s.gear.normal_module_mm, "gear.normal_module_mm");
    fuzz::require_finite(s.gear.helix_angle_rad, "gear.helix_angle");
    fuzz::require_finite(s.gear.profile_shift, "gear.profile_shift");
    fuzz::require_finite(s.gear.face_width_mm, "gear.face_width_mm");
    fuzz::require_finite(s.gear.tip_diameter_mm, "gear.tip_diameter_mm");
    fuzz::require_finite(s.gear.root_diameter_mm, "gear.root_diameter_mm");
    fuzz::require_finite(s.machine.datum_face_z_mm, "machine.datum_face_z_mm");
    fuzz::require_finite(s.wheel.outer_diameter_mm, "wheel.outer_diameter_mm");
    for (const auto& e : s.effects)
      for (double v : e.values) fuzz::require_finite(v, "effect parameter");
    if (static_cast<long long>(s.grid.dense_rows) * s.grid.dense_cols > 4'000'000) fuzz::finding("huge dense grid", "");
  });
  return 0;
}
