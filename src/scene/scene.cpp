#include "geartopo/scene/scene.hpp"

#include "geartopo/machine/component_change.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/core/limits.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/core/field_error.hpp"
#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/flank_modifications.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/core/text_field.hpp"
#include "chain_reader.hpp"
#include "custom_law_reader.hpp"
#include "design_table.hpp"
#include "yaml_reader.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/grinding/wheel_setting.hpp"
#include "geartopo/machine/error_table.hpp"
#include "geartopo/effects/registry.hpp"

#include <fmt/format.h>
#include <yaml-cpp/depthguard.h>   // YAML::DeepRecursion, not included by yaml.h in 0.7
#include <yaml-cpp/eventhandler.h> // nor YAML::EventHandler

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

namespace geartopo::scene {
namespace {


// One flank's modification keys (gear.modifications.both / left / right), each over `base` (both's values for left and
// right). Amounts ≥ 0 except the slopes; 1 mm (1000 µm) bounds every amount far above any drawing's few tens of µm.
gears::FlankModifications read_flank_modifications(MapReader& m, gears::FlankModifications f) {
  constexpr Range kAmountUm{0.0, 1000.0};
  constexpr Range kSlopeUm{-1000.0, 1000.0};
  constexpr Range kDiameterMm = positive_length_mm(50000.0);
  constexpr Range kLengthMm = positive_length_mm(5000.0);
  const auto shape = [&m](const std::string& key, gears::ReliefShape fallback) {
    const auto c = m.optional_choice(key, {"linear", "arc"});
    return c ? (*c == "arc" ? gears::ReliefShape::Arc : gears::ReliefShape::Linear) : fallback;
  };
  f.profile_crowning_um = m.optional_number("profile_crowning_um", kAmountUm).value_or(f.profile_crowning_um);
  f.profile_slope_um = m.optional_number("profile_slope_um", kSlopeUm).value_or(f.profile_slope_um);
  f.tip_relief_um = m.optional_number("tip_relief_um", kAmountUm).value_or(f.tip_relief_um);
  f.tip_relief_start_diameter_mm =
      m.optional_number("tip_relief_start_diameter_mm", kDiameterMm).value_or(f.tip_relief_start_diameter_mm);
  f.tip_relief_shape = shape("tip_relief_shape", f.tip_relief_shape);
  f.root_relief_um = m.optional_number("root_relief_um", kAmountUm).value_or(f.root_relief_um);
  f.root_relief_start_diameter_mm =
      m.optional_number("root_relief_start_diameter_mm", kDiameterMm).value_or(f.root_relief_start_diameter_mm);
  f.root_relief_shape = shape("root_relief_shape", f.root_relief_shape);
  f.helix_crowning_um = m.optional_number("helix_crowning_um", kAmountUm).value_or(f.helix_crowning_um);
  f.helix_slope_um = m.optional_number("helix_slope_um", kSlopeUm).value_or(f.helix_slope_um);
  f.end_relief_um = m.optional_number("end_relief_um", kAmountUm).value_or(f.end_relief_um);
  f.end_relief_length_mm = m.optional_number("end_relief_length_mm", kLengthMm).value_or(f.end_relief_length_mm);
  f.end_relief_shape = shape("end_relief_shape", f.end_relief_shape);
  m.finish();
  return f;
}

// gear.modifications: `both` for the two flanks, `left` / `right` overriding it key by key (DIN ISO 21771 flanks).
gears::DesignModifications read_modifications(MapReader& m, const std::filesystem::path& base) {
  gears::FlankModifications both;
  if (auto b = m.optional_map("both")) both = read_flank_modifications(*b, both);
  gears::DesignModifications d{both, both, {}};
  if (auto l = m.optional_map("left")) d.left = read_flank_modifications(*l, both);
  if (auto r = m.optional_map("right")) d.right = read_flank_modifications(*r, both);
  // `table`: any other designed topology, point by point, relative to the scene's folder (design_table.hpp).
  if (auto t = m.optional_text("table")) {
    if (t->empty()) m.context().fail_field(m.field("table"), "an empty path (name a CSV file, or leave the key out)");
    d.table = read_design_table((base / *t).lexically_normal());
  }
  m.finish();
  return d;
}

gears::GearSpec read_gear(MapReader& g, Scene& scene, const std::filesystem::path& base) {
  gears::GearSpec s;
  s.normal_module_mm = g.number("normal_module_mm", positive_length_mm(100.0));
  // ISO 21771 writes an internal gear's number of teeth negative; geartopo grinds external gears only: say so rather
  // than "-35 is outside [5, 10000]".
  if (const YAML::Node z = g.raw("teeth"); z.IsScalar() && !z.Scalar().empty() && z.Scalar().front() == '-')
    g.context().fail_field(g.field("teeth"), fmt::format("{} is an internal gear (z < 0, ISO 21771): geartopo models "
                                                         "external gears ground with a form wheel only",
                                                         text::excerpt(z.Scalar())));
  s.teeth = static_cast<int>(g.integer("teeth", 5, 10000));
  s.normal_pressure_angle_rad = g.number("normal_pressure_angle_deg", {5.0, 45.0, true, true}) * units::kRadPerDeg;
  const double beta_deg = g.number("helix_angle_deg", {-45.0, 45.0});
  s.helix_angle_rad = beta_deg * units::kRadPerDeg;
  if (const auto hand = g.optional_choice("hand", {"right", "left", "spur"})) {
    if (*hand != gears::to_string(s.hand()))
      g.context().fail_field(g.field("hand"),
                             fmt::format("'{}' contradicts helix_angle_deg = {} (positive: right, negative: left, "
                                         "zero: spur)",
                                         *hand, beta_deg));
  }
  s.profile_shift = g.number("profile_shift", {-3.0, 3.0});
  s.face_width_mm = g.number("face_width_mm", positive_length_mm(5000.0));
  if (auto da = g.optional_number("tip_diameter_mm", positive_length_mm(50000.0))) {
    s.tip_diameter_mm = *da;
  } else {
    s.tip_diameter_mm = gears::conventional_tip_diameter(s);
    scene.defaulted.push_back("tip_diameter_mm");
  }
  if (auto df = g.optional_number("root_diameter_mm", positive_length_mm(50000.0))) {
    s.root_diameter_mm = *df;
  } else {
    s.root_diameter_mm = gears::conventional_root_diameter(s);
    scene.defaulted.push_back("root_diameter_mm");
  }
  s.root_form_diameter_mm = g.optional_number("root_form_diameter_mm", positive_length_mm(50000.0));
  if (auto v = g.optional_number("rack_dedendum_coef", {0.5, 2.0})) s.rack_dedendum_coef = *v;
  if (auto v = g.optional_number("rack_root_radius_coef", {0.0, 0.6})) s.rack_root_radius_coef = *v;
  // Read in µm (the drawing's unit), kept in mm inside; the message quotes the values as written.
  const double upper_um = g.optional_number("thickness_allowance_upper_um", {-100000.0, 100000.0}).value_or(0.0);
  const double lower_um = g.optional_number("thickness_allowance_lower_um", {-100000.0, 100000.0}).value_or(0.0);
  if (lower_um > upper_um) {
    // Blame the key that is written: an absent lower allowance is 0 and the upper one is then the wrong one.
    if (g.has("thickness_allowance_lower_um"))
      g.context().fail_field(g.field("thickness_allowance_lower_um"),
                             fmt::format("{} µm is above thickness_allowance_upper_um = {} µm (A_sni ≤ A_sne)",
                                         lower_um, upper_um));
    g.context().fail_field(g.field("thickness_allowance_upper_um"),
                           fmt::format("{} µm is below the lower allowance {} µm (absent: 0; A_sni ≤ A_sne)", upper_um,
                                       lower_um));
  }
  s.thickness_allowance_upper_mm = units::mm_from_um(upper_um);
  s.thickness_allowance_lower_mm = units::mm_from_um(lower_um);
  s.ball_diameter_mm = g.optional_number("ball_diameter_mm", positive_length_mm(1000.0));
  if (auto m = g.optional_map("modifications")) s.modifications = read_modifications(*m, base);
  scene.assumed = g.optional_text_list("assumed");
  for (size_t i = 0; i < scene.assumed.size(); ++i) {
    const auto& key = scene.assumed[i];
    if (key == "assumed" || !g.has(key))
      g.fail_item("assumed", i, fmt::format("'{}' is not a key given in this gear section", key));
    if (std::find(scene.assumed.begin(), scene.assumed.begin() + static_cast<std::ptrdiff_t>(i), key) !=
        scene.assumed.begin() + static_cast<std::ptrdiff_t>(i))
      g.fail_item("assumed", i, fmt::format("'{}' is listed twice", key));
  }
  g.finish();
  return s;
}

machine::Interval read_interval(MapReader& m, const std::string& key, machine::Interval fallback) {
  if (!m.has(key)) return fallback;
  const auto items = m.optional_text_list(key);
  machine::Interval iv{};
  bool ok = items.size() == 2;
  if (ok) {
    ok = text::parse_number(items[0], iv.min) == std::errc() && text::parse_number(items[1], iv.max) == std::errc() &&
         std::isfinite(iv.min) && std::isfinite(iv.max) && iv.min < iv.max;
  }
  if (!ok) m.context().fail_field(m.field(key), "expected [min, max] with min < max, two finite numbers");
  return iv;
}

// "<component>_<unit>" → (component, unit), split at the last underscore ("delta_xc_um" → delta_xc, um).
std::pair<std::string, std::string> split_unit(const std::string& key) {
  const auto us = key.rfind('_');
  if (us == std::string::npos) return {key, ""};
  return {key.substr(0, us), key.substr(us + 1)};
}

// Without a given set-up the face width sits in the middle of the Z stroke.
double centred_datum_z(const machine::Strokes& st, double face_width) {
  return 0.5 * (st.z_mm.min + st.z_mm.max) - 0.5 * face_width;
}

// "… of the CAFXZY chain" on another chain than the seed machine's (whose messages stay as they were).
std::string not_a_component(const std::string& name, const machine::KinematicChain& chain) {
  return fmt::format("'{}' is not an error component{} (docs/error-components.md)", text::excerpt(name),
                     &chain == &machine::cfxzay() ? "" : " of the " + chain.name() + " chain");
}

// The standard uncertainty of one kind of component: a length (µm) or an angle (µrad), bounded like a table value.
constexpr Range kLengthUncertaintyUm{0.0, machine::kMaxTableLengthMm * units::kUmPerMm};
constexpr Range kAngleUncertaintyUrad{0.0, machine::kMaxTableAngleRad * units::kUradPerRad};

// machine.uncertainty: per-kind defaults, then per-component values (`components: {epsilon_zc_urad: 2}`). A component
// whose table has a `u_` column takes its uncertainty from there (over its kind's value); naming it in `components`
// too is refused: one quantity stated twice, and which one the user meant cannot be known.
void read_uncertainty(MapReader& u, MachineUncertainty& out, ReadContext& ctx,
                      const std::vector<machine::ErrorSource>& sources, const machine::KinematicChain& chain) {
  using machine::Axis;
  using machine::ComponentId;
  // (key, applies to): a component of quantity q on axis group g.
  const auto set_kind = [&](const std::string& key, bool rotary_axes, machine::Quantity q, bool motion) {
    const bool length = q == machine::Quantity::Length;
    const auto v = u.optional_number(key, length ? kLengthUncertaintyUm : kAngleUncertaintyUrad);
    if (!v) return;
    for (int k = 0; k < machine::kComponentCount; ++k) {
      const auto& c = machine::info(machine::component_at(k));
      const bool is_rotary = c.axis == Axis::A || c.axis == Axis::C;
      if (c.quantity != q || c.position_dependent != motion || (motion && is_rotary != rotary_axes)) continue;
      out.component_u[static_cast<size_t>(k)] = length ? units::mm_from_um(*v) : units::rad_from_urad(*v);
    }
  };
  set_kind("linear_axis_um", false, machine::Quantity::Length, true);
  set_kind("linear_axis_urad", false, machine::Quantity::Angle, true);
  set_kind("rotary_axis_um", true, machine::Quantity::Length, true);
  set_kind("rotary_axis_urad", true, machine::Quantity::Angle, true);
  // Constants: squareness (S_…, angles) and the axis-line location (E_…: offsets and angles).
  if (auto v = u.optional_number("squareness_urad", kAngleUncertaintyUrad))
    for (auto id : {ComponentId::S_xy, ComponentId::S_zy, ComponentId::S_xz})
      out.component_u[static_cast<size_t>(machine::index(id))] = units::rad_from_urad(*v);
  const auto set_location = [&](const std::string& key, machine::Quantity q) {
    const bool length = q == machine::Quantity::Length;
    const auto v = u.optional_number(key, length ? kLengthUncertaintyUm : kAngleUncertaintyUrad);
    if (!v) return;
    for (int k = machine::index(ComponentId::E_XOC); k < machine::kComponentCount; ++k)
      if (machine::info(machine::component_at(k)).quantity == q)
        out.component_u[static_cast<size_t>(k)] = length ? units::mm_from_um(*v) : units::rad_from_urad(*v);
  };
  set_location("location_um", machine::Quantity::Length);
  set_location("location_urad", machine::Quantity::Angle);
  if (auto c = u.optional_map("components")) {
    for (const auto& key : c->keys()) {
      const auto [name, unit] = split_unit(key);
      const auto id = chain.component_from_name(name);
      if (!id) ctx.fail_field(c->field(key), not_a_component(name, chain));
      const auto q = machine::info(*id).quantity;
      const auto scale = machine::value_unit_scale(q, unit);
      if (!scale)
        ctx.fail_field(c->field(key), fmt::format("'{}' is not a unit of {} (use {})", unit,
                                                  q == machine::Quantity::Length ? "a length" : "an angle",
                                                  machine::file_unit(q)));
      const auto with_column = std::find_if(sources.begin(), sources.end(), [&](const machine::ErrorSource& src) {
        return src.id() == *id && src.has_uncertainty_column();
      });
      if (with_column != sources.end())
        ctx.fail_field(c->field(key),
                       fmt::format("{}'s standard uncertainty is already given by table {} column {} '{}': state it in "
                                   "one place (remove this key or the table's column)",
                                   name, with_column->origin()->file, with_column->origin()->uncertainty_column,
                                   with_column->origin()->uncertainty_field));
      const double bound = q == machine::Quantity::Length ? machine::kMaxTableLengthMm : machine::kMaxTableAngleRad;
      const double v = c->number(key, {0.0, bound / *scale});
      out.component_u[static_cast<size_t>(machine::index(*id))] = v * *scale;
    }
    c->finish();
  }
  u.finish();
}

// repeatability / resolution per axis of the chain, by its letters in pose order: <letter>_um (linear axes),
// <letter>_mdeg (rotary axes) — x_um, y_um, z_um, a_mdeg, c_mdeg on the CFXZAY — each ≥ 0, times `scale`.
void read_axis_values(MapReader& m, const machine::KinematicChain& chain, machine::Vector5d& out, double scale) {
  constexpr Range kLinearUm{0.0, 1000.0};
  constexpr Range kRotaryMdeg{0.0, 1000.0};
  for (int i = 0; i < machine::kAxisCount; ++i) {
    const auto slot = static_cast<machine::Axis>(i);
    std::string key(chain.axis_name(slot));
    for (char& ch : key) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (!chain.is_rotary(slot)) {
      if (auto v = m.optional_number(key + "_um", kLinearUm)) out(i) = scale * units::mm_from_um(*v);
    } else if (auto v = m.optional_number(key + "_mdeg", kRotaryMdeg)) {
      out(i) = scale * units::rad_from_deg(*v * 1e-3);
    }
  }
  m.finish();
}

// The chain's strokes by pose slot, each overridden by `strokes.<axis letter>_mm` (linear) or `_deg` (the swivel): on
// the CFXZAY x_mm, y_mm, z_mm, a_deg. The chain then carries the scene's strokes (ChainProcess checks paths with them).
void read_strokes(MapReader& m, MachineSection& s) {
  using machine::Axis;
  const machine::KinematicChain& chain = *s.chain;
  std::array<machine::Interval*, 4> slots{&s.strokes.x_mm, &s.strokes.y_mm, &s.strokes.z_mm, &s.strokes.a_deg};
  for (int k = 0; k < 4; ++k) {
    const auto& stroke = chain.axis(static_cast<Axis>(k)).stroke; // validated: every linear axis and the swivel have one
    const double scale = k == 3 ? units::kDegPerRad : 1.0;
    *slots[static_cast<std::size_t>(k)] = machine::Interval{stroke->min * scale, stroke->max * scale};
  }
  auto st = m.optional_map("strokes");
  if (!st) return;
  std::array<std::optional<machine::Interval>, machine::kAxisCount> given{};
  for (int k = 0; k < 4; ++k) {
    std::string key(chain.axis_name(static_cast<Axis>(k)));
    for (char& ch : key) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    key += k == 3 ? "_deg" : "_mm";
    if (!st->has(key)) continue;
    auto& slot = *slots[static_cast<std::size_t>(k)];
    slot = read_interval(*st, key, slot);
    given[static_cast<std::size_t>(k)] = k == 3 ? machine::Interval{slot.min * units::kRadPerDeg, slot.max * units::kRadPerDeg}
                                                : slot;
  }
  st->finish();
  s.chain = &chain.with_strokes(given);
}

MachineSection read_machine(MapReader& m, const std::filesystem::path& base, double face_width) {
  MachineSection s;
  s.name = m.optional_text("name").value_or("");
  const auto datum = m.optional_number("datum_face_z_mm", {-1e4, 1e4});
  s.chain = &read_chain(m, base);
  read_strokes(m, s);
  s.datum_face_z_mm = datum ? *datum : centred_datum_z(s.strokes, face_width);
  auto& ctx = m.context();
  const auto tables = m.optional_text_list("tables");
  for (size_t i = 0; i < tables.size(); ++i) {
    const auto path = (base / tables[i]).lexically_normal();
    // The same table twice would add its errors twice (or be refused later as components given twice, without
    // saying that the file is simply listed twice).
    if (std::find(s.table_files.begin(), s.table_files.end(), path.string()) != s.table_files.end())
      m.fail_item("tables", i, fmt::format("table {} is listed twice", text::excerpt(tables[i])));
    // A scene copied to another folder, or read from text without its file's name, names a table that is not
    // there: say where it was looked for and why there (the table reader's message would name only the path).
    if (std::error_code ec; !std::filesystem::exists(path, ec))
      m.fail_item("tables", i, fmt::format("table {} not found: {} does not exist (a table's path is relative to the "
                                           "scene file{})", text::excerpt(tables[i]),
                                           std::filesystem::absolute(path).lexically_normal().string(),
                                           base.empty() ? "; this scene has no file name (read from text), so relative "
                                                          "to the working folder"
                                                        : ", in " + base.string()));
    try {
      for (auto& src : machine::load_error_tables(path, *s.chain)) s.sources.push_back(std::move(src));
    } catch (const InputError&) {
      throw; // located in the table file
    }
    s.table_files.push_back(path.string());
  }
  if (auto c = m.optional_map("constants")) {
    for (const auto& key : c->keys()) {
      const auto [name, unit] = split_unit(key);
      const auto id = s.chain->component_from_name(name);
      if (!id) ctx.fail_field(c->field(key), not_a_component(name, *s.chain));
      const double value = c->number(key, {-1e6, 1e6});
      try {
        s.sources.push_back(machine::ErrorSource::constant(*id, value, unit));
      } catch (const std::invalid_argument& e) {
        ctx.fail_field(c->field(key), e.what());
      }
    }
    c->finish();
  }
  if (auto p = m.optional_map("polynomials")) {
    for (const auto& key : p->keys()) {
      const auto id = s.chain->component_from_name(key);
      if (!id) ctx.fail_field(p->field(key), not_a_component(key, *s.chain));
      MapReader poly = p->map(key);
      const std::string unit = poly.text("unit"), pos_unit = poly.text("position_unit");
      std::vector<double> coef;
      for (const auto& t : poly.optional_text_list("coefficients")) {
        double v = 0.0;
        if (text::parse_number(t, v) != std::errc() || !std::isfinite(v))
          ctx.fail_field(poly.field("coefficients"), fmt::format("'{}' is not a finite number", text::excerpt(t)));
        coef.push_back(v);
      }
      if (coef.empty()) ctx.fail_field(poly.field("coefficients"), "missing (a list of numbers, ascending powers)");
      poly.finish();
      try {
        s.sources.push_back(machine::ErrorSource::polynomial(*id, coef, unit, pos_unit));
      } catch (const std::invalid_argument& e) {
        ctx.fail_field(p->field(key), e.what());
      }
    }
    p->finish();
  }
  if (auto u = m.optional_map("uncertainty")) read_uncertainty(*u, s.uncertainty, ctx, s.sources, *s.chain);
  // The file gives ISO 230-2's unidirectional repeatability R↑ = 4 s (data sheets quote it); inside: s.
  if (auto r = m.optional_map("repeatability")) read_axis_values(*r, *s.chain, s.uncertainty.repeatability, 0.25);
  if (auto r = m.optional_map("resolution")) read_axis_values(*r, *s.chain, s.uncertainty.resolution, 1.0);
  m.finish();
  try {
    (void)s.model(); // strokes, duplicates and table coverage
  } catch (const InputError&) {
    throw; // located in a table file
  } catch (const std::invalid_argument& e) {
    ctx.fail_field(m.field("tables"), e.what());
  }
  return s;
}

grinding::WheelSpec read_wheel(MapReader& w) {
  grinding::WheelSpec s;
  s.outer_diameter_mm = w.number("outer_diameter_mm", {10.0, 2000.0});
  if (auto y = w.optional_number("axial_position_mm", {-1000.0, 1000.0})) s.axial_position_mm = *y;
  w.finish();
  return s;
}

grinding::ProcessSpec read_process(MapReader& p) {
  grinding::ProcessSpec s;
  // A grinding feed is a few hundred to a few thousand mm/min. Below 1 mm/min a stroke would take days, and a feed
  // such as 1e-320 (inside a bare "> 0") makes every stroke time infinite: the times reach the effects and the fits
  // as inf/NaN (issue 18).
  if (auto v = p.optional_number("feed_mm_per_min", {1.0, 1e5})) s.feed_mm_per_min = *v;
  if (auto v = p.optional_number("overtravel_mm", {0.0, 500.0})) s.overtravel_mm = *v;
  if (auto v = p.optional_number("indexing_time_s", {0.0, 3600.0})) s.indexing_time_s = *v;
  if (p.has("index_step")) s.index_step = static_cast<int>(p.integer("index_step", 1, 10000));
  if (p.has("first_space")) s.first_space = static_cast<int>(p.integer("first_space", 1, 10000));
  if (auto d = p.optional_choice("stroke", {"up", "down", "alternate"}))
    s.direction = *d == "up" ? grinding::StrokeDirection::Up
                  : *d == "down" ? grinding::StrokeDirection::Down
                                 : grinding::StrokeDirection::Alternate;
  if (auto c = p.optional_choice("lead_crowning", {"twist_free", "radial_infeed"}))
    s.lead_crowning = *c == "radial_infeed" ? grinding::LeadCrowning::RadialInfeed : grinding::LeadCrowning::TwistFree;
  p.finish();
  return s;
}

// One `correlation` entry of an effect, resolved after every effect is read (it may name a later one).
struct PendingCorrelation {
  std::string field;         ///< effects[i].correlation[j], for messages
  YAML::Mark mark;
  size_t effect = 0;         ///< the effect whose item holds the entry
  std::string key_a, key_b;  ///< "key" (this effect) or "type.key" (another effect of the list)
  double r = 0.0;
};

// The effect's values' standard uncertainties (`uncertainty: {key: u}`, the key's unit; absent: exact) and its
// correlation entries (`correlation: [[key_a, key_b, r], …]`), resolved by resolve_correlation.
std::vector<double> read_effect_uncertainty(MapReader& m, const std::string& type, const effects::Effect& effect,
                                            size_t effect_index, std::vector<PendingCorrelation>& pending) {
  auto& ctx = m.context();
  const auto& params = effect.parameters();
  std::vector<double> us(params.size(), 0.0);
  if (auto u = m.optional_map("uncertainty")) {
    for (const auto& key : u->keys()) {
      const auto it = std::find_if(params.begin(), params.end(), [&](const auto& p) { return p.key == key; });
      if (it == params.end()) {
        std::vector<std::string> keys;
        for (const auto& p : params) keys.push_back(p.key);
        ctx.fail_field(u->field(key), fmt::format("'{}' is not a parameter of {} ({})", key, type, fmt::join(keys, ", ")));
      }
      if (it->whole)
        ctx.fail_field(u->field(key), fmt::format("'{}' is a count set up on the machine, not an uncertain value", key));
      // A standard uncertainty wider than the parameter's whole allowed range says nothing a draw could use.
      us[static_cast<size_t>(it - params.begin())] = u->number(key, {0.0, it->hi - it->lo});
    }
    u->finish();
  }
  const YAML::Node list = m.raw("correlation");
  if (!list.IsDefined()) return us;
  const std::string list_field = m.field("correlation");
  if (!list.IsSequence()) ctx.fail(list.Mark(), list_field, "expected a list of [key_a, key_b, r]");
  for (size_t j = 0; j < list.size(); ++j) {
    const YAML::Node entry = list[j];
    const std::string field = fmt::format("{}[{}]", list_field, j);
    if (!entry.IsSequence() || entry.size() != 3 || !entry[0].IsScalar() || !entry[1].IsScalar() || !entry[2].IsScalar())
      ctx.fail(entry.Mark(), field, "expected [key_a, key_b, r]: two parameter keys and a correlation coefficient");
    PendingCorrelation c{field, entry.Mark(), effect_index, entry[0].Scalar(), entry[1].Scalar(), 0.0};
    if (text::parse_number(entry[2].Scalar(), c.r) != std::errc() || !std::isfinite(c.r) || std::abs(c.r) > 1.0)
      ctx.fail(entry[2].Mark(), field, fmt::format("'{}' is not a correlation coefficient (a number in [-1, 1])",
                                                   text::excerpt(entry[2].Scalar())));
    pending.push_back(std::move(c));
  }
  return us;
}

// The effect's equally likely value sets (`draws: {keys: [k, …], sets: [[v, …], …]}`, docs/scene-format.md): sets ×
// all of the effect's values (parameter order, file units), the keys not listed at the effect's value. Each set has one
// number per key, each inside its parameter's allowed range: a set is a whole explanation the prediction grinds with.
Eigen::MatrixXd read_effect_draws(MapReader& m, const std::string& type, const effects::Effect& effect,
                                  const std::vector<double>& values) {
  auto& ctx = m.context();
  auto d = m.optional_map("draws");
  if (!d) return {};
  (void)d->has("keys"), (void)d->has("sets"); // a misspelled key is named as unknown before anything is missing
  d->finish();
  const auto& params = effect.parameters();
  std::vector<std::string> all;
  for (const auto& p : params) all.push_back(p.key);
  const auto keys = d->optional_text_list("keys");
  if (keys.empty()) ctx.fail_field(d->field("keys"), fmt::format("missing: the keys each set gives, of {} ({})", type, fmt::join(all, ", ")));
  std::vector<size_t> column;
  for (size_t j = 0; j < keys.size(); ++j) {
    const auto it = std::find(all.begin(), all.end(), keys[j]);
    if (it == all.end()) d->fail_item("keys", j, fmt::format("'{}' is not a parameter of {} ({})", text::excerpt(keys[j]), type, fmt::join(all, ", ")));
    const auto k = static_cast<size_t>(it - all.begin());
    if (params[k].whole) d->fail_item("keys", j, fmt::format("'{}' is a count set up on the machine, not a drawn value", keys[j]));
    if (std::find(column.begin(), column.end(), k) != column.end()) d->fail_item("keys", j, fmt::format("'{}' is listed twice", keys[j]));
    column.push_back(k);
  }
  const YAML::Node sets = d->raw("sets");
  const std::string sets_field = d->field("sets");
  if (!sets.IsDefined()) ctx.fail(d->mark(), sets_field, "missing: a list of value sets, [v, …] in the order of keys");
  constexpr size_t kMaxSets = 100000;
  if (!sets.IsSequence() || sets.size() < 2 || sets.size() > kMaxSets)
    ctx.fail(sets.Mark(), sets_field, fmt::format("expected a list of 2 … {} value sets [v, …]", kMaxSets));
  Eigen::MatrixXd out(static_cast<Eigen::Index>(sets.size()), static_cast<Eigen::Index>(values.size()));
  for (size_t i = 0; i < sets.size(); ++i) {
    const YAML::Node row = sets[i];
    const std::string field = fmt::format("{}[{}]", sets_field, i);
    if (!row.IsSequence() || row.size() != keys.size())
      ctx.fail(row.Mark(), field, fmt::format("expected [{}]: one number per key", fmt::join(keys, ", ")));
    for (size_t v = 0; v < values.size(); ++v) out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(v)) = values[v];
    for (size_t j = 0; j < keys.size(); ++j) {
      const auto& p = params[column[j]];
      double x = 0.0;
      if (!row[j].IsScalar() || text::parse_number(row[j].Scalar(), x) != std::errc() || !std::isfinite(x))
        ctx.fail(row[j].Mark(), field, fmt::format("{}: '{}' is not a number", keys[j], row[j].IsScalar() ? text::excerpt(row[j].Scalar()) : "a list or map"));
      if (x < p.lo || x > p.hi)
        ctx.fail(row[j].Mark(), field, fmt::format("{} {} is outside its allowed range [{}, {}]", keys[j], text::excerpt(row[j].Scalar()), p.lo, p.hi));
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(column[j])) = x;
    }
  }
  return out;
}

