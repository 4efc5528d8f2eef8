// geartopo — the axis motions along each stroke that grind the drawing's helix modifications (crowning, slope, end
// relief; gears/flank_modifications.hpp) on an ideal machine: the nominal NC program's additions to the C–Z screw
// (docs/modifications.md). The profile modifications are dressed into the wheel (FormWheel) and need no motion.
//
//   radial infeed (LeadCrowning::RadialInfeed): the radial slide alone at every pose (X; on another chain its slide
//       along x, radial_slot), the least-squares X over both contact lines
//       of the space (the flank objective of compensator.hpp with X free). The contact line runs diagonally across a
//       helical flank, so each point of a transverse profile is ground at a different stroke position and with a
//       different infeed: the flank is twisted (profile slope changing over the face width, helix slope over the
//       profile).
//   twist free (LeadCrowning::TwistFree): X, Y, Z, A and C at every pose, the flank objective with all five axes: the
//       motions that bring both contact lines to the design as closely as rigid wheel motions can.
//
// Both are solved with the compensator's flank objective on the ideal process, whose target is the design's helix part
// at each contact point. The motions are in the axes of the StrokeCheck's chain (chain_axes.hpp: the setting's on the
// CFXZAY, the chain's own on any other) and checked against that chain's strokes. Units: mm, rad.
#pragma once

#include "geartopo/compensation/compensator.hpp"

namespace geartopo::compensation {

/// The pose slot of `chain`'s radial slide, the linear axis along x (the centre distance): X on the CFXZAY, the
/// CAFXZY and the CXFZAY, U on a chain whose radial slide is called U; X without a chain.
int radial_slot(const machine::KinematicChain* chain);

/// The design motions of `setup`'s helix modifications for every sample of the path (step_mm apart along each
/// stroke), in the axes of `strokes.chain`; corrections of 0 where the design has no helix part. `strokes` marks rows
/// outside the chain's strokes (the machine model's on the CFXZAY).
CorrectionTable design_motions(const grinding::GrindingSetup& setup, grinding::LeadCrowning mode,
                               const StrokeCheck& strokes, double step_mm = 2.0);

} // namespace geartopo::compensation
