#include "geartopo/compensation/design_motion.hpp"

namespace geartopo::compensation {

CorrectionTable design_motions(const grinding::GrindingSetup& setup, grinding::LeadCrowning mode,
                               const StrokeCheck& strokes, double step_mm) {
  CompensationOptions o;
  o.method = Method::Flank;
  o.step_mm = step_mm;
  if (mode == grinding::LeadCrowning::RadialInfeed) o.free_axes << 1.0, 0.0, 0.0, 0.0, 0.0;
  const grinding::IdealProcess ideal; // the NC program's nominal motions: the machine's errors are not known to it
  return compute_corrections(setup, ideal, strokes, o);
}

} // namespace geartopo::compensation
