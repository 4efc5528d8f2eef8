// geartopo diagnosis, private — the hypothesis families diagnose tries beyond the library, one registration line each
// (docs/adding-an-effect.md, "Adding a hypothesis family"). The order is the listing order of hypotheses whose ΔBIC
// ties, component by component (a component's laws in this order), then the wheel's.
#pragma once

#include "geartopo/diagnosis/hypothesis_family.hpp"

#include <memory>

#define GEARTOPO_HYPOTHESIS_FAMILY_LIST(X) \
  X(component_constant)                    \
  X(component_linear_in_time)              \
  X(component_steady_state)                \
  X(component_periodic)                    \
  X(wheel_flank_profile)                   \
  X(wheel_flank_waviness)                  \
  X(wheel_profile_wear)

namespace geartopo::diagnosis::families {
#define GEARTOPO_DECLARE_FAMILY(name) std::shared_ptr<const HypothesisFamily> make_##name();
GEARTOPO_HYPOTHESIS_FAMILY_LIST(GEARTOPO_DECLARE_FAMILY)
#undef GEARTOPO_DECLARE_FAMILY
} // namespace geartopo::diagnosis::families
