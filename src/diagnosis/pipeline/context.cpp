// geartopo diagnosis — the pipeline's context (stages.hpp): the measurement against the model, its noise, set-up terms
// and contact states, built once. Units: µm, s.
#include "stages.hpp"

#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/grinding/flank_deviation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string_view>

namespace geartopo::diagnosis::stages {
namespace {

/// Refuses options that would make the rules meaningless (the message names the option and its allowed range).
void check_options(const DiagnoseOptions& o) {
  const auto refuse = [](std::string_view name, double value, std::string_view rule) {
    throw std::invalid_argument(fmt::format("diagnose: option {} = {} (must be {})", name, value, rule));
  };
  if (!(std::isfinite(o.bic_threshold) && o.bic_threshold >= 0.0)) refuse("bic_threshold", o.bic_threshold, "finite and ≥ 0");
  if (o.min_points < 1) refuse("min_points", static_cast<double>(o.min_points), "≥ 1");
  if (!(o.unexplained_false_alarm > 0.0 && o.unexplained_false_alarm < 1.0))
    refuse("unexplained_false_alarm", o.unexplained_false_alarm, "in (0, 1)");
  if (o.pair_candidates < 1) refuse("pair_candidates", static_cast<double>(o.pair_candidates), "≥ 1");
  if (!(std::isfinite(o.covariance_ridge) && o.covariance_ridge >= 0.0))
    refuse("covariance_ridge", o.covariance_ridge, "finite and ≥ 0");
  if (o.plan_profile_traces < 1 || o.plan_helix_traces < 1)
    refuse("plan_profile_traces / plan_helix_traces", std::min(o.plan_profile_traces, o.plan_helix_traces), "≥ 1");
  if (o.plan_trace_points < 2) refuse("plan_trace_points", o.plan_trace_points, "≥ 2");
  if (o.plan_rows < 1 || o.plan_cols < 1) refuse("plan_rows / plan_cols", std::min(o.plan_rows, o.plan_cols), "≥ 1");
  if (o.profile_walk_steps < 0) refuse("profile_walk_steps", o.profile_walk_steps, "≥ 0");
  if (!(std::isfinite(o.profile_min_step) && o.profile_min_step > 0.0))
    refuse("profile_min_step", o.profile_min_step, "finite and > 0");
  for (int a = 0; a < 5; ++a)
    if (!(std::isfinite(o.stroke_repeatability_sd(a)) && o.stroke_repeatability_sd(a) >= 0.0))
      refuse("stroke_repeatability_sd", o.stroke_repeatability_sd(a), "finite and ≥ 0 on every axis");
  limits::require(limits::noise_um_refusal(o.noise_um), "diagnose: option noise_um");
  if (!o.model_uncertainty_um.allFinite())
    throw std::invalid_argument("diagnose: option model_uncertainty_um has a non-finite value");
  if (!(o.alike_share > 0.0 && o.alike_share <= 1.0)) refuse("alike_share", o.alike_share, "in (0, 1]");
  if (!(std::isfinite(o.plausible_wave_um) && o.plausible_wave_um > 0.0))
    refuse("plausible_wave_um", o.plausible_wave_um, "finite and > 0");
  if (!(std::isfinite(o.plausible_wheel_profile_um) && o.plausible_wheel_profile_um > 0.0))
    refuse("plausible_wheel_profile_um", o.plausible_wheel_profile_um, "finite and > 0");
  for (const auto& f : o.families)
    if (!f) throw std::invalid_argument("diagnose: option families holds a null family");
}

/// The set-up terms, with the stroke-to-stroke scatter the options declare (none: white noise, ordinary least squares).
SetupTermModel setup_term_model(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                                const std::vector<MeasuredPoint>& pts, double noise_um, const DiagnoseOptions& o) {
  if (o.stroke_repeatability_sd.isZero() && o.model_uncertainty_um.size() == 0) return SetupTermModel(setup.geometry(), pts);
  std::vector<int> space(pts.size());
  for (size_t i = 0; i < pts.size(); ++i)
    space[i] = grinding::space_of(pts[i].tooth, pts[i].flank, setup.geometry().teeth());
  const Eigen::MatrixXd G = stroke_sensitivity(setup, model, pts, o.stroke_repeatability_sd,
                                               {o.chain, o.datum_face_z_mm}, o.threads, o.keep_going); // n × 5
  return SetupTermModel(setup.geometry(), pts, StrokeScatter(space, G, noise_um, o.model_uncertainty_um));
}

/// The residual before any explanation: measured − model (exact simulation), after the checks every later step needs.
std::vector<double> checked_residual(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                                     const std::vector<MeasuredPoint>& pts, const DiagnoseOptions& o) {
  check_options(o);
  if (pts.size() < o.min_points)
    throw std::invalid_argument(fmt::format("diagnose: {} measured point(s); at least {} are needed", pts.size(), o.min_points));
  if (o.model_uncertainty_um.size() > 0 && o.model_uncertainty_um.rows() != static_cast<Eigen::Index>(pts.size()))
    throw std::invalid_argument(fmt::format("diagnose: option model_uncertainty_um has {} rows for {} measured points",
                                            o.model_uncertainty_um.rows(), pts.size()));
  if (o.keep_going) o.keep_going();
  const auto base = predict(setup, model, pts, grinding::Method::Exact, o.threads, o.keep_going);
  if (o.keep_going) o.keep_going();
  std::vector<double> r(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) r[i] = pts[i].deviation_um - base[i];
  return r;
}

/// On a large measurement the fits search from their starts on every k-th point (FitSubsample, effect_fit.hpp).
std::optional<FitSubsample> fit_subsample(const Context& c) {
  const std::size_t k = subsample_stride(c.points.size(), c.options.fit_search_points);
  if (k <= 1) return std::nullopt;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < c.points.size(); i += k) rows.push_back(i);
  std::vector<MeasuredPoint> sub_pts;
  std::vector<double> sub_r0;
  DiagnoseOptions sub_o = c.options; // the model's uncertainty, if given, at the subsample's points
  const auto& M = c.options.model_uncertainty_um;
  if (M.size() > 0) sub_o.model_uncertainty_um.resize(static_cast<Eigen::Index>(rows.size()), M.cols());
  for (std::size_t j = 0; j < rows.size(); ++j) {
    sub_pts.push_back(c.points[rows[j]]);
    sub_r0.push_back(c.residual_before_um[rows[j]]);
    if (M.size() > 0) sub_o.model_uncertainty_um.row(static_cast<Eigen::Index>(j)) = M.row(static_cast<Eigen::Index>(rows[j]));
  }
  return FitSubsample{c.at_points.rows(rows), setup_term_model(c.setup, c.model, sub_pts, c.noise_um, sub_o),
                      std::move(sub_r0)};
}

} // namespace

