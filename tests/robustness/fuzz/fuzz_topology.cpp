// libFuzzer target: grinding::read_topology_csv and read_traces_csv on arbitrary text. Documented: std::runtime_error
// "file:line:column: field: message"; accepted rows are finite.
#include "fuzz_common.hpp"

#include "geartopo/grinding/topology_csv.hpp"

#include <cstdint>
#include <sstream>

using namespace geartopo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::run_expecting<std::runtime_error>([&] {
    std::istringstream in(text);
    for (const auto& r : grinding::read_topology_csv(in, "fuzz.csv", 35)) {
      fuzz::require_finite(r.diameter_mm, "diameter_mm");
      fuzz::require_finite(r.z_mm, "z_mm");
      fuzz::require_finite(r.deviation_um, "deviation_um");
    }
  });
  fuzz::run_expecting<std::runtime_error>([&] {
    std::istringstream in(text);
    for (const auto& ft : grinding::read_traces_csv(in, "fuzz.csv", 35))
      for (const auto* trace : {&ft.profile, &ft.helix})
        for (const auto& p : *trace) fuzz::require_finite(p.deviation_um, "trace deviation_um");
  });
  return 0;
}