// The N × N correlation over all effects' values (scene order) from the entries; validated: keys that exist, a pair
// once, not a value with itself, positive semidefinite (within the rounding of written coefficients).
Eigen::MatrixXd resolve_correlation(const std::vector<EffectSpec>& specs, const std::vector<PendingCorrelation>& pending,
                                    const std::vector<Eigen::MatrixXd>& draws, const ReadContext& ctx) {
  std::vector<Eigen::Index> first(specs.size() + 1, 0);
  for (size_t e = 0; e < specs.size(); ++e) first[e + 1] = first[e] + static_cast<Eigen::Index>(specs[e].values.size());
  const Eigen::Index n = first.back();
  const auto slot = [&](const PendingCorrelation& c, const std::string& key) -> Eigen::Index {
    size_t e = c.effect;
    std::string name = key;
    if (const auto dot = key.find('.'); dot != std::string::npos) {
      const std::string type = key.substr(0, dot);
      const auto it = std::find_if(specs.begin(), specs.end(), [&](const auto& s) { return s.type == type; });
      if (it == specs.end()) ctx.fail(c.mark, c.field, fmt::format("'{}': no effect of type '{}' in this scene", key, type));
      e = static_cast<size_t>(it - specs.begin());
      name = key.substr(dot + 1);
    }
    if (e < draws.size() && draws[e].rows() > 0)
      ctx.fail(c.mark, c.field, fmt::format("'{}': {} is drawn from its value sets (draws), which carry its correlations",
                                            text::excerpt(key), specs[e].type));
    const auto params = effects::make_effect(specs[e].type)->parameters();
    for (size_t k = 0; k < params.size(); ++k)
      if (params[k].key == name) return first[e] + static_cast<Eigen::Index>(k);
    ctx.fail(c.mark, c.field, fmt::format("'{}' is not a parameter of {} (another effect's: type.key)", text::excerpt(key),
                                          specs[e].type));
  };
  Eigen::MatrixXd C = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXi given = Eigen::MatrixXi::Zero(n, n);
  for (const auto& c : pending) {
    const Eigen::Index a = slot(c, c.key_a), b = slot(c, c.key_b);
    if (a == b) ctx.fail(c.mark, c.field, fmt::format("'{}' with itself: its correlation is 1", c.key_a));
    if (given(a, b)) ctx.fail(c.mark, c.field, fmt::format("the pair {}, {} is given twice", c.key_a, c.key_b));
    given(a, b) = given(b, a) = 1;
    C(a, b) = C(b, a) = c.r;
  }
  // A correlation matrix is positive semidefinite; coefficients written to 6 digits may dip below by their rounding.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(C, Eigen::EigenvaluesOnly);
  if (eig.eigenvalues().minCoeff() < -1e-5 * static_cast<double>(n))
    ctx.fail(pending.front().mark, pending.front().field,
             fmt::format("the effects' correlation coefficients are not a correlation matrix (not positive "
                         "semidefinite: smallest eigenvalue {:.3g}); no joint distribution has them",
                         eig.eigenvalues().minCoeff()));
  return C;
}

