// geartopo — an effect the user declares without C++ (docs/scene-format.md, "custom_effects"; docs/tutorial.md,
// "Adding your own physics"): a deviation law deviation_um = f(parameters, contact state) written as an expression of
// muParser (Debian's libmuparser-dev), compiled once to its bytecode and evaluated with the variables bound by
// pointer. The effect acts through the simulator like every library effect: at a point of the wheel path the wheel is
// made bigger or smaller at its axial coordinate v by the law's value at the flank point that v touches there, so the
// ground flank moves along its normal by the law's value — in the exact envelope, the first-order model, the fit,
// compensation and the Monte Carlo alike.
// Units: the law's value µm (plus material positive); the variables' units are in their names (ContactVariables).
#pragma once

#include "geartopo/core/cubic_spline.hpp"
#include "geartopo/core/flank.hpp"
#include "geartopo/effects/effect.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::effects {

/// The contact state of a ground point: the variables of a custom law, in this order (kContactVariableNames), each
/// defined in docs/scene-format.md, "custom_effects". Gear frame: z along the gear axis from the datum face.
struct ContactVariables {
  double t_s = 0.0;                    ///< grinding time of the contact since the first stroke began (s)
  double stroke = 0.0;                 ///< the stroke's place in the grinding order: 0 for the first (count)
  double strokes_since_dressing = 0.0; ///< strokes since the last dressing, fractional along the running stroke
  double tooth = 0.0;                  ///< tooth number 1 … z (ISO 1328)
  double side = 0.0;                   ///< +1 right flank, −1 left flank
  double x_mm = 0.0, y_mm = 0.0, z_mm = 0.0; ///< the flank point in the gear frame (mm)
  double r_mm = 0.0;                   ///< its radius √(x² + y²) (mm)
  double roll_mm = 0.0;                ///< its roll length ξ = √(r² − r_b²) (mm)
  double nx = 0.0, ny = 0.0, nz = 0.0; ///< the unit flank normal out of the material, gear frame
  double c_deg = 0.0;                  ///< C command at the contact, [0, 360) (deg)
  double X_mm = 0.0, Y_mm = 0.0, Z_mm = 0.0; ///< X, Y commands; Z command from the datum face (mm)
  double A_deg = 0.0;                  ///< A command (deg)
  double wheel_r_mm = 0.0;             ///< the nominal wheel radius R(v) at the contact (mm)
};
inline constexpr std::size_t kContactVariableCount = 19;
static_assert(sizeof(ContactVariables) == kContactVariableCount * sizeof(double));
inline constexpr std::array<std::string_view, kContactVariableCount> kContactVariableNames{
    "t_s", "stroke", "strokes_since_dressing", "tooth", "side", "x_mm", "y_mm", "z_mm", "r_mm", "roll_mm",
    "nx", "ny", "nz", "c_deg", "X_mm", "Y_mm", "Z_mm", "A_deg", "wheel_r_mm"};
/// The variables as an array in kContactVariableNames order.
inline const double* as_array(const ContactVariables& v) { return &v.t_s; }

/// Where on the nominal flank the wheel at a path point touches with its axial coordinate v: the inverse of the form
/// wheel's two contact lines (form_wheel.hpp), a roll length ξ(v) per wheel flank, then z = Z + z_c(ξ). Const after
/// bind; shared by every custom effect on one set-up.
class ContactMap {
public:
  explicit ContactMap(const grinding::GrindingSetup& setup);
  /// The contact variables at wheel coordinate v (mm) at path point pp, strokes since dressing counted with
  /// `dressing_interval` (< 1: not dressed during the gear).
  ContactVariables at(double v, const grinding::PathPoint& pp, int dressing_interval) const {
    return at_side(side_of(v), v, pp, dressing_interval);
  }
  /// The wheel flank v lies on (0: the one grinding right flanks, 1: left); between them the nearer one.
  int side_of(double v) const;
  /// The contact variables at v on wheel flank `side`, v clamped into its range for the roll length.
  ContactVariables at_side(int side, double v, const grinding::PathPoint& pp, int dressing_interval) const;
  /// The wheel coordinates (mm) wheel flank `side` grinds the flank over (its roll lengths ξ_Ff − 1 … ξ_a + 1 mm).
  double v_lo(int side) const { return sides_[static_cast<std::size_t>(side)].v_lo; }
  double v_hi(int side) const { return sides_[static_cast<std::size_t>(side)].v_hi; }
  /// The roll length ξ (mm) wheel flank `side` grinds at v (v clamped into its range), and the inverse: the v at ξ.
  double roll_at(int side, double v) const;
  double v_at_roll(int side, double xi) const;

private:
  struct Side {
    geartopo::Flank flank;
    geartopo::CubicSpline xi_of_v; ///< over the wheel flank's v range, increasing v
    geartopo::CubicSpline v_of_xi; ///< its inverse, over increasing ξ
    double v_lo, v_hi;
  };
  const grinding::GrindingSetup& setup_;
  std::array<Side, 2> sides_;
};

