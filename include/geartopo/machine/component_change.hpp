// geartopo — an error component that changed since the map was measured, and the law it follows in time
// (docs/error-components.md, "Changes since the map"; scene key `machine_changes`, docs/scene-format.md).
//
// A change adds δe_k(t) to component k at every axis position: constant (δe_k = c), linear in time (δe_k = ρ·t, t the
// time since the first stroke began, as grinding::PathPoint::time_s) or an approach to a steady state
// (δe_k = c_∞·(1 − e^(−t/τ)), the first-order thermal law); a C-axis component may instead have changed periodically
// in the table's turn, k times per revolution (δe_k = a·cos(kγ − φ), γ the commanded C angle: k = 1 an indexing or
// run-out error of a shifted encoder or bearing, k = 2 an elliptic one, …). Its effect on the wheel pose is first order:
// ξ_w = J_twistw_e(q)·δe (machine/first_order.hpp), exact to O(δe·e, δe²) — below 0.02 µm for 400 µrad on a 200 mm
// lever. Units inside: mm and rad (rates per second); in files µm or µrad, rates per minute.
#pragma once

#include "geartopo/machine/error_component.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace geartopo::machine {

class KinematicChain;

enum class ChangeLaw { Constant, LinearInTime, SteadyState, PerRevolution };

/// "constant", "linear_in_time", "steady_state", "per_revolution" (the law alone: law_name says its order too)
std::string_view to_string(ChangeLaw law);

/// A law as the scene and the diagnosis name it: "constant", "linear_in_time", "steady_state", and periodic in C
/// with its order k: "once_per_revolution" (k = 1), "twice_per_revolution" (2), "3_times_per_revolution" (k ≥ 3).
std::string law_name(ChangeLaw law, int order = 1);
struct NamedLaw {
  ChangeLaw law = ChangeLaw::Constant;
  int order = 1; ///< revolutions' order k (PerRevolution), 1 otherwise
};
/// The law of a name law_name gives (k ≤ kMaxRevolutionOrder); nullopt for any other.
std::optional<NamedLaw> law_from_name(std::string_view name);
/// The highest order a periodic change may have (count per revolution): far beyond any gear's z/2.
inline constexpr int kMaxRevolutionOrder = 1000;

struct ComponentChange {
  ComponentId component = ComponentId::delta_xx;
  ChangeLaw law = ChangeLaw::Constant;
  /// Constant: the change c; linear in time: the rate ρ per second; steady state: the final change c_∞; once per
  /// revolution: the amplitude a. mm or rad (per second for the rate).
  double size = 0.0;
  double time_constant_s = 0.0; ///< τ (s), steady state only
  double phase_rad = 0.0;       ///< φ, per revolution only: kγ − φ = 0 where the change is largest
  int order = 1;                ///< k, per revolution only: periods per table revolution (count ≥ 1)
  /// δe_k at time t (s since the first stroke began) and commanded C angle γ (rad), mm or rad.
  double at(double time_s, double c_rad) const { return size * law_shape(time_s, c_rad); }
  /// The law per unit size: 1, t (s), 1 − e^(−t/τ) or cos(kγ − φ).
  double law_shape(double time_s, double c_rad) const;
  /// law_name(law, order): "E_AOA linear_in_time"'s second word.
  std::string law_name() const { return machine::law_name(law, order); }
};

/// The scene key that holds a change's size in file units: "change_um"/"change_urad" (constant),
/// "rate_um_per_min"/"rate_urad_per_min" (linear in time), "final_um"/"final_urad" (steady state).
std::string size_key(ChangeLaw law, Quantity q);
/// File units of size_key per internal unit (µm per mm, µrad per rad; per minute for a rate per second: × 60).
double file_per_internal(ChangeLaw law, Quantity q);

/// "E_AOA (zero-position error of A) drifts by +0.80 µrad/min": a change in words, with its size in file units and an
/// optional uncertainty text already formatted; for a change per revolution, `phase_text` (its φ in degrees, with its
/// uncertainty) replaces the bare φ.
/// `chain` names the component (null: the CFXZAY).
std::string describe(const ComponentChange& change, const std::string& size_text, const std::string& phase_text = {},
                     const KinematicChain* chain = nullptr);

} // namespace geartopo::machine
