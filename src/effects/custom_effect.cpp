// The user's law as an effect (custom_effect.hpp). The expression is compiled by muParser; each thread keeps its own
// compiled copy per law (a muParser object binds its variables by pointer and is not safe to share), filled with the
// parameter values and the contact variables before each evaluation.
#include "geartopo/effects/custom_effect.hpp"

#include "geartopo/core/units.hpp"
#include "geartopo/effects/registry.hpp"
#include "stroke_table.hpp"
#include "strokes_since_dressing.hpp"

#include <fmt/format.h>
#include <muParser.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <unordered_map>

namespace geartopo::effects {
namespace {

// ------------------------------------------------------------------------------------------------ the compiled law

/// One thread's compiled copy of a law: the parser and the storage its variables are bound to.
struct Compiled {
  mu::Parser parser;
  std::vector<double> parameters;
  std::array<double, kContactVariableCount> variables{};
};

bool identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

/// muParser's message, said in the terms of a scene: an unknown name is a variable or a function.
ExpressionError expression_error(const mu::Parser::exception_type& e, const std::string& expression) {
  const int pos = std::clamp(static_cast<int>(e.GetPos()), 0, static_cast<int>(expression.size()));
  const std::string token = e.GetToken();
  std::string message;
  if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN && identifier(token)) {
    std::size_t after = static_cast<std::size_t>(pos) + token.size();
    while (after < expression.size() && expression[after] == ' ') ++after;
    const bool call = after < expression.size() && expression[after] == '(';
    message = call ? fmt::format("unknown function '{}'", token)
                   : fmt::format("unknown variable '{}' (neither a parameter of this effect nor a contact variable)", token);
  } else {
    message = e.GetMsg();
    if (const auto at = message.find(" at position"); at != std::string::npos) message.resize(at);
    if (const auto at = message.find(" found at position"); at != std::string::npos) message.resize(at);
  }
  return ExpressionError(fmt::format("{} at character {} of the expression", message, pos + 1), pos);
}

/// table(x, x0, y0, x1, y1, …): y at x interpolated linearly between the pairs (x_k increasing), constant beyond the
/// ends — a law measured as a time table (a coolant temperature log). NaN when the pairs are not increasing in x or
/// incomplete (the caller refuses the non-finite value, naming the point).
double table(const double* a, int n) {
  if (n < 3 || (n - 1) % 2 != 0) return std::numeric_limits<double>::quiet_NaN();
  const double x = a[0];
  const int pairs = (n - 1) / 2;
  for (int k = 1; k < pairs; ++k)
    if (!(a[1 + 2 * k] > a[1 + 2 * (k - 1)])) return std::numeric_limits<double>::quiet_NaN();
  if (x <= a[1]) return a[2];
  for (int k = 1; k < pairs; ++k) {
    const double x0 = a[1 + 2 * (k - 1)], y0 = a[2 + 2 * (k - 1)], x1 = a[1 + 2 * k], y1 = a[2 + 2 * k];
    if (x <= x1) return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
  }
  return a[n - 1];
}

std::unique_ptr<Compiled> compile(const std::vector<CustomParameter>& params, const std::string& expression) {
  auto c = std::make_unique<Compiled>();
  c->parameters.resize(params.size());
  try {
    for (std::size_t k = 0; k < params.size(); ++k) c->parameters[k] = params[k].value;
    c->parser.DefineFun("table", table);
    for (std::size_t k = 0; k < kContactVariableCount; ++k)
      c->parser.DefineVar(std::string(kContactVariableNames[k]), &c->variables[k]);
    for (std::size_t k = 0; k < params.size(); ++k) c->parser.DefineVar(params[k].key, &c->parameters[k]);
    c->parser.SetExpr(expression);
    (void)c->parser.Eval(); // muParser compiles on the first evaluation: syntax and names are checked here
  } catch (const mu::Parser::exception_type& e) {
    throw expression_error(e, expression);
  }
  return c;
}

std::atomic<std::uint64_t> next_law_id{1};

double typical_of(const CustomParameter& p) { return std::max(std::abs(p.max), std::abs(p.min)) / 10.0; }

/// Where diagnose's fit starts, from the bounds alone (the declared `value` is the truth simulate uses, not a start: a
/// law registered by another scene with other values then fits the same): 0 when the range holds it (an amplitude),
/// else the range's middle — in the logarithm for a positive range over more than a decade (a time constant).
double neutral_start(const CustomParameter& p) {
  if (p.min <= 0.0 && p.max >= 0.0) return 0.0;
  if (p.min > 0.0 && p.max > 10.0 * p.min) return std::sqrt(p.min * p.max);
  return 0.5 * (p.min + p.max);
}

/// Fitting starts: the neutral start, and for a positive range spanning more than a decade three more points spread
/// evenly in its logarithm, so that a fit does not stay in the first local minimum.
std::vector<double> starts_of(const CustomParameter& p) {
  std::vector<double> s{neutral_start(p)};
  if (p.min > 0.0 && p.max > 10.0 * p.min)
    for (double f : {1.0 / 6.0, 1.0 / 3.0, 5.0 / 6.0}) s.push_back(p.min * std::pow(p.max / p.min, f));
  return s;
}

// ------------------------------------------------------------------------------------------------ the effect

class CustomEffect final : public Effect {
public:
  explicit CustomEffect(std::shared_ptr<const CustomLaw> law) : law_(std::move(law)) { init_defaults(); }
  /// A copy shares the law and the contact map, not the stroke tables: its values are its own.
  CustomEffect(const CustomEffect& o) : Effect(o), law_(o.law_), map_(o.map_) {}
  CustomEffect& operator=(const CustomEffect&) = delete;
  std::string_view type() const override { return law_->name(); }
  std::string_view explanation() const override { return law_->explanation(); }
  const std::vector<ParameterSpec>& parameters() const override { return law_->parameters(); }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<CustomEffect>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table
  void bind(const grinding::GrindingSetup& setup) override {
    Effect::bind(setup);
    map_ = std::make_shared<const ContactMap>(setup);
    tables_ = std::make_shared<Tables>();
  }
  /// The law's value at the flank point v touches, as the wheel's radial change there: a normal deviation e (plus
  /// material) is the wheel smaller by e along its normal, −e / normal_per_radial(v) radially. A function law is read
  /// from its stroke's table (stroke_table.hpp): one call per stroke, not per point.
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    if (law_->function()) {
      const int side = map_->side_of(v);
      const double e_um = table(pp.space)->deviation_um(side, map_->roll_at(side, v), pp.z_stroke_mm);
      return -units::mm_from_um(e_um) / setup().wheel().normal_per_radial(v);
    }
    const ContactVariables at = map_->at(v, pp, law_->dressing_interval_strokes());
    const double e_um = law_->deviation_um(values_, at);
    if (!std::isfinite(e_um)) throw NonFiniteDeviation(non_finite_message(*law_, e_um, at, values_));
    return -units::mm_from_um(e_um) / setup().wheel().normal_per_radial(v);
  }
  bool evaluates_in_batches() const override { return law_->function() != nullptr; }
  /// A function law at the contacts themselves, in one call (no table): what diagnosis and the scene's checks use.
  void wheel_radius_errors_mm(std::span<const double> v, std::span<const grinding::PathPoint> pp,
                              std::span<double> out) const override {
    if (!law_->function()) return Effect::wheel_radius_errors_mm(v, pp, out);
    std::vector<ContactVariables> at(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) at[i] = map_->at(v[i], pp[i], law_->dressing_interval_strokes());
    law_->deviations_um(values_, at, out);
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!std::isfinite(out[i])) throw NonFiniteDeviation(non_finite_message(*law_, out[i], at[i], values_));
      out[i] = -units::mm_from_um(out[i]) / setup().wheel().normal_per_radial(v[i]);
    }
  }

