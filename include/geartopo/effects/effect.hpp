// geartopo — a physical effect beyond the machine's geometric errors (docs/adding-an-effect.md).
//
// An effect acts through the simulator, never on its output: it may offset the axis commands the machine receives
// (thermal growth, deflection, servo lag, head vibration), displace the gear against the C table (eccentricity,
// wobble), or change the wheel's radius (wear, dressing errors). Parameters are kept in the units of the scene file
// (named in each parameter's key, e.g. "x_growth_um"); hooks return mm and rad.
#pragma once

#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/wheel_path.hpp"
#include "geartopo/machine/twist.hpp"

#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::effects {

struct ParameterSpec {
  std::string key;       ///< scene key with its unit, e.g. "x_growth_um"
  std::string meaning;   ///< one line
  double default_value;  ///< file units
  double lo, hi;         ///< allowed range, file units
  double typical;        ///< typical magnitude (file units): fitting scale and step
  bool fitted = true;    ///< identified by `diagnose`; false: a set-up value the user must know (e.g. arbor span)
  std::vector<double> starts{}; ///< start values for fitting a parameter the deviations depend on nonlinearly
  /// Where a real machine's value lies (file units; engineering judgement, listed in docs/diagnosis.md). A fit that
  /// needs a value beyond it by more than 2σ is no explanation (diagnosis rejects it). NaN: the allowed range [lo, hi].
  double plausible_lo = std::numeric_limits<double>::quiet_NaN();
  double plausible_hi = std::numeric_limits<double>::quiet_NaN();
  bool whole = false;    ///< a count (e.g. strokes between dressings): the scene must give a whole number
  /// The deviation is proportional to this parameter: with the effect's other parameters fixed, it is Σ θ_k b_k over
  /// its `linear` parameters k (jointly linear, zero when they are all zero). A fit then takes the parameter's
  /// Jacobian column in closed form, b_k, instead of by finite differences (diagnosis/effect_fit.cpp); tests/diagnosis
  /// checks every claim against finite differences of the simulator's own first-order model.
  bool linear = false;
};

class Effect {
public:
  virtual ~Effect() = default;

  /// Scene `type:` of the effect, e.g. "thermal_drift".
  virtual std::string_view type() const = 0;
  /// One line of physics, shown with diagnosis results.
  virtual std::string_view explanation() const = 0;
  virtual const std::vector<ParameterSpec>& parameters() const = 0;
  virtual std::unique_ptr<Effect> clone() const = 0;

  /// Called once before use, with the grinding set-up (gear, wheel, path). The set-up must outlive the effect.
  virtual void bind(const grinding::GrindingSetup& setup) { setup_ = &setup; }

  /// Added to the machine's axis commands at pp: δX, δY, δZ (mm), δA, δC (rad) — the slides along x, y, z, the swivel
  /// and the spindle, which EffectsProcess gives to the chain's axes of those roles (effects::chain_offsets).
  virtual machine::Vector5d command_offset(const grinding::PathPoint& /*pp*/) const { return machine::Vector5d::Zero(); }
  /// Pose of the machine's table frame in the gear frame (identity for a perfectly mounted gear).  wMc
  virtual machine::Pose table_in_gear(const grinding::PathPoint& /*pp*/) const { return machine::Pose::Identity(); }
  /// True when table_in_gear gives the same pose at every path point (a clamping error, fixed for the gear): a caller
  /// evaluating many points may then call it once per parameter set (diagnosis::EffectContribution). The default
  /// claims nothing; an effect that keeps the default identity table or mounts the gear once may say true
  /// (tests/effects checks the claim of every library effect at random path points).
  virtual bool table_in_gear_is_constant() const { return false; }
  /// Change of the wheel radius at wheel axial coordinate v (mm; positive: bigger wheel, deeper cut).
  virtual double wheel_radius_error_mm(double /*v*/, const grinding::PathPoint& /*pp*/) const { return 0.0; }
  /// wheel_radius_error_mm at n contacts known up front: out[i] at (v[i], pp[i]). The default asks per point; an effect
  /// whose law costs per call rather than per point (a Python function: one call per batch) says so by
  /// evaluates_in_batches, and callers holding many contacts (diagnosis, the scene's checks) then call this instead.
  virtual void wheel_radius_errors_mm(std::span<const double> v, std::span<const grinding::PathPoint> pp,
                                      std::span<double> out) const;
  virtual bool evaluates_in_batches() const { return false; }

  /// Parameter values, file units, in the order of parameters().
  const std::vector<double>& values() const { return values_; }
  void set_values(std::vector<double> v);
  double value(size_t i) const { return values_[i]; }
  /// Index of the parameter with this key; throws std::out_of_range naming the effect and the key.
  size_t index_of(std::string_view key) const;

protected:
  void init_defaults();
  const grinding::GrindingSetup& setup() const;

  std::vector<double> values_;
  const grinding::GrindingSetup* setup_ = nullptr;
};

} // namespace geartopo::effects