/// What the effect lists (`effects`, `custom_effects`) leave for the end: each value's uncertainty and the
/// correlation entries, resolved once every effect of both lists is known.
struct EffectUncertainties {
  std::vector<std::vector<double>> values;
  std::vector<PendingCorrelation> pending;
  std::vector<Eigen::MatrixXd> draws; // per effect its value sets (0 rows: none)
  std::optional<size_t> drawn_from;   // the first effect with value sets
  bool any = false;
};

void read_effects(MapReader& top, ReadContext& ctx, Scene& scene, EffectUncertainties& u) {
  std::vector<EffectSpec>& out = scene.effects;
  const YAML::Node list = top.raw("effects");
  if (!list.IsDefined()) return;
  if (!list.IsSequence()) ctx.fail(list.Mark(), "effects", "expected a list of effects (- type: …)");
  for (size_t i = 0; i < list.size(); ++i) {
    MapReader m(list[i], fmt::format("effects[{}]", i), ctx);
    const std::string type = m.text("type");
    const auto effect = effects::is_custom_effect(type) ? nullptr : effects::make_effect(type);
    if (!effect)
      ctx.fail_field(m.field("type"), fmt::format("'{}' is not an effect of the library ({}); an effect of your own is "
                                                  "declared under custom_effects",
                                                  type, fmt::join(effects::effect_types(), ", ")));
    for (const auto& other : out)
      if (other.type == type) ctx.fail_field(m.field("type"), fmt::format("'{}' is listed twice", type));
    EffectSpec spec{type, effect->values()};
    const auto& params = effect->parameters();
    for (size_t k = 0; k < params.size(); ++k) {
      if (params[k].whole) {
        // A count: 2.5 strokes between dressings is not a set-up anyone can run (issue 18).
        if (m.has(params[k].key))
          spec.values[k] = static_cast<double>(m.integer(params[k].key, static_cast<long long>(params[k].lo),
                                                         static_cast<long long>(params[k].hi)));
      } else if (auto v = m.optional_number(params[k].key, {params[k].lo, params[k].hi})) {
        spec.values[k] = *v;
      }
    }
    const size_t pending_before = u.pending.size();
    u.values.push_back(read_effect_uncertainty(m, type, *effect, out.size(), u.pending));
    const bool uncertain = std::any_of(u.values.back().begin(), u.values.back().end(), [](double x) { return x > 0.0; });
    u.any = u.any || uncertain;
    u.draws.push_back(read_effect_draws(m, type, *effect, spec.values));
    if (u.draws.back().rows() > 0) {
      // Two descriptions of one distribution: the sets are the whole of it (a Gaussian would add what they exclude).
      if (uncertain || u.pending.size() > pending_before)
        ctx.fail_field(m.field("draws"), fmt::format("{} has value sets and an {}: give one or the other",
                                                     type, uncertain ? "uncertainty" : "own correlation"));
      if (u.drawn_from && u.draws.back().rows() != u.draws[*u.drawn_from].rows())
        ctx.fail_field(m.field("draws"), fmt::format("{} value sets here, {} in effects[{}].draws: the sets of all effects "
                                                     "are drawn together, set j of each with set j of the others",
                                                     u.draws.back().rows(), u.draws[*u.drawn_from].rows(), *u.drawn_from));
      if (!u.drawn_from) u.drawn_from = i;
    }
    m.finish();
    out.push_back(std::move(spec));
  }
}

