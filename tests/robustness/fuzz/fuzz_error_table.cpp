// libFuzzer target: machine::parse_error_tables on arbitrary text. Documented: throws geartopo::InputError only; an accepted
// table gives finite values on its range (a value near 1e308 may
// overflow in the spline: that is reported as a finding too, a table should refuse values beyond any physical range).
#include "fuzz_common.hpp"

#include "geartopo/machine/error_table.hpp"

#include <cstdint>
#include <string_view>

using namespace geartopo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  fuzz::run_expecting<geartopo::InputError>([&] {
    for (const auto& src : machine::parse_error_tables(text, "fuzz.csv")) {
      // Sample the spline on its own range (mm or rad inside); values may be huge but must stay finite.
      const auto* sp = src.spline();
      if (!sp) fuzz::finding("a table column that is not a table", "");
      for (int k = 0; k <= 16; ++k) {
        const double q = sp->front() + (sp->back() - sp->front()) * k / 16.0;
        fuzz::require_finite(q, "table position");
        fuzz::require_finite(src.value(q), "table value");
      }
    }
  });
  return 0;
}
