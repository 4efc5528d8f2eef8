// geartopo — an error component that changed since the map was measured, and the law it follows in time
// (docs/error-components.md, "Changes since the map"; scene key `machine_changes`, docs/scene-format.md).
//
// A change adds δe_k(t) to component k at every axis position: constant (δe_k = c), linear in time (δe_k = ρ·t, t the
// time since the first stroke began, as grinding::PathPoint::time_s) or an approach to a steady state
// (δe_k = c_∞·(1 − e^(−t/τ)), the first-order thermal law); a C-axis component may instead have changed once per table
// revolution (δe_k = a·cos(γ − φ), γ the commanded C angle: a new indexing or run-out error). Its effect on the wheel pose is first order:
// ξ_w = J_twistw_e(q)·δe (machine/first_order.hpp), exact to O(δe·e, δe²) — below 0.02 µm for 400 µrad on a 200 mm
// lever. Units inside: mm and rad (rates per second); in files µm or µrad, rates per minute.
#pragma once

#include "geartopo/machine/error_component.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace geartopo::machine {

enum class ChangeLaw { Constant, LinearInTime, SteadyState, OncePerRevolution };

/// "constant", "linear_in_time", "steady_state", "once_per_revolution"
std::string_view to_string(ChangeLaw law);
std::optional<ChangeLaw> change_law_from_name(std::string_view name);

struct ComponentChange {
  ComponentId component = ComponentId::delta_xx;
  ChangeLaw law = ChangeLaw::Constant;
  /// Constant: the change c; linear in time: the rate ρ per second; steady state: the final change c_∞; once per
  /// revolution: the amplitude a. mm or rad (per second for the rate).
  double size = 0.0;
  double time_constant_s = 0.0; ///< τ (s), steady state only
  double phase_rad = 0.0;       ///< φ, once per revolution only: the C angle of the largest change
  /// δe_k at time t (s since the first stroke began) and commanded C angle γ (rad), mm or rad.
  double at(double time_s, double c_rad) const { return size * law_shape(time_s, c_rad); }
  /// The law per unit size: 1, t (s), 1 − e^(−t/τ) or cos(γ − φ).
  double law_shape(double time_s, double c_rad) const;
};

/// The scene key that holds a change's size in file units: "change_um"/"change_urad" (constant),
/// "rate_um_per_min"/"rate_urad_per_min" (linear in time), "final_um"/"final_urad" (steady state).
std::string size_key(ChangeLaw law, Quantity q);
/// File units of size_key per internal unit (µm per mm, µrad per rad; per minute for a rate per second: × 60).
double file_per_internal(ChangeLaw law, Quantity q);

/// "E_AOA (zero-position error of A) drifts by +0.80 µrad/min": a change in words, with its size in file units and an
/// optional uncertainty text already formatted; for a change once per revolution, `phase_text` (its φ in degrees, with
/// its uncertainty) replaces the bare φ.
std::string describe(const ComponentChange& change, const std::string& size_text, const std::string& phase_text = {});

} // namespace geartopo::machine