void read_custom_effects(MapReader& top, ReadContext& ctx, Scene& scene, EffectUncertainties& u) {
  const YAML::Node list = top.raw("custom_effects");
  if (!list.IsDefined()) return;
  if (!list.IsSequence()) ctx.fail(list.Mark(), "custom_effects", "expected a list of your effects (- name: …)");
  for (size_t i = 0; i < list.size(); ++i) {
    MapReader m(list[i], fmt::format("custom_effects[{}]", i), ctx);
    const auto law = read_custom_law(m, scene);
    const auto effect = effects::make_custom_effect(law);
    EffectSpec spec{law->name(), effects::declared_values(*law)};
    u.values.push_back(read_effect_uncertainty(m, law->name(), *effect, scene.effects.size(), u.pending));
    for (double x : u.values.back()) u.any = u.any || x > 0.0;
    u.draws.emplace_back(); // a law of the user's carries no value sets (docs/scene-format.md)
    m.finish();
    scene.custom_effects.push_back(law->name());
    scene.effects.push_back(std::move(spec));
  }
}

void read_all_effects(MapReader& top, ReadContext& ctx, Scene& scene) {
  EffectUncertainties u;
  read_effects(top, ctx, scene, u);
  read_custom_effects(top, ctx, scene, u);
  // Empty when nothing is uncertain: the effects are then exact (Scene::effect_uncertainties).
  if (u.any) scene.effect_uncertainties = std::move(u.values);
  if (u.drawn_from) scene.effect_draws = std::move(u.draws);
  if (!u.pending.empty())
    scene.effect_correlation = resolve_correlation(scene.effects, u.pending, scene.effect_draws, ctx);
}

