#include "geartopo/effects/registry.hpp"

#include "effect_list.hpp"

#include "geartopo/effects/custom_effect.hpp"

#include <stdexcept>

namespace geartopo::effects {

#define GEARTOPO_DECLARE(name) std::unique_ptr<Effect> make_##name();
GEARTOPO_EFFECT_LIST(GEARTOPO_DECLARE)
#undef GEARTOPO_DECLARE

namespace {
struct Entry {
  std::string type;
  std::unique_ptr<Effect> (*make)();
};
const std::vector<Entry>& entries() {
#define GEARTOPO_ENTRY(name) Entry{#name, &make_##name},
  static const std::vector<Entry> e{GEARTOPO_EFFECT_LIST(GEARTOPO_ENTRY)};
#undef GEARTOPO_ENTRY
  return e;
}
} // namespace

const std::vector<std::string>& effect_types() {
  static const std::vector<std::string> types = [] {
    std::vector<std::string> t;
    for (const auto& e : entries()) t.push_back(e.type);
    return t;
  }();
  return types;
}

std::unique_ptr<Effect> make_effect(std::string_view type) {
  for (const auto& e : entries())
    if (e.type == type) return e.make();
  if (auto law = find_custom_law(type)) return make_custom_effect(std::move(law));
  return nullptr;
}

std::unique_ptr<Effect> make_effect(std::string_view type, std::vector<double> values, const grinding::GrindingSetup& setup) {
  auto e = make_effect(type);
  if (!e) throw std::invalid_argument("unknown effect type '" + std::string(type) + "'");
  e->set_values(std::move(values));
  e->bind(setup);
  return e;
}

bool is_custom_effect(std::string_view type) {
  for (const auto& e : entries())
    if (e.type == type) return false;
  return find_custom_law(type) != nullptr;
}

} // namespace geartopo::effects
