// geartopo scene — the machine's kinematic chain (chain_reader.hpp). File units: mm, deg.
#include "chain_reader.hpp"

#include "geartopo/core/text_field.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/files/input_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>

namespace geartopo::scene {
namespace {

/// A list of three finite numbers (a direction or an offset), located at `key` when it is not.
Eigen::Vector3d read_vector(MapReader& m, const std::string& key, const Eigen::Vector3d& fallback) {
  if (!m.has(key)) return fallback;
  const auto items = m.optional_text_list(key);
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  bool ok = items.size() == 3;
  for (std::size_t i = 0; ok && i < 3; ++i)
    ok = text::parse_number(items[i], v(static_cast<Eigen::Index>(i))) == std::errc() &&
         std::isfinite(v(static_cast<Eigen::Index>(i)));
  if (!ok) m.context().fail_field(m.field(key), "expected [x, y, z], three finite numbers");
  return v;
}

/// The stroke of one axis: `stroke_mm` (linear) or `stroke_deg` (rotary), [min, max]; none when absent.
std::optional<machine::Interval> read_stroke(MapReader& m, const std::string& key, double scale) {
  if (!m.has(key)) return std::nullopt;
  const auto items = m.optional_text_list(key);
  machine::Interval iv{};
  bool ok = items.size() == 2 && text::parse_number(items[0], iv.min) == std::errc() &&
            text::parse_number(items[1], iv.max) == std::errc() && std::isfinite(iv.min) && std::isfinite(iv.max) &&
            iv.min < iv.max;
  if (!ok) m.context().fail_field(m.field(key), "expected [min, max] with min < max, two finite numbers");
  return machine::Interval{iv.min * scale, iv.max * scale};
}

machine::AxisSpec read_axis(MapReader& a) {
  machine::AxisSpec s;
  s.name = a.text("name");
  const auto kind = a.optional_choice("kind", {"linear", "rotary"});
  if (!kind) a.context().fail(a.mark(), a.field("kind"), "missing (linear or rotary)");
  s.kind = *kind == "rotary" ? machine::AxisKind::Rotary : machine::AxisKind::Linear;
  s.direction = read_vector(a, "direction", Eigen::Vector3d::Zero());
  if (!a.has("direction")) a.context().fail(a.mark(), a.field("direction"), "missing ([x, y, z] in its parent frame)");
  s.offset_mm = read_vector(a, "offset_mm", Eigen::Vector3d::Zero());
  const bool rotary = s.kind == machine::AxisKind::Rotary;
  const std::string other = rotary ? "stroke_mm" : "stroke_deg";
  if (a.has(other))
    a.context().fail_field(a.field(other), fmt::format("a {} axis' stroke is in {}", rotary ? "rotary" : "linear",
                                                       rotary ? "deg: stroke_deg" : "mm: stroke_mm"));
  s.stroke = read_stroke(a, rotary ? "stroke_deg" : "stroke_mm", rotary ? units::kRadPerDeg : 1.0);
  a.finish();
  return s;
}

/// One side's list of axes (`workpiece` or `tool`), each a map.
std::vector<machine::AxisSpec> read_side(MapReader& c, const std::string& key) {
  const YAML::Node list = c.raw(key);
  if (!list.IsDefined()) c.context().fail(c.mark(), c.field(key), "missing (a list of axes: - {name, kind, direction, …})");
  if (!list.IsSequence()) c.context().fail(list.Mark(), c.field(key), "expected a list of axes");
  std::vector<machine::AxisSpec> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].IsMap()) c.context().fail(list[i].Mark(), fmt::format("{}[{}]", c.field(key), i), "expected a map (an axis)");
    const std::string item = fmt::format("{}[{}]", c.field(key), i);
    c.context().marks[item] = list[i].Mark(); // a refusal of a field the axis does not give is located at the axis
    MapReader a(list[i], item, c.context());
    out.push_back(read_axis(a));
  }
  return out;
}

/// An inline description (`c` is the chain's map), validated by make_chain; its refusal located at the axis' field.
const machine::KinematicChain& read_description(MapReader& c, const std::string& chain_field) {
  machine::ChainSpec spec;
  spec.name = c.text("name");
  spec.workpiece = read_side(c, "workpiece");
  spec.tool = read_side(c, "tool");
  c.finish();
  try {
    return machine::make_chain(spec);
  } catch (const machine::ChainError& e) {
    const int nw = static_cast<int>(spec.workpiece.size());
    if (e.axis() < 0) c.context().fail(c.mark(), chain_field, e.what());
    const bool work = e.axis() < nw;
    const auto& axis = work ? spec.workpiece[static_cast<std::size_t>(e.axis())]
                            : spec.tool[static_cast<std::size_t>(e.axis() - nw)];
    std::string field = e.field();
    if (field == "stroke") field = axis.kind == machine::AxisKind::Rotary ? "stroke_deg" : "stroke_mm";
    const std::string item = fmt::format("{}[{}]", c.field(work ? "workpiece" : "tool"), work ? e.axis() : e.axis() - nw);
    c.context().fail_field(field.empty() ? item : item + "." + field, e.what());
  }
}

} // namespace

const machine::KinematicChain& read_chain(MapReader& m, const std::filesystem::path& base) {
  auto& ctx = m.context();
  const bool inline_chain = m.has("chain"), from_file = m.has("chain_file");
  if (inline_chain && from_file)
    ctx.fail_field(m.field("chain_file"), "give the chain once: either machine.chain or machine.chain_file");
  if (from_file) {
    const std::string name = m.text("chain_file");
    const auto path = (base / name).lexically_normal();
    ReadContext file_ctx{path.string(), {}};
    std::string text;
    try {
      text = input::read_input_file(path, input::kMaxSceneBytes, "chain file");
    } catch (const InputError& e) {
      ctx.fail_field(m.field("chain_file"), fmt::format("{}: {} (a chain file's path is relative to the scene file)",
                                                        std::filesystem::absolute(path).lexically_normal().string(),
                                                        e.message()));
    }
    const YAML::Node root = load_one_document(text, file_ctx, "chain file");
    if (!root.IsMap()) file_ctx.fail(root.Mark(), "", "expected a map (name, workpiece, tool)");
    MapReader c(root, "", file_ctx);
    return read_description(c, "");
  }
  if (!inline_chain) return machine::cfxzay();
  const YAML::Node node = m.raw("chain");
  if (node.IsScalar()) {
    const std::string name = m.text("chain");
    if (const auto* preset = machine::chain_preset(name)) return *preset;
    ctx.fail_field(m.field("chain"), fmt::format("'{}' is not a preset chain ({}); describe the chain as a map "
                                                 "(docs/scene-format.md)",
                                                 text::excerpt(name), fmt::join(machine::chain_preset_names(), ", ")));
  }
  if (!node.IsMap()) ctx.fail_field(m.field("chain"), "expected a preset's name or a map (name, workpiece, tool)");
  MapReader c = m.map("chain");
  return read_description(c, m.field("chain"));
}

} // namespace geartopo::scene