/// `machine_changes`: error components changed since the map was measured (docs/scene-format.md), each
/// {component, law, <size key of the law and the component's quantity>[, time_constant_s]}.
void read_machine_changes(MapReader& top, ReadContext& ctx, Scene& scene) {
  const YAML::Node list = top.raw("machine_changes");
  if (!list.IsDefined()) return;
  if (!list.IsSequence()) ctx.fail(list.Mark(), "machine_changes", "expected a list (- component: …, law: …)");
  for (size_t i = 0; i < list.size(); ++i) {
    MapReader m(list[i], fmt::format("machine_changes[{}]", i), ctx);
    const std::string name = m.text("component");
    const auto id = scene.machine.chain->component_from_name(name);
    if (!id) ctx.fail_field(m.field("component"), not_a_component(name, *scene.machine.chain));
    machine::ComponentChange c;
    c.component = *id;
    if (const auto law = m.optional_text("law")) {
      const auto named = machine::law_from_name(*law);
      if (!named)
        ctx.fail_field(m.field("law"), fmt::format("'{}' is not a law: constant, linear_in_time, steady_state, "
                                                   "once_per_revolution, twice_per_revolution or K_times_per_revolution "
                                                   "(K = 3 … {})",
                                                   text::excerpt(*law), machine::kMaxRevolutionOrder));
      c.law = named->law, c.order = named->order;
    }
    for (const auto& other : scene.machine_changes)
      if (other.component == c.component && other.law == c.law && other.order == c.order)
        ctx.fail_field(m.field("component"), fmt::format("{} with law {} is listed twice", name, c.law_name()));
    const auto q = machine::info(c.component).quantity;
    // Hard limits, far beyond any real machine (a change of 1 mm or 10 mrad, 100 µm or 1 mrad per minute): a value
    // beyond them is a typing error, not a drift.
    const double limit = machine_change_limit(c.law, q);
    const auto other_q = q == machine::Quantity::Length ? machine::Quantity::Angle : machine::Quantity::Length;
    if (m.has(machine::size_key(c.law, other_q)) && !m.has(machine::size_key(c.law, q)) &&
        m.optional_number(machine::size_key(c.law, other_q), {-1e300, 1e300})) // located at that key
      ctx.fail_field(m.field(machine::size_key(c.law, other_q)),
                     fmt::format("{} is {} ({}): give {}", name,
                                 q == machine::Quantity::Length ? "a length" : "an angle", machine::file_unit(q),
                                 machine::size_key(c.law, q)));
    c.size = m.number(machine::size_key(c.law, q), {-limit, limit}) / machine::file_per_internal(c.law, q);
    if (c.law == machine::ChangeLaw::SteadyState) c.time_constant_s = m.number("time_constant_s", {1.0, 1e7});
    if (c.law == machine::ChangeLaw::PerRevolution) {
      if (machine::info(c.component).axis != machine::Axis::C || !machine::info(c.component).position_dependent)
        ctx.fail_field(m.field("law"), fmt::format("{} needs a C-axis motion component (delta_xc … epsilon_zc); {} "
                                                   "does not turn with the table",
                                                   c.law_name(), name));
      c.phase_rad = units::rad_from_deg(m.number("phase_deg", {-360.0, 360.0}));
    }
    double u = 0.0;
    if (auto um = m.optional_map("uncertainty")) {
      u = um->number(machine::size_key(c.law, q), {0.0, limit});
      um->finish();
    }
    m.finish();
    scene.machine_changes.push_back(c);
    scene.machine_change_uncertainties.push_back(u);
  }
}

