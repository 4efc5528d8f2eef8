// libFuzzer target: measurement::parse_klingelnberg and klingelnberg_points on arbitrary text, against the gear of the
// shipped example export (tests/measurement/data/klingelnberg_example.mka: m_n 2, z 24, β 15°). Documented: InputError
// (a std::runtime_error, "file:line:column: field: message"); accepted points are finite and on the flank.
#include "fuzz_common.hpp"

#include "geartopo/core/units.hpp"
#include "geartopo/measurement/klingelnberg.hpp"

#include <cstdint>
#include <string_view>

using namespace geartopo;

namespace {

const gears::GearGeometry& example_gear() {
  static const gears::GearGeometry g = [] {
    gears::GearSpec s;
    s.normal_module_mm = 2.0;
    s.teeth = 24;
    s.normal_pressure_angle_rad = 20.0 * units::kRadPerDeg;
    s.helix_angle_rad = 15.0 * units::kRadPerDeg;
    s.face_width_mm = 20.0;
    s.tip_diameter_mm = 53.6933;
    s.root_diameter_mm = 44.6933;
    return gears::GearGeometry(s);
  }();
  return g;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  fuzz::run_expecting<std::runtime_error>([&] {
    const auto file = measurement::parse_klingelnberg(text, "fuzz.mka");
    // values_um holds NaN for the export's undefined value by design: the points, not the raw values, must be finite.
    const auto& g = example_gear();
    for (const auto& p : measurement::klingelnberg_points(file, g).points) {
      fuzz::require_finite(p.deviation_um, "deviation_um");
      fuzz::require_finite(p.diameter_mm, "diameter_mm");
      fuzz::require_finite(p.z_mm, "z_mm");
      if (p.diameter_mm < g.root_form_diameter_mm() - 1e-3 || p.diameter_mm > g.tip_diameter_mm() + 1e-3)
        fuzz::finding("accepted a point off the flank", "diameter_mm");
    }
  });
  return 0;
}
