// geartopo — the design motions of the helix modifications (design_motion.hpp). Units: mm, rad.
#include "geartopo/compensation/design_motion.hpp"

namespace geartopo::compensation {

int radial_slot(const machine::KinematicChain* chain) {
  if (chain == nullptr) return static_cast<int>(machine::Axis::X);
  // Every body frame is parallel at home and the swivel turns about x, so a slide along x moves the wheel centre along
  // the centre distance whatever the other axes stand at (kinematic_chain.hpp).
  for (const machine::Joint& j : chain->joints())
    if (j.kind == machine::AxisKind::Linear && j.dir == 0) return static_cast<int>(j.slot);
  return static_cast<int>(machine::Axis::X); // not reached: a valid chain has a linear axis along each direction
}

CorrectionTable design_motions(const grinding::GrindingSetup& setup, grinding::LeadCrowning mode,
                               const StrokeCheck& strokes, double step_mm) {
  CompensationOptions o;
  o.method = Method::Flank;
  o.step_mm = step_mm;
  if (mode == grinding::LeadCrowning::RadialInfeed) {
    o.free_axes.setZero();
    o.free_axes(radial_slot(strokes.chain)) = 1.0;
  }
  const grinding::IdealProcess ideal; // the NC program's nominal motions: the machine's errors are not known to it
  return compute_corrections(setup, ideal, strokes, o);
}

} // namespace geartopo::compensation