MeasurementGrid read_grid(MapReader& m, int teeth, const std::filesystem::path& base) {
  MeasurementGrid g;
  if (m.has("rows")) g.rows = static_cast<int>(m.integer("rows", 2, limits::kMaxGridLines));
  if (m.has("cols")) g.cols = static_cast<int>(m.integer("cols", 2, limits::kMaxGridLines));
  if (m.has("profile_points")) g.profile_points = static_cast<int>(m.integer("profile_points", 2, limits::kMaxTracePoints));
  if (m.has("helix_points")) g.helix_points = static_cast<int>(m.integer("helix_points", 2, limits::kMaxTracePoints));
  // The same bound as the CLI's --dense and the module's dense= (core/limits.hpp)
  if (m.has("dense_rows")) g.dense_rows = static_cast<int>(m.integer("dense_rows", 2, limits::kMaxGridLines));
  if (m.has("dense_cols")) g.dense_cols = static_cast<int>(m.integer("dense_cols", 2, limits::kMaxGridLines));
  if ((g.dense_rows > 0) != (g.dense_cols > 0))
    m.context().fail_field(m.field(g.dense_rows > 0 ? "dense_cols" : "dense_rows"),
                           "missing: give both dense_rows and dense_cols");
  // Refuse grids that could not be held in memory before anything is allocated (per flank; all teeth × 2 flanks).
  const long long per_flank = static_cast<long long>(g.rows) * g.cols + static_cast<long long>(g.dense_rows) * g.dense_cols;
  if (per_flank > grinding::kMaxPointsPerFlank)
    m.context().fail_field(m.field(g.dense_rows > 0 ? "dense_rows" : "rows"),
                           fmt::format("{} points per flank is more than the {} a simulation may hold", per_flank,
                                       grinding::kMaxPointsPerFlank));
  const auto listed = m.optional_text_list("teeth");
  for (size_t i = 0; i < listed.size(); ++i) {
    int v = 0;
    if (text::parse_number(listed[i], v) != std::errc() || v < 1 || v > teeth)
      m.fail_item("teeth", i, fmt::format("'{}' is not a tooth number of 1..{}", text::excerpt(listed[i]), teeth));
    // The words of `--teeth 1,1` (app/parsers.cpp parse_teeth): a tooth simulated twice is a slip, never a wish.
    if (std::find(g.teeth.begin(), g.teeth.end(), v) != g.teeth.end())
      m.fail_item("teeth", i, fmt::format("tooth {} is listed twice", v));
    g.teeth.push_back(v);
  }
  if (auto f = m.optional_text("measured")) {
    // '' would name the scene's own folder (base / "" is base): refused here rather than read as a directory.
    if (f->empty()) m.context().fail_field(m.field("measured"), "an empty file name");
    g.measured_file = (base / *f).lexically_normal().string();
  }
  if (auto a = m.optional_choice("measured_against", {"design", "involute"})) {
    if (g.measured_file.empty()) m.context().fail_field(m.field("measured_against"), "says nothing without measured");
    g.measured_against = *a;
  }
  m.finish();
  return g;
}

} // namespace

