// geartopo — the library of effects: ONE LINE PER EFFECT. Adding an effect is one class (a .cpp in src/effects/ that
// defines `std::unique_ptr<Effect> make_<name>()`) and one line here (docs/adding-an-effect.md).
#pragma once

#define GEARTOPO_EFFECT_LIST(X) \
  X(thermal_drift)              \
  X(wheel_wear)                 \
  X(eccentricity)               \
  X(deflection)                 \
  X(wheel_profile)              \
  X(servo_lag)                  \
  X(wheel_runout)               \
  X(wheel_flank_profile)        \
  X(wheel_profile_wear)          \
  X(wheel_flank_waviness)