private:
  /// The stroke tables of a function law at the values they were made with; made when first asked for, under the
  /// lock (a table depends on the values and the stroke only, so whichever thread makes it, it is the same).
  struct Tables {
    std::mutex mutex;
    std::vector<double> values;
    std::vector<std::shared_ptr<const StrokeTable>> by_space; ///< [space − 1]
  };
  std::shared_ptr<const StrokeTable> table(int space) const {
    const std::lock_guard lock(tables_->mutex);
    if (tables_->by_space.empty() || tables_->values != values_) {
      tables_->values = values_;
      tables_->by_space.assign(static_cast<std::size_t>(setup().geometry().teeth()), nullptr);
    }
    auto& t = tables_->by_space.at(static_cast<std::size_t>(space - 1));
    if (!t) t = std::make_shared<const StrokeTable>(*law_, values_, *map_, setup(), space);
    return t;
  }

  std::shared_ptr<const CustomLaw> law_;
  std::shared_ptr<const ContactMap> map_;
  std::shared_ptr<Tables> tables_ = std::make_shared<Tables>();
};

std::mutex registry_mutex;
std::map<std::string, std::shared_ptr<const CustomLaw>, std::less<>>& registry() {
  static std::map<std::string, std::shared_ptr<const CustomLaw>, std::less<>> r;
  return r;
}

} // namespace