double machine_change_limit(machine::ChangeLaw law, machine::Quantity q) {
  return (q == machine::Quantity::Length ? 1000.0 : 10000.0) / (law == machine::ChangeLaw::LinearInTime ? 10.0 : 1.0);
}

MachineUncertainty MachineUncertainty::defaults() {
  MachineUncertainty u;
  for (int k = 0; k < machine::kComponentCount; ++k) {
    const auto& c = machine::info(machine::component_at(k));
    const bool rotary = c.axis == machine::Axis::A || c.axis == machine::Axis::C;
    const bool length = c.quantity == machine::Quantity::Length;
    double v = 0.0;
    if (c.position_dependent)
      v = length ? units::mm_from_um(rotary ? 2.0 : 1.0) : units::rad_from_urad(rotary ? 5.0 : 3.0);
    else // squareness 5 µrad; axis-line location 2 µm / 5 µrad
      v = length ? units::mm_from_um(2.0) : units::rad_from_urad(5.0);
    u.component_u[static_cast<size_t>(k)] = v;
  }
  const double mdeg = units::rad_from_deg(1e-3);
  // R↑ = 3 µm, 1 mdeg (the seed paper's machine) = 4 s (ISO 230-2).
  u.repeatability << units::mm_from_um(0.75), units::mm_from_um(0.75), units::mm_from_um(0.75), 0.25 * mdeg, 0.25 * mdeg;
  u.resolution << units::mm_from_um(1.0), units::mm_from_um(1.0), units::mm_from_um(1.0), mdeg, mdeg;
  return u;
}

namespace {
// The wheel must be synthesizable and the whole path must stay within the machine's strokes.
} // namespace

void Scene::fail_at(const std::string& field, const std::string& message) const {
  for (std::string p = field;;) {
    if (auto it = positions.find(p); it != positions.end()) throw InputError(it->second, field, message);
    const auto dot = p.rfind('.');
    if (dot == std::string::npos) break;
    p.resize(dot);
  }
  throw InputError(SourcePosition{source, 0, 0}, field, message);
}

