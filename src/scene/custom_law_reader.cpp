#include "custom_law_reader.hpp"

#include "geartopo/effects/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace geartopo::scene {
namespace {

/// The largest |bound| of a custom parameter: beyond 1e12 in any unit a value is a typing error, and the fit's
/// scaled units would lose the digits of a real value.
constexpr double kBoundLimit = 1e12;

effects::CustomParameter read_parameter(MapReader& params, const std::string& key) {
  MapReader p = params.map(key);
  effects::CustomParameter out;
  out.key = key;
  for (const char* bound : {"min", "max"})
    if (!p.has(bound))
      p.context().fail(p.mark(), p.field(bound),
                       fmt::format("missing: every parameter of your effect needs its bounds min and max (diagnose "
                                   "fits it within them) and its value and unit"));
  out.min = p.number("min", {-kBoundLimit, kBoundLimit});
  out.max = p.number("max", {-kBoundLimit, kBoundLimit});
  if (!(out.min < out.max)) p.context().fail_field(p.field("max"), fmt::format("{} is not above min = {}", out.max, out.min));
  out.value = p.number("value", {out.min, out.max});
  out.unit = p.text("unit");
  if (out.unit.empty()) p.context().fail_field(p.field("unit"), "empty: say the parameter's unit (e.g. um_per_mm, s)");
  p.finish();
  return out;
}

/// The expression's own error located in the file: at the character at fault when the expression stands on one line
/// (the quote, if any, skipped), else at the field.
[[noreturn]] void fail_in_expression(MapReader& m, const YAML::Node& node, const std::string& expression,
                                     const effects::ExpressionError& e) {
  const std::string field = m.field("deviation_um");
  const auto pos = static_cast<std::size_t>(e.position());
  const std::string shown = expression.substr(0, pos) + " ⟨here⟩ " + expression.substr(std::min(pos, expression.size()));
  const std::string message = fmt::format("{}: {}", e.what(), shown);
  YAML::Mark mark = node.Mark();
  if (expression.find('\n') == std::string::npos && !mark.is_null()) {
    const bool quoted = node.Tag() == "!";
    mark.column += static_cast<int>(pos) + (quoted ? 1 : 0);
  }
  m.context().fail(mark, field, message);
}

} // namespace

std::shared_ptr<const effects::CustomLaw> read_custom_law(MapReader& m, const Scene& scene) {
  const std::string name = m.text("name");
  const auto& library = effects::effect_types();
  if (std::find(library.begin(), library.end(), name) != library.end())
    m.context().fail_field(m.field("name"), fmt::format("'{}' is an effect of the library (list it under effects); "
                                                        "give your own effect another name",
                                                        name));
  for (const auto& other : scene.custom_effects)
    if (other == name) m.context().fail_field(m.field("name"), fmt::format("'{}' is listed twice", name));
  std::vector<effects::CustomParameter> params;
  MapReader pm = m.map("parameters");
  for (const auto& key : pm.keys()) params.push_back(read_parameter(pm, key));
  pm.finish();
  int dressing = 0;
  if (m.has("dressing_interval_strokes")) dressing = static_cast<int>(m.integer("dressing_interval_strokes", 0, 100000));
  std::shared_ptr<const effects::CustomLaw> law;
  if (m.has("python")) {
    // A law given as a Python function (geartopo.custom_effect, docs/python.md): registered under its name by the
    // process that made it; the entry gives its parameters' values and bounds as any entry does.
    const std::string function = m.text("python");
    const auto registered = effects::find_custom_law(name);
    if (!registered || !registered->function())
      m.context().fail_field(m.field("python"),
                             fmt::format("'{}' is a law given as the Python function {}: only the Python process that "
                                         "made it by geartopo.custom_effect(...) can use this scene",
                                         name, function));
    try {
      law = std::make_shared<const effects::CustomLaw>(name, std::move(params), registered->function(), function,
                                                       dressing);
      effects::register_custom_law(law);
    } catch (const std::invalid_argument& e) {
      m.context().fail_field(m.field("parameters"), e.what());
    }
    return law;
  }
  const std::string expression = m.text("deviation_um");
  const YAML::Node node = m.raw("deviation_um");
  try {
    law = std::make_shared<const effects::CustomLaw>(name, std::move(params), expression, dressing);
  } catch (const effects::ExpressionError& e) {
    fail_in_expression(m, node, expression, e);
  } catch (const std::invalid_argument& e) {
    m.context().fail_field(m.field("parameters"), e.what());
  }
  try {
    effects::register_custom_law(law);
  } catch (const std::invalid_argument& e) {
    m.context().fail_field(m.field("name"), e.what());
  }
  return law;
}

} // namespace geartopo::scene
