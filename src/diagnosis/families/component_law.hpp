// geartopo diagnosis, private — what the component families share (component_constant, component_linear,
// component_steady_state, component_periodic): one of the chain's error components changed under a law in time or in
// the table's turn. Each hypothesis is one component and its law; its columns are the component's first-order
// sensitivity at the points' generating poses (wᵀ J_twistw_e) times the law's shape (1, t, 1 − e^(−t/τ), or cos kγ and
// sin kγ). Units: the component's (mm or rad) per unit of coefficient, rates per second.
#pragma once

#include "geartopo/diagnosis/hypothesis_family.hpp"
#include "geartopo/machine/component_change.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <string>
#include <vector>

namespace geartopo::diagnosis::families {

/// The components whose sensitivity at these points is not identically zero, in the chain's order.
std::vector<int> visible_components(const ContactStates& states);

/// A hypothesis: component k changed under `law` (τ for a steady state, k for a periodic one).
Candidate component_hypothesis(const machine::KinematicChain* chain, int component, machine::ChangeLaw law, double time_constant_s = 0.0, int order = 1);

/// The largest plausible change over one job (mm or rad): DiagnoseOptions::plausible_change_um or _urad.
double plausible_change(const machine::ComponentChange& change, const DiagnoseOptions& options);

/// The finding of a one-coefficient law (constant, linear in time, steady state): its size (file units) with σ, τ as
/// a grid parameter for a steady state, the sentence, and the rejection when its reach over the job exceeds the
/// plausible change by more than 2σ.
Candidate one_coefficient_finding(Candidate h, const LinearFit& fit, const ContactStates& states,
                                  const DiagnoseOptions& options);

/// "µm" or "µrad": the file unit of a component's quantity.
std::string unit_of(machine::Quantity q);

} // namespace geartopo::diagnosis::families
