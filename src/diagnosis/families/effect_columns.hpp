// geartopo diagnosis, private — what the wheel families share (wheel_flank_profile, wheel_flank_waviness,
// wheel_profile_wear): a library effect some of whose parameters are linear (ParameterSpec::linear), zero at its
// default, fitted as a hypothesis' coefficients. Units: µm per unit of each parameter.
#pragma once

#include "geartopo/diagnosis/hypothesis_family.hpp"

#include <vector>

namespace geartopo::diagnosis::families {

/// The effect's columns (n × k, µm per unit of each fitted parameter): its deviation with fitted parameter j set to 1
/// and the other fitted ones 0, the rest at `spec`'s values.
Eigen::MatrixXd effect_columns(const scene::EffectSpec& spec, const std::vector<int>& fitted, const ContactStates& states);

/// "left" or "right".
std::string side_word(Flank side);

/// The rejection of a fitted parameter outside its plausible range by more than 2σ (the effect's ParameterSpec), or none.
std::optional<Decision> implausible(const std::string& effect, int parameter, double value, double sd);

} // namespace geartopo::diagnosis::families
