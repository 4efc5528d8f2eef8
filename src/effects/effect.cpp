#include "geartopo/effects/effect.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace geartopo::effects {

void Effect::set_values(std::vector<double> v) {
  if (v.size() != parameters().size())
    throw std::invalid_argument(fmt::format("{}: {} values for {} parameters", type(), v.size(), parameters().size()));
  values_ = std::move(v);
}

void Effect::wheel_radius_errors_mm(std::span<const double> v, std::span<const grinding::PathPoint> pp,
                                    std::span<double> out) const {
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = wheel_radius_error_mm(v[i], pp[i]);
}

size_t Effect::index_of(std::string_view key) const {
  const auto& p = parameters();
  for (size_t i = 0; i < p.size(); ++i)
    if (p[i].key == key) return i;
  throw std::out_of_range(fmt::format("effect {} has no parameter {}", type(), key));
}

void Effect::init_defaults() {
  values_.clear();
  for (const auto& p : parameters()) values_.push_back(p.default_value);
}

const grinding::GrindingSetup& Effect::setup() const {
  if (!setup_) throw std::logic_error(fmt::format("effect {} used before bind()", type()));
  return *setup_;
}

} // namespace geartopo::effects