std::vector<FlankSurface> flank_surfaces(const std::vector<MeasuredPoint>& pts) {
  std::map<std::pair<int, int>, std::vector<size_t>> flanks;
  for (size_t i = 0; i < pts.size(); ++i) flanks[{pts[i].tooth, static_cast<int>(pts[i].flank)}].push_back(i);
  std::vector<FlankSurface> out;
  for (auto& [key, idx] : flanks) {
    if (idx.size() < 10) continue;
    double xlo = 1e300, xhi = -1e300, zlo = 1e300, zhi = -1e300;
    for (size_t i : idx) {
      xlo = std::min(xlo, pts[i].roll_length_mm), xhi = std::max(xhi, pts[i].roll_length_mm);
      zlo = std::min(zlo, pts[i].z_mm), zhi = std::max(zhi, pts[i].z_mm);
    }
    Eigen::MatrixXd X(static_cast<long>(idx.size()), 6);
    for (size_t k = 0; k < idx.size(); ++k) {
      const auto& p = pts[idx[k]];
      const double u = xhi > xlo ? 2 * (p.roll_length_mm - xlo) / (xhi - xlo) - 1 : 0.0;
      const double w = zhi > zlo ? 2 * (p.z_mm - zlo) / (zhi - zlo) - 1 : 0.0;
      X.row(static_cast<long>(k)) << 1.0, u, w, u * w, u * u, w * w;
    }
    out.push_back({std::move(idx), std::move(X)});
  }
  return out;
}

Context::Context(const grinding::GrindingSetup& setup_, const grinding::GrindingProcess& model_,
                 const std::vector<MeasuredPoint>& points_, const std::vector<std::string>& in_scene_,
                 const DiagnoseOptions& options_)
    : setup(setup_), model(model_), points(points_), in_scene(in_scene_), options(options_),
      n(static_cast<double>(points_.size())), residual_before_um(checked_residual(setup_, model_, points_, options_)),
      before(Eigen::Map<const Eigen::VectorXd>(residual_before_um.data(), static_cast<Eigen::Index>(points_.size()))),
      noise_um(options_.noise_um > 0.0 ? options_.noise_um : estimate_noise_um(points_, residual_before_um)),
      noise_estimated(options_.noise_um <= 0.0), rms_before_um(std::sqrt(before.squaredNorm() / n)),
      // Set-up terms (thickness offset, angular registration) are fitted in the baseline and in every candidate; with
      // declared stroke-to-stroke scatter by generalised least squares (the residual's covariance, stroke_scatter.hpp).
      setup_terms(setup_term_model(setup_, model_, points_, noise_um, options_)),
      // What every fit evaluates thousands of times: the effects' first-order deviation at these points, whose
      // parameter-independent part (pose, contact, axis Jacobian) is computed here once for all candidates.
      at_points(setup_, points_, options_.threads, options_.chain, options_.datum_face_z_mm, options_.keep_going), surfaces(flank_surfaces(points_)) {
  if (options.keep_going) options.keep_going(); // each step above takes a second on 10⁵ points
  rms_before_setup_um = std::sqrt(setup_terms.remove_shown(before).squaredNorm() / n);
  subsample = fit_subsample(*this);
  first_time_s = 1e300, last_time_s = -1e300;
  for (size_t i = 0; i < points.size(); ++i) {
    first_time_s = std::min(first_time_s, at_points.path_point(i).time_s);
    last_time_s = std::max(last_time_s, at_points.path_point(i).time_s);
  }
}

double Context::ln_n() const { return std::log(n); }

} // namespace geartopo::diagnosis::stages
