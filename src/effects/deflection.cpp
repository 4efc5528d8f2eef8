// Workpiece/arbor deflection under the grinding force: the gear sits in the middle of an arbor supported at both
// ends; the radial grinding force bends it away from the wheel by δ(s) = δ_mid · 16 s² (L − s)² / L⁴ (point load at
// s on a simply supported beam of span L, scaled to δ_mid at mid span). The wheel's contact travels along the face
// width, so both flanks get more material in the middle: a helix crowning, the same on every tooth.
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

#include <algorithm>

namespace geartopo::effects {
namespace {

class Deflection final : public Effect {
public:
  Deflection() { init_defaults(); }
  std::string_view type() const override { return "deflection"; }
  std::string_view explanation() const override {
    return "the grinding force bends the workpiece arbor away from the wheel, most at mid face: the flanks come out "
           "crowned along the helix";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"deflection_um", "radial deflection when the wheel grinds at mid face (away from the wheel: +)", 0.0, -500.0,
         500.0, 5.0, true, {}, -100.0, 100.0, /*whole*/ false, /*linear*/ true},
        {"arbor_span_mm", "distance between the arbor's supports (gear in the middle)", 600.0, 10.0, 10000.0, 100.0, false}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<Deflection>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table
  machine::Vector5d command_offset(const grinding::PathPoint& pp) const override {
    const double b = setup().geometry().spec().face_width_mm;
    const double L = std::max(value(1), b);
    const double s = 0.5 * (L - b) + std::clamp(pp.z_stroke_mm, 0.0, b);
    const double shape = 16.0 * s * s * (L - s) * (L - s) / (L * L * L * L);
    machine::Vector5d o = machine::Vector5d::Zero();
    o(0) = units::mm_from_um(value(0)) * shape; // the workpiece gives way: as if the wheel stood further out
    return o;
  }
};

} // namespace

std::unique_ptr<Effect> make_deflection() { return std::make_unique<Deflection>(); }

} // namespace geartopo::effects
