// libFuzzer target: surfaces::read_point_cloud on arbitrary text. Documented: std::runtime_error naming
// source:line:column; accepted points are finite.
#include "fuzz_common.hpp"

#include "geartopo/surfaces/point_cloud.hpp"

#include <cstdint>
#include <sstream>

using namespace geartopo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::run_expecting<std::runtime_error>([&] {
    std::istringstream in(text);
    for (const auto& p : surfaces::read_point_cloud(in, "fuzz.csv"))
      for (int k = 0; k < 3; ++k) fuzz::require_finite(p.position_mm[k], "position");
  });
  return 0;
}
