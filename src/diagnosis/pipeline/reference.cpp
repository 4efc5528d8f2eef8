// geartopo diagnosis — stage 0 (stages.hpp): a measurement read as against the bare involute because nobody said what
// it is measured from, whose residual is minus the scene's design. Units: µm.
#include "stages.hpp"

#include <algorithm>
#include <cmath>

namespace geartopo::diagnosis::stages {

// A file without a design_um column is read as measured against the bare involute (docs/modifications.md). A measuring
// machine that evaluates against the drawing writes the same columns, and then the flank as read lacks its design: the
// residual is minus the design, plus what the machine really did. Said when the design shows above the noise
// (kDesignVisibleSigma) and referring the file to the drawing leaves at most kAgainstDrawingShare of the residual's RMS
// (three quarters of its sum of squares explained by the design alone, with no parameter fitted) — both with the
// set-up terms removed, which absorb the design's mean.
std::optional<Decision> reference_in_doubt(const std::vector<MeasuredPoint>& pts, const Eigen::VectorXd& residual,
                                           const SetupTermModel& setup_terms, double noise_um) {
  constexpr double kDesignVisibleSigma = 3.0, kAgainstDrawingShare = 0.5;
  if (std::all_of(pts.begin(), pts.end(), [](const MeasuredPoint& p) { return p.reference_declared; })) return {};
  Eigen::VectorXd design(static_cast<Eigen::Index>(pts.size())); // n: the scene's design at the points
  for (size_t i = 0; i < pts.size(); ++i) design(static_cast<Eigen::Index>(i)) = pts[i].design_um;
  const Eigen::VectorXd d = setup_terms.remove_shown(design), r = setup_terms.remove_shown(residual);
  const double n = static_cast<double>(pts.size());
  const auto rms = [&](const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / n); };
  const double design_rms = rms(d), as_read = rms(r), against_drawing = rms(r + d);
  if (design_rms < kDesignVisibleSigma * noise_um || against_drawing > kAgainstDrawingShare * as_read) return {};
  return Decision{Reason::reference_in_doubt,
                  "measurement",
                  {},
                  {{"residual_rms_um", as_read},
                   {"against_drawing_rms_um", against_drawing},
                   {"design_rms_um", design_rms},
                   {"noise_um", noise_um},
                   {"share_limit", kAgainstDrawingShare}}};
}

std::optional<Decision> reference_in_doubt(const Context& ctx) {
  return reference_in_doubt(ctx.points, ctx.before, ctx.setup_terms, ctx.noise_um);
}

} // namespace geartopo::diagnosis::stages

namespace geartopo::diagnosis {

std::optional<Decision> reference_in_doubt(const gears::GearGeometry& g, const std::vector<MeasuredPoint>& points,
                                           const std::vector<double>& residual_um, double noise_um) {
  if (points.empty() || residual_um.size() != points.size()) return {};
  const Eigen::Map<const Eigen::VectorXd> r(residual_um.data(), static_cast<Eigen::Index>(residual_um.size()));
  return stages::reference_in_doubt(points, r, SetupTermModel(g, points), noise_um);
}

} // namespace geartopo::diagnosis