// ---------------------------------------------------------------------------------------------------- ContactMap

ContactMap::ContactMap(const grinding::GrindingSetup& setup) : setup_(setup) {
  const auto& g = setup.geometry();
  const auto& wheel = setup.wheel();
  // The roll lengths the form wheel was synthesised over (form_wheel.cpp), each flank's contact line at Z = 0 in
  // space 1, seen from the wheel: its axial coordinate v.
  const double xi_ff = g.roll_length_at(g.root_form_diameter_mm()), xi_a = g.roll_length_at(g.tip_diameter_mm());
  const double xi_lo = std::max(xi_ff - 1.0, 0.5 * xi_ff), xi_hi = xi_a + 1.0;
  const int n = std::max(400, static_cast<int>(std::ceil((xi_hi - xi_lo) / 0.025)) + 1);
  const machine::Pose gMw = wheel.reference_wMg().inverse();
  for (std::size_t s = 0; s < 2; ++s) {
    const auto flank = s == 0 ? geartopo::Flank::Right : geartopo::Flank::Left;
    const int tooth = flank == geartopo::Flank::Right ? 1 : 2; // space 1, as the form wheel was synthesised
    std::vector<std::pair<double, double>> v_xi;
    for (int i = 0; i < n; ++i) {
      const double xi = xi_lo + (xi_hi - xi_lo) * i / (n - 1);
      const Eigen::Vector3d p = setup.flanks().at(tooth, flank, xi, wheel.contact_offset_mm(flank, xi)).p;
      v_xi.emplace_back((gMw * p).y(), xi);
    }
    std::sort(v_xi.begin(), v_xi.end());
    std::vector<double> v, xi;
    for (const auto& [a, b] : v_xi)
      if (v.empty() || a > v.back()) v.push_back(a), xi.push_back(b);
    // ξ runs one way along v on a wheel flank: the inverse from the same pairs, in increasing ξ.
    std::vector<double> xi_up = xi, v_up = v;
    if (xi_up.front() > xi_up.back()) std::reverse(xi_up.begin(), xi_up.end()), std::reverse(v_up.begin(), v_up.end());
    sides_[s] = Side{flank, geartopo::CubicSpline(v, xi, geartopo::CubicSpline::Ends::NotAKnot),
                     geartopo::CubicSpline(xi_up, v_up, geartopo::CubicSpline::Ends::NotAKnot), v.front(), v.back()};
  }
}

double ContactMap::roll_at(int side, double v) const {
  const Side& s = sides_[static_cast<std::size_t>(side)];
  return s.xi_of_v.value(std::clamp(v, s.v_lo, s.v_hi));
}

double ContactMap::v_at_roll(int side, double xi) const { return sides_[static_cast<std::size_t>(side)].v_of_xi.value(xi); }

int ContactMap::side_of(double v) const {
  // Between the wheel flanks (the wheel's tip blend, below the root form circle) the nearer one.
  const auto distance = [v](const Side& s) { return v < s.v_lo ? s.v_lo - v : (v > s.v_hi ? v - s.v_hi : 0.0); };
  return distance(sides_[0]) <= distance(sides_[1]) ? 0 : 1;
}