/// One parameter of a custom law, file units.
struct CustomParameter {
  std::string key;
  double value = 0.0, min = 0.0, max = 0.0;
  std::string unit;
};

/// A law the expression cannot be compiled into: the message and the character (0-based) of the expression at fault.
class ExpressionError : public std::runtime_error {
public:
  ExpressionError(const std::string& message, int position) : std::runtime_error(message), position_(position) {}
  int position() const noexcept { return position_; }

private:
  int position_;
};

/// A law given as a function evaluated on a batch of contacts (a Python function,
/// python/src/custom_effect_binding.cpp): out[i] = the deviation (µm, plus material) with the parameter values
/// `values` (file units, parameters() order) at at[i]. It may throw (the exception goes to the caller as it is);
/// non-finite values are refused by the caller.
using BatchLaw = std::function<void(const std::vector<double>& values, std::span<const ContactVariables> at,
                                    std::span<double> out)>;

/// The user's law: its name, parameters and expression, compiled once (the constructor checks it: syntax, unknown
/// variables and functions) and evaluated thread-safely (each thread its own compiled copy, variables bound by
/// pointer). Immutable.
class CustomLaw {
public:
  /// Throws ExpressionError (syntax, unknown variable or function, a parameter named like a variable) and
  /// std::invalid_argument (a parameter's bounds).
  CustomLaw(std::string name, std::vector<CustomParameter> parameters, std::string expression,
            int dressing_interval_strokes = 0);
  /// A law given as a function; `description` names it where an expression would stand (e.g. the Python function's
  /// qualified name). Throws std::invalid_argument (a parameter's name or bounds).
  CustomLaw(std::string name, std::vector<CustomParameter> parameters, std::shared_ptr<const BatchLaw> function,
            std::string description, int dressing_interval_strokes = 0);

  const std::string& name() const { return name_; }
  const std::string& expression() const { return expression_; }
  const std::vector<CustomParameter>& declared() const { return declared_; }
  const std::vector<ParameterSpec>& parameters() const { return specs_; }
  int dressing_interval_strokes() const { return dressing_interval_; }
  /// The function of a law given as one (null for an expression); its description is expression().
  const std::shared_ptr<const BatchLaw>& function() const { return function_; }
  /// "your effect (custom_effects): deviation_um = <expression>"; for a function "your effect (Python function
  /// <description>): deviation_um = <description>(params, state)".
  const std::string& explanation() const { return explanation_; }
  /// The law's value (µm) with these parameter values (file units, parameters() order) at a contact; NaN or ±∞ as
  /// the expression gives it (callers refuse those).
  double deviation_um(const std::vector<double>& values, const ContactVariables& at) const;
  /// The law at a batch of contacts: out[i] at at[i] (out.size() == at.size()); a function law is called once.
  void deviations_um(const std::vector<double>& values, std::span<const ContactVariables> at,
                     std::span<double> out) const;
  /// The same law: name, parameters with their bounds and units, expression, dressing interval (values aside).
  bool same_law(const CustomLaw& other) const;

private:
  std::string name_, expression_, explanation_;
  std::vector<CustomParameter> declared_;
  std::vector<ParameterSpec> specs_;

  void check_parameters();
  std::shared_ptr<const BatchLaw> function_;
  int dressing_interval_ = 0;
  std::uint64_t id_; ///< the key of each thread's compiled copy
};

/// A non-finite value of a law at a point: the point (tooth, flank, diameter, z) and the variables' values there.
class NonFiniteDeviation : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};
/// "custom effect '<name>' = <value> (not finite) at tooth …, right flank, d = … mm, z = … mm, where t_s = …, …".
std::string non_finite_message(const CustomLaw& law, double value, const ContactVariables& at,
                               const std::vector<double>& values);
/// "tooth …, right flank, d = … mm, z = … mm, where <parameter> = …, t_s = …, …": a point and the variables there.
std::string point_message(const CustomLaw& law, const ContactVariables& at, const std::vector<double>& values);

/// An effect of the user's law. Its default values are the fit's neutral starts (0, or the middle of the range), not
/// the declared ones: set those with set_values(declared_values(law)).
std::unique_ptr<Effect> make_custom_effect(std::shared_ptr<const CustomLaw> law);
/// The `value`s the scene declared, in parameter order (file units).
std::vector<double> declared_values(const CustomLaw& law);

/// Custom laws known by name in this process, for effects::make_effect (registry.hpp): a scene that declares one
/// registers it. A name may be registered again only with the same law (same_law): another law under a name already
/// in use would change the meaning of effects made earlier. Throws std::invalid_argument then, and for a name of the
/// library. Thread-safe.
void register_custom_law(std::shared_ptr<const CustomLaw> law);
/// The registered law of that name; null when none.
std::shared_ptr<const CustomLaw> find_custom_law(std::string_view name);

} // namespace geartopo::effects
