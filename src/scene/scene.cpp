#include "scene/scene.hpp"

#include "gears/field_error.hpp"
#include "gears/gear_geometry.hpp"
#include "scene/yaml_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <numbers>
#include <sstream>

namespace geartopo::scene {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string located(const std::string& file, int line, int column, const std::string& field, const std::string& msg) {
  std::string where = file;
  if (line > 0) where += fmt::format(":{}:{}", line, column);
  return fmt::format("{}: {}{}", where, field.empty() ? "" : field + ": ", msg);
}

gears::GearSpec read_gear(MapReader& g, Scene& scene) {
  gears::GearSpec s;
  s.normal_module_mm = g.number("normal_module_mm", {0.0, 100.0, true, false});
  s.teeth = static_cast<int>(g.integer("teeth", 5, 10000));
  s.normal_pressure_angle_rad = g.number("normal_pressure_angle_deg", {5.0, 45.0, true, true}) * kDeg;
  const double beta_deg = g.number("helix_angle_deg", {-45.0, 45.0});
  s.helix_angle_rad = beta_deg * kDeg;
  if (const auto hand = g.optional_choice("hand", {"right", "left", "spur"})) {
    if (*hand != gears::to_string(s.hand()))
      g.context().fail_field(g.field("hand"),
                             fmt::format("'{}' contradicts helix_angle_deg = {} (positive: right, negative: left, "
                                         "zero: spur)",
                                         *hand, beta_deg));
  }
  s.profile_shift = g.number("profile_shift", {-3.0, 3.0});
  s.face_width_mm = g.number("face_width_mm", {0.0, 5000.0, true, false});
  if (auto da = g.optional_number("tip_diameter_mm", {0.0, 50000.0, true, false})) {
    s.tip_diameter_mm = *da;
  } else {
    s.tip_diameter_mm = gears::conventional_tip_diameter(s);
    scene.defaulted.push_back("tip_diameter_mm");
  }
  if (auto df = g.optional_number("root_diameter_mm", {0.0, 50000.0, true, false})) {
    s.root_diameter_mm = *df;
  } else {
    s.root_diameter_mm = gears::conventional_root_diameter(s);
    scene.defaulted.push_back("root_diameter_mm");
  }
  s.root_form_diameter_mm = g.optional_number("root_form_diameter_mm", {0.0, 50000.0, true, false});
  if (auto v = g.optional_number("rack_dedendum_coef", {0.5, 2.0})) s.rack_dedendum_coef = *v;
  if (auto v = g.optional_number("rack_root_radius_coef", {0.0, 0.6})) s.rack_root_radius_coef = *v;
  scene.assumed = g.optional_text_list("assumed");
  for (const auto& key : scene.assumed) {
    if (key == "assumed" || !g.has(key))
      g.context().fail_field(g.field("assumed"),
                             fmt::format("'{}' is not a key given in this gear section", key));
  }
  g.finish();
  return s;
}

} // namespace

SceneError::SceneError(const std::string& file, int line, int column, const std::string& field,
                       const std::string& message)
    : std::runtime_error(located(file, line, column, field, message)), file_(file), field_(field), line_(line),
      column_(column) {}

Scene parse_scene(const std::string& text, const std::string& source) {
  ReadContext ctx{source, {}};
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    ctx.fail(e.mark, "", "YAML syntax error: " + e.msg);
  }
  if (!root.IsDefined() || root.IsNull()) ctx.fail(YAML::Mark::null_mark(), "", "empty scene (a 'gear' map is needed)");

  Scene scene;
  scene.source = source;
  MapReader top(root, "", ctx);
  scene.name = top.optional_text("name").value_or("");
  scene.description = top.optional_text("description").value_or("");
  MapReader gear = top.map("gear");
  scene.gear = read_gear(gear, scene);
  top.finish();

  // Domain rules that involve several fields (undercut, pointed tip, form diameter) live in GearGeometry; locate
  // what it reports in the file.
  try {
    gears::GearGeometry check(scene.gear);
  } catch (const FieldError& e) {
    ctx.fail_field(e.field(), e.what());
  }
  return scene;
}

Scene load_scene(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneError(file.string(), 0, 0, "", "cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), file.string());
}

} // namespace geartopo::scene