ContactVariables ContactMap::at_side(int side_index, double v, const grinding::PathPoint& pp,
                                     int dressing_interval) const {
  const Side& side = sides_[static_cast<std::size_t>(side_index)];
  const double xi = side.xi_of_v.value(std::clamp(v, side.v_lo, side.v_hi));
  const auto& g = setup_.geometry();
  const auto& path = setup_.path();
  const int teeth = g.teeth();
  // Space s holds the right flank of tooth s and the left flank of tooth s + 1 (wheel_path.hpp).
  const int tooth = side.flank == geartopo::Flank::Right ? pp.space : pp.space % teeth + 1;
  const double z = pp.z_stroke_mm + setup_.wheel().contact_offset_mm(side.flank, xi);
  const gears::FlankPoint fp = setup_.flanks().at(tooth, side.flank, xi, z);
  ContactVariables c;
  c.t_s = pp.time_s;
  c.stroke = path.stroke_index(pp.space);
  c.strokes_since_dressing = strokes_since_dressing(setup_, pp, dressing_interval);
  c.tooth = tooth;
  c.side = side.flank == geartopo::Flank::Right ? 1.0 : -1.0;
  c.x_mm = fp.p.x(), c.y_mm = fp.p.y(), c.z_mm = fp.p.z();
  c.r_mm = std::hypot(fp.p.x(), fp.p.y());
  c.roll_mm = xi;
  c.nx = fp.n.x(), c.ny = fp.n.y(), c.nz = fp.n.z();
  c.c_deg = units::deg_from_rad(pp.q.c);
  c.X_mm = pp.q.x, c.Y_mm = pp.q.y, c.Z_mm = pp.q.z;
  c.A_deg = units::deg_from_rad(pp.q.a);
  c.wheel_r_mm = setup_.wheel().radius(v);
  return c;
}

// ---------------------------------------------------------------------------------------------------- CustomLaw

CustomLaw::CustomLaw(std::string name, std::vector<CustomParameter> parameters, std::string expression,
                     int dressing_interval_strokes)
    : name_(std::move(name)), expression_(std::move(expression)), declared_(std::move(parameters)),
      dressing_interval_(dressing_interval_strokes), id_(next_law_id++) {
  check_parameters();
  (void)compile(declared_, expression_); // throws ExpressionError
  explanation_ = fmt::format("your effect (custom_effects): deviation_um = {}", expression_);
}

CustomLaw::CustomLaw(std::string name, std::vector<CustomParameter> parameters,
                     std::shared_ptr<const BatchLaw> function, std::string description, int dressing_interval_strokes)
    : name_(std::move(name)), expression_(std::move(description)), declared_(std::move(parameters)),
      function_(std::move(function)), dressing_interval_(dressing_interval_strokes), id_(next_law_id++) {
  if (!function_ || !*function_) throw std::invalid_argument(fmt::format("custom effect '{}': no function", name_));
  check_parameters();
  explanation_ = fmt::format("your effect (Python function {0}): deviation_um = {0}(params, state)", expression_);
}

void CustomLaw::check_parameters() {
  for (const auto& p : declared_) {
    if (!identifier(p.key)) throw std::invalid_argument(fmt::format("'{}' is not a name (letters, digits, _)", p.key));
    if (std::find(kContactVariableNames.begin(), kContactVariableNames.end(), p.key) != kContactVariableNames.end())
      throw std::invalid_argument(fmt::format("'{}' is a contact variable: name the parameter otherwise", p.key));
    if (!(std::isfinite(p.min) && std::isfinite(p.max) && p.min < p.max))
      throw std::invalid_argument(fmt::format("'{}': min {} must be below max {}", p.key, p.min, p.max));
    if (!(p.value >= p.min && p.value <= p.max))
      throw std::invalid_argument(fmt::format("'{}': value {} outside [min, max] = [{}, {}]", p.key, p.value, p.min, p.max));
    specs_.push_back(ParameterSpec{p.key, fmt::format("{} ({})", p.key, p.unit), neutral_start(p), p.min, p.max,
                                   typical_of(p), true, starts_of(p)});
  }
}

