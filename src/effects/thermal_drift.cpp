// Thermal drift of the X and Z axes with grinding time: the machine warms up after the start and its axes grow
// towards a steady state with a first-order time constant, δ(t) = δ_∞ (1 − e^(−t/τ)). Positive X growth leaves the
// wheel further out than commanded (more material); positive Z growth shifts it along the Z slide. The growth is a
// ball screw's, so it belongs to the named slide (EffectsProcess, effects::chain_offsets): on another chain its slide
// along x (the centre distance: the wheel head's X on the CAFXZY, the radial table's on the CXFZAY) and its slide
// along z (the wheel head's Z; on the CAFXZY along the bed's z, which the tilted gear sees as cos α along its axis and
// sin α across it; on the CFXZAY and the CXFZAY along the gear axis) — docs/machine-model.md §9.
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

#include <cmath>

namespace geartopo::effects {
namespace {

class ThermalDrift final : public Effect {
public:
  ThermalDrift() { init_defaults(); }
  std::string_view type() const override { return "thermal_drift"; }
  std::string_view explanation() const override {
    return "the machine warms up while grinding: X and Z grow towards a steady state, so teeth ground later come out "
           "thicker or thinner";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"x_growth_um", "steady-state growth of X (wheel further out: +)", 0.0, -500.0, 500.0, 5.0, true, {}, -100.0, 100.0, /*whole*/ false, /*linear*/ true},
        {"z_growth_um", "steady-state growth of Z (the slide along z: the gear axis on the CFXZAY)", 0.0, -500.0, 500.0, 5.0, true, {}, -100.0, 100.0, /*whole*/ false, /*linear*/ true},
        {"time_constant_s", "thermal time constant", 1800.0, 10.0, 1e6, 1000.0, true, {300.0, 1000.0, 3000.0, 10000.0}, 60.0, 20000.0}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<ThermalDrift>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table
  machine::Vector5d command_offset(const grinding::PathPoint& pp) const override {
    const double f = 1.0 - std::exp(-pp.time_s / value(2));
    machine::Vector5d o = machine::Vector5d::Zero();
    o(0) = units::mm_from_um(value(0)) * f;
    o(2) = units::mm_from_um(value(1)) * f;
    return o;
  }
};

} // namespace

std::unique_ptr<Effect> make_thermal_drift() { return std::make_unique<ThermalDrift>(); }

} // namespace geartopo::effects
