// geartopo — a grinding process with physical effects on top of another process (usually the machine's geometric
// error model). Commands get the effects' offsets before the machine sees them; the gear frame gets the effects'
// mounting errors; the wheel gets their radius changes. Units: mm, rad.
#pragma once

#include "geartopo/effects/effect.hpp"
#include "geartopo/grinding/grinding_process.hpp"

#include <memory>
#include <vector>

namespace geartopo::effects {

class EffectsProcess final : public grinding::GrindingProcess {
public:
  /// `effects` must be bound to the same set-up and outlive the process.
  EffectsProcess(const grinding::GrindingProcess& inner, std::vector<const Effect*> effects)
      : inner_(inner), effects_(std::move(effects)) {}
  /// The same over effects someone owns (a scene's, a diagnosis candidate's); they must outlive the process.
  EffectsProcess(const grinding::GrindingProcess& inner, const std::vector<std::unique_ptr<Effect>>& effects)
      : inner_(inner) {
    for (const auto& e : effects) effects_.push_back(e.get());
  }

  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override;
  /// The first-order pose error in w: the inner process's, plus J_twistw_q · (command offsets), plus the table's
  /// mounting twists — the linear counterpart of actual_wMg (equal to it to second order in the effects).
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override;
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override;

private:
  grinding::PathPoint commanded(const grinding::PathPoint& pp) const;

  const grinding::GrindingProcess& inner_;
  std::vector<const Effect*> effects_;
};

} // namespace geartopo::effects