double CustomLaw::deviation_um(const std::vector<double>& values, const ContactVariables& at) const {
  if (function_) {
    double out = 0.0;
    (*function_)(values, std::span<const ContactVariables>(&at, 1), std::span<double>(&out, 1));
    return out;
  }
  thread_local std::unordered_map<std::uint64_t, std::unique_ptr<Compiled>> compiled;
  auto& c = compiled[id_];
  if (!c) c = compile(declared_, expression_);
  std::copy(values.begin(), values.end(), c->parameters.begin());
  std::copy(as_array(at), as_array(at) + kContactVariableCount, c->variables.begin());
  return c->parser.Eval();
}

void CustomLaw::deviations_um(const std::vector<double>& values, std::span<const ContactVariables> at,
                              std::span<double> out) const {
  if (function_) return (*function_)(values, at, out);
  for (std::size_t i = 0; i < at.size(); ++i) out[i] = deviation_um(values, at[i]);
}

bool CustomLaw::same_law(const CustomLaw& o) const {
  if (name_ != o.name_ || expression_ != o.expression_ || dressing_interval_ != o.dressing_interval_ ||
      function_ != o.function_ || declared_.size() != o.declared_.size())
    return false;
  for (std::size_t k = 0; k < declared_.size(); ++k) {
    const auto &a = declared_[k], &b = o.declared_[k];
    if (a.key != b.key || a.min != b.min || a.max != b.max || a.unit != b.unit) return false;
  }
  return true;
}

std::string point_message(const CustomLaw& law, const ContactVariables& at, const std::vector<double>& values) {
  std::string vars;
  for (std::size_t k = 0; k < law.declared().size() && k < values.size(); ++k)
    vars += fmt::format("{} = {:.6g}, ", law.declared()[k].key, values[k]);
  for (std::size_t k = 0; k < kContactVariableCount; ++k)
    vars += fmt::format("{}{} = {:.6g}", k == 0 ? "" : ", ", kContactVariableNames[k], as_array(at)[k]);
  return fmt::format("tooth {}, {} flank, d = {:.3f} mm, z = {:.3f} mm, where {}", static_cast<int>(at.tooth),
                     at.side > 0 ? "right" : "left", 2.0 * at.r_mm, at.z_mm, vars);
}

std::string non_finite_message(const CustomLaw& law, double value, const ContactVariables& at,
                               const std::vector<double>& values) {
  return fmt::format("custom effect '{}': deviation_um = {} is not finite at {}", law.name(), value,
                     point_message(law, at, values));
}

std::unique_ptr<Effect> make_custom_effect(std::shared_ptr<const CustomLaw> law) {
  return std::make_unique<CustomEffect>(std::move(law));
}

std::vector<double> declared_values(const CustomLaw& law) {
  std::vector<double> v;
  for (const auto& p : law.declared()) v.push_back(p.value);
  return v;
}

void register_custom_law(std::shared_ptr<const CustomLaw> law) {
  const auto& library = effect_types();
  if (std::find(library.begin(), library.end(), law->name()) != library.end())
    throw std::invalid_argument(fmt::format("'{}' is an effect of the library: give your effect another name", law->name()));
  const std::lock_guard lock(registry_mutex);
  auto& r = registry();
  if (const auto it = r.find(law->name()); it != r.end()) {
    if (!it->second->same_law(*law))
      throw std::invalid_argument(fmt::format(
          "a custom effect named '{}' with another law (deviation_um = {}) is in use in this process: give this one "
          "another name",
          law->name(), it->second->expression()));
    return;
  }
  r.emplace(law->name(), std::move(law));
}

std::shared_ptr<const CustomLaw> find_custom_law(std::string_view name) {
  const std::lock_guard lock(registry_mutex);
  const auto& r = registry();
  const auto it = r.find(name);
  return it == r.end() ? nullptr : it->second;
}

} // namespace geartopo::effects