/// yaml-cpp 0.7 (Debian 12) never returns from LoadAll when a document's first token is a ',' (found by fuzz_scene:
/// ",` !" hung `geartopo gear` for ever; docs/robustness.md, "Findings": finding 22). A ',' is a flow indicator and
/// cannot start a document, so such a text is refused here, before the parser sees it, at the comma's line and
/// column, also behind a tag or an anchor; so is a control character, which YAML does not allow and which hid such a
/// comma.
void refuse_what_hangs_yaml_cpp(const std::string& text, const ReadContext& ctx) {
  // YAML's character set (1.2, c-printable) excludes the C0 controls but TAB, LF and CR, and DEL: a NUL in front of
  // the ',' hid it from the check below and hung the parser again (the second fuzzing run). Refused, located.
  int control_line = 0;
  size_t line_start = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') ++control_line, line_start = i + 1;
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7F) {
      YAML::Mark mark;
      mark.line = control_line;
      mark.column = static_cast<int>(i - line_start);
      mark.pos = static_cast<int>(i);
      ctx.fail(mark, "", fmt::format("control character U+{:04X}: YAML allows none but tab, line feed and carriage "
                                     "return (is this a text file?)", static_cast<unsigned>(c)));
    }
  }
  bool at_start = true;
  int line = 0;
  size_t begin = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  while (begin <= text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string_view l(text.data() + begin, end - begin);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    const bool marker = (l.substr(0, 3) == "---" || l.substr(0, 3) == "...") && (l.size() == 3 || l[3] == ' ' || l[3] == '\t');
    size_t col = 0;
    if (marker) {
      at_start = true;
      col = 3;
    }
    if (at_start) {
      while (col < l.size() && (l[col] == ' ' || l[col] == '\t')) ++col;
      // Node properties — a tag '!…' or an anchor '&…' — in front of the ',' hang it as well (" ! ," in the third
      // fuzzing run): looked through.
      size_t first = col;
      while (first < l.size() && (l[first] == '!' || l[first] == '&')) {
        while (first < l.size() && l[first] != ' ' && l[first] != '\t' && l[first] != ',') ++first;
        while (first < l.size() && (l[first] == ' ' || l[first] == '\t')) ++first;
      }
      if (first < l.size() && l[first] == ',') {
        YAML::Mark mark;
        mark.line = line;
        mark.column = static_cast<int>(first);
        mark.pos = static_cast<int>(begin + first);
        ctx.fail(mark, "", "YAML syntax error: a document cannot start with ',' (a flow indicator)");
      }
      if (col < l.size() && l[col] != '#' && !(l[col] == '%' && !marker)) at_start = false;
    }
    ++line;
    begin = end + 1;
  }
}

namespace {

/// Remembers where a document starts; every other event is ignored (nothing is built).
struct DocumentStart final : YAML::EventHandler {
  std::optional<YAML::Mark> mark;
  void OnDocumentStart(const YAML::Mark& m) override { mark = m; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

/// Where the text's second YAML document starts, if it has one. Two documents at most are read: yaml-cpp 0.7's
/// LoadAll loops for ever — a null document per turn, all of the memory — when a token no node starts with follows
/// the root ("- a\n,", "&a x\n,", "\"q\" ,": the fifth fuzzing run; yaml-cpp#1040, fixed upstream by #1319), so it is
/// not called: the first document is then read alone (YAML::Load).
std::optional<YAML::Mark> second_document(const std::string& text) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentStart first, second;
  if (!parser.HandleNextDocument(first) || !parser.HandleNextDocument(second)) return std::nullopt;
  return second.mark;
}

} // namespace

YAML::Node load_one_document(const std::string& text, const ReadContext& ctx, std::string_view what) {
  YAML::Node root;
  try {
    refuse_what_hangs_yaml_cpp(text, ctx);
    // A second document is refused: YAML::Load would read the first and silently drop the rest ("---").
    if (const auto second = second_document(text)) {
      const auto at = std::min(static_cast<size_t>(std::max(second->pos, 0)), text.size());
      if (text.compare(at, 3, "---") == 0)
        ctx.fail(*second, "", fmt::format("a second YAML document ('---'): a {} is one document (merge them or "
                                          "split the file)", what));
      size_t n = 1; // the whole UTF-8 character
      while (at + n < text.size() && (static_cast<unsigned char>(text[at + n]) & 0xC0) == 0x80) ++n;
      const std::string token = text.substr(at, n);
      ctx.fail(*second, "", fmt::format("YAML syntax error: '{}' after the document's root node{}", text::excerpt(token),
                                        token == "," ? " (a ',' belongs in a [ ] or { } list)" : ""));
    }
    root = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    // yaml-cpp stops at a fixed depth and reports it only as "bad file".
    ctx.fail(e.mark, "", fmt::format("YAML nested deeper than {} levels, the parser's limit", e.depth()));
  } catch (const YAML::ParserException& e) {
    ctx.fail(e.mark, "", "YAML syntax error: " + e.msg);
  }
  return root;
}

Scene parse_scene(const std::string& text, const std::string& source) {
  ReadContext ctx{source, {}};
  const YAML::Node root = load_one_document(text, ctx, "scene");
  if (!root.IsDefined() || root.IsNull()) ctx.fail(YAML::Mark::null_mark(), "", "empty scene (a 'gear' map is needed)");

  Scene scene;
  scene.source = source;
  MapReader top(root, "", ctx);
  scene.name = top.optional_text("name").value_or("");
  scene.description = top.optional_text("description").value_or("");
  MapReader gear = top.map("gear");
  scene.gear = read_gear(gear, scene, std::filesystem::path(source).parent_path());
  if (auto mm = top.optional_map("machine"))
    scene.machine = read_machine(*mm, std::filesystem::path(source).parent_path(), scene.gear.face_width_mm);
  else
    scene.machine.datum_face_z_mm = centred_datum_z(scene.machine.strokes, scene.gear.face_width_mm);
  if (auto w = top.optional_map("wheel")) scene.wheel = read_wheel(*w);
  if (auto p = top.optional_map("process")) scene.process = read_process(*p);
  if (auto m = top.optional_map("measurement"))
    scene.grid = read_grid(*m, scene.gear.teeth, std::filesystem::path(source).parent_path());
  read_all_effects(top, ctx, scene);
  read_machine_changes(top, ctx, scene);
  if (auto r = top.optional_map("report")) {
    scene.report.part = r->optional_text("part").value_or("");
    scene.report.drawing = r->optional_text("drawing").value_or("");
    scene.report.operator_name = r->optional_text("operator").value_or("");
    scene.report.measuring_machine = r->optional_text("measuring_machine").value_or("");
    scene.report.probe_diameter_mm = r->optional_number("probe_diameter_mm", positive_length_mm(100.0));
    if (r->has("tolerance_class")) scene.report.tolerance_class = static_cast<int>(r->integer("tolerance_class", 1, 11));
    r->finish();
  }
  top.finish();

  // Domain rules that involve several fields (undercut, pointed tip, form diameter) live in GearGeometry; locate
  // what it reports in the file.
  try {
    gears::GearGeometry check(scene.gear);
    gears::FlankDesign design(check, gears::iso1328_ranges(check), scene.gear.modifications); // where reliefs start
    // A wheel the scene gives is checked against the gear here, so every command (also `gear`, which builds no
    // set-up) refuses one that cannot grind it; without one the workbench picks a diameter that fits.
    if (ctx.marks.count("wheel.outer_diameter_mm") != 0) grinding::check_wheel_diameter(check, scene.wheel.outer_diameter_mm);
  } catch (const FieldError& e) {
    ctx.fail_field(e.field(), e.what());
  }
  for (const auto& [field, mark] : ctx.marks)
    scene.positions[field] = SourcePosition{source, mark.is_null() ? 0 : mark.line + 1, mark.is_null() ? 0 : mark.column + 1};
  return scene;
}

Scene load_scene(const std::filesystem::path& file) {
  return parse_scene(input::read_input_file(file, input::kMaxSceneBytes, "scene file"), file.string());
}

} // namespace geartopo::scene
