// Internal: the names of the quantities a Monte Carlo sample records (gear_quantities, monte_carlo.hpp) and what
// each can physically be: the check read_run_csv makes on every value of a shard.
#pragma once

#include "geartopo/evaluation/gear_evaluation.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::pipeline::detail {

/// The quantity's name in a file's header: "f_Halpha", "F_beta", … (ASCII).
std::string_view ascii_name(evaluation::Quantity q);

struct QuantityRule {
  enum class Kind { IsoClass, Magnitude, Signed } kind;
  /// "" when v is allowed; else why not (follows the value in the message).
  std::string refusal(double v) const;
};

/// The rule of a quantity geartopo writes; nullopt for any other name.
std::optional<QuantityRule> rule_of(const std::string& name);
/// Every name geartopo writes, for messages.
std::vector<std::string> known_quantity_names();

} // namespace geartopo::pipeline::detail
