// geartopo — which physical effect is missing from a model, judged on measurements (docs/diagnosis.md).
//
// For every candidate effect of the library that the scene does not model, its parameters are fitted to the residual
// (measured − model) by Levenberg–Marquardt on the simulator: the effect's contribution at the measured points is its
// first-order deviation (superposed on the model's exact deviation — both are small). Each fit reports values with
// standard uncertainties, the fraction of the residual's sum of squares it explains, the RMS before and after, and
// ΔBIC = n ln(RSS/RSS₀) + p ln n against the model without it, so that a many-parameter effect does not win by
// over-fitting. Every fit, the baseline included, also fits the measurement's set-up terms (thickness offset, angular
// registration: SetupTerms), which are reported on their own and never credited to an effect. Candidates are ranked
// by ΔBIC; an effect is significant when ΔBIC < −threshold. When two or more are significant, pairs are fitted
// jointly and one is taken when it beats the best single effect by the threshold again. What is left is judged
// against the noise by two χ² tests (all of it; its smooth part per flank). Explanations within the threshold of the
// chosen one are rivals: the verdict says "ambiguous" and a measurement plan names the unmeasured teeth (and grid) whose
// measurement is expected to separate them after both are refitted. Units: µm, and each parameter's own unit (its
// key).
#pragma once

#include "geartopo/core/limits.hpp"
#include "geartopo/diagnosis/decision.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/machine/axis_pose.hpp"
#include "geartopo/machine/component_change.hpp"
#include "geartopo/scene/scene.hpp"

#include <Eigen/Dense>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace geartopo::diagnosis {

using measurement::MeasuredPoint; ///< what diagnosis works on: measured points, read by the measurement library

class HypothesisFamily; // hypothesis_family.hpp: a kind of explanation beyond the library
using HypothesisFamilies = std::vector<std::shared_ptr<const HypothesisFamily>>;
/// The families diagnose tries beyond the library, in their registration order (families/family_list.hpp).
HypothesisFamilies default_hypothesis_families();

struct FittedParameter {
  std::string key;           ///< with its unit, e.g. "x_growth_um"
  double value = 0.0;
  double uncertainty = 0.0;  ///< standard uncertainty (1σ); 0 for parameters held fixed
  bool fitted = true;
  /// False when the data do not fix the value: it sits at the end of its allowed range, or its σ is wider than its
  /// whole plausible range (a thermal amplitude trading against its time constant on two teeth). Such a value is no
  /// finding: it is printed as "not determined", never as a number with an uncertainty.
  bool determined = true;
};

/// Set-up terms of a measurement (not process physics; docs/diagnosis.md): a thickness offset on every flank and the
/// gear's angular registration, fitted alongside every explanation and reported on their own.
struct SetupTerms {
  double thickness_um = 0.0, thickness_sd_um = 0.0;  ///< uniform normal offset, plus material positive, and its 1σ
  double rotation_urad = 0.0, rotation_sd_urad = 0.0; ///< rigid turn of the gear (+: right flanks gain material)
  bool rotation_identified = true;                    ///< false with one flank side: the offset then holds both
};

struct Candidate {
  std::vector<scene::EffectSpec> effects;               ///< one (or two, for a combination) with fitted values
  /// Beyond the library (docs/diagnosis.md, "Beyond the library"): a changed error component of the chain with its law
  /// and fitted size (internal units), and the size's 1σ, parallel. Empty for a library effect.
  std::vector<machine::ComponentChange> changes;
  std::vector<double> change_sd;
  /// The chain whose components `changes` are, which names them (null: the CFXZAY).
  const machine::KinematicChain* chain = nullptr;
  /// The family beyond the library that made this hypothesis (hypothesis_family.hpp); null for the library's effects
  /// and their pairs. Its field at any points is family->columns(…) · coefficients.
  std::shared_ptr<const HypothesisFamily> family;
  Eigen::VectorXd coefficients; ///< a hypothesis' fitted coefficients β (p, the family's columns' units)
  /// A hypothesis that is neither effects nor component changes (a caller's own family): its name, e.g.
  /// "x_step_per_stroke". Empty otherwise: the name is made from the effects and changes.
  std::string label;
  /// One sentence for people: "E_AOA (zero-position error of A) drifts by +0.80 ± 0.02 µrad/min (+38 µrad over the
  /// job)"; empty for a library effect.
  std::string description;
  /// Other hypotheses beyond the library that these flanks cannot tell from this one (within the ΔBIC threshold and
  /// their fitted fields alike by DiagnoseOptions::alike_share; or, for a change per revolution, the orders the
  /// measured teeth alias with this one's): named as one equivalence class, never as a choice between them.
  std::vector<std::string> equivalent;
  /// Library explanations (an effect or a pair, by name) that can leave this hypothesis' field on these flanks: at
  /// least alike_share of it lies in the span of their parameters' columns at their fitted values (an X drifting
  /// linearly in time is a thermal X growth in its early phase), whatever their ΔBIC — theirs pays for parameters the
  /// flanks do not fix.
  std::vector<std::string> library_equivalent;
  /// A user's own effect (a scene's custom_effects) alone: how alike its fitted field is, on these flanks with the
  /// set-up terms removed, to each library effect's and each listed machine element's — |ρ|, the share of its field the
  /// other can make (share_of_field_in_span: by the library effect's parameter columns at its fitted values, by the
  /// element's fitted field); 1 is the same field. Highest first. Empty for the library's and the families' candidates.
  std::vector<std::pair<std::string, double>> look_alikes;
  /// Which wheel flank a one-sided hypothesis is about (wheel_flank_profile, wheel_flank_waviness): the gear flanks
  /// it grinds. Printed after the name: "wheel_flank_profile (left)".
  std::optional<Flank> wheel_flank;
  std::vector<std::vector<FittedParameter>> parameters; ///< per effect (a component change: its size, phase or τ)
  std::vector<std::string> explanations;                ///< one line of physics per effect
  double rms_before_um = 0.0, rms_after_um = 0.0; ///< with the set-up terms removed (µm)
  double explained_fraction = 0.0; ///< 1 − RSS/RSS₀, both with the set-up terms fitted
  double delta_bic = 0.0;
  /// Why this fit is no explanation, none when it can be one: a fitted parameter outside its plausible range
  /// (effects::ParameterSpec) by more than 2σ, a machine element changing beyond what one plausibly does, what it
  /// leaves more than noise. A rejected candidate is never significant, whatever its ΔBIC. to_text() says it.
  std::optional<Decision> rejection;
  bool significant = false;
  /// Correlation of the fitted parameters (p × p, unit-free; p the fitted parameters, effect by effect in parameter
  /// order) from the linearised covariance (JᵀJ)⁻¹; the uncertainties themselves may be wider (profile likelihood).
  Eigen::MatrixXd correlation;
  /// The fitted parameters' σ from the same linearised covariance (p, file units), before the profile-likelihood
  /// widening: with `correlation` the covariance a derived quantity's σ is taken from (delta method), consistently.
  Eigen::VectorXd linearised_sd;
  std::string name() const;        ///< "thermal_drift", "thermal_drift + wheel_wear" or "E_AOA linear_in_time"
  int fitted_parameters() const;   ///< number of fitted parameters over its effects (count)
  bool is_rejected() const { return rejection.has_value(); }
  /// Every effect of this one is in `bigger`, which has more (eccentricity in eccentricity + wheel_wear).
  bool nested_in(const Candidate& bigger) const;
};

/// One unmeasured tooth as a place to measure next: how far apart two competing explanations predict it
/// (docs/diagnosis.md, "Ambiguity and what to measure next").
struct ToothSuggestion {
  int tooth = 0;
  /// Expected separation in noise units: √(Σ Δ²)/σ over the tooth's grid (both flanks, rows × cols), Δ the difference
  /// of the two explanations' predictions (effects and their set-up terms). Its square is the χ² by which measuring the
  /// tooth would tell them apart, before both are refitted.
  double separation_sigma = 0.0;
  double max_difference_um = 0.0; ///< largest |Δ| on the tooth (µm)
  Flank flank = Flank::Left;      ///< where that largest |Δ| is: flank, grid row (1 root … rows tip), column (1 … cols
  int row = 0, col = 0;           ///< along the face width)
};

/// One way to measure more: which teeth, on which grid, and how far apart the two explanations are expected to be after
/// both are refitted on the measured and the new points (docs/diagnosis.md, "Ambiguity and what to measure next").
struct MeasurementOption {
  std::vector<int> teeth;   ///< new teeth, both flanks each
  int rows = 0, cols = 0;   ///< grid per flank (ISO evaluation ranges): rows along the profile, columns along the face
  int points = 0;           ///< new points (count): teeth × 2 flanks × rows × cols (traces: × lines × points per line)
  /// Traces instead of a grid (DiagnoseOptions::PlanLayout::Traces): per flank, a profile trace at each face-width
  /// position and a helix trace at each diameter, points_per_trace points each (rows, cols then 0).
  bool traces = false;
  std::vector<double> profile_z_mm, helix_diameter_mm;
  int points_per_trace = 0;
  /// √(Σ Δ²)/σ over the new points, Δ the difference of the two explanations' predictions as fitted now: the
  /// separation before the refit (noise units), for comparison — the refit absorbs part of it.
  double separation_before_refit_sigma = 0.0;
  /// Expected ΔBIC by which the right explanation wins after measuring (unit-free): the new points synthesised from one
  /// explanation without noise, the other refitted on measured + new, both charged the noise σ² per new point. "If
  /// first": the first (best now) is the truth, the second is refitted; "if second": the other way round.
  double delta_bic_if_first = 0.0, delta_bic_if_second = 0.0;
  /// Both expected gaps reach DiagnoseOptions::plan_target_delta_bic; a direction whose truth is nested in the other
  /// explanation (eccentricity in eccentricity + wear) counts as reached: the larger one can only fall behind by its
  /// extra parameters' penalty, and a nested rival that is not the better fit is no rival.
  bool resolves = false;
};

/// What an option measures on each new tooth, in words: "a 7 × 9 grid per flank" or "3 profile traces (z = 20, 75,
/// 130 mm) and 3 helix traces (d = 498.1, 507.3, 516.8 mm) of 100 points per flank".
std::string what_to_measure(const MeasurementOption& option);

/// What to measure to tell two explanations apart, whose ΔBIC are within the threshold of each other.
struct MeasurementPlan {
  std::string first, second;         ///< Candidate::name() of the best and its rival ("none": no effect)
  double delta_bic_gap = 0.0;        ///< ΔBIC(second) − ΔBIC(first), ≥ 0 and < the threshold (unit-free)
  double noise_um = 0.0;             ///< σ the separations are counted in (µm)
  int rows = 0, cols = 0;            ///< the grid `teeth` and the row/column separations are computed on (count)
  std::vector<ToothSuggestion> teeth; ///< every unmeasured tooth, largest separation first
  /// Separation (noise units) by grid row (profile position) and column (face-width position), over all unmeasured
  /// teeth and both flanks: which profile row / helix column of a scan carries the difference.
  std::vector<double> row_separation_sigma, col_separation_sigma;
  /// The options scored after refit, fewest new points first: the best 2, 4, 8, 16 teeth of `teeth` on the plan grid
  /// and on grids 2× and 3× denser each way, until one resolves (later ones are not scored).
  std::vector<MeasurementOption> options;
  /// The recommendation: the first option that resolves, else the one with the largest smaller expected gap (its
  /// `resolves` false: more than these options would be needed). `teeth` empty when every tooth is measured.
  MeasurementOption recommended;
};

/// What diagnose does and when; the defaults are the documented behaviour (docs/diagnosis.md).
struct DiagnoseOptions {
  double noise_um = 0.0;            ///< probe noise σ (µm) in [kMinNoiseUm, kMaxNoiseUm]; 0: estimated (estimate_noise_um)
  /// Stroke-to-stroke scatter of the axis commands, one standard deviation per axis of `chain` in its pose order
  /// (linear mm, rotary rad; the CFXZAY's X, Y, Z, A, C): the scene's `machine.repeatability` (ISO 230-2 R/4).
  /// Non-zero: the residual's covariance is σ² I plus each stroke's scatter (stroke_scatter.hpp) and every fit is
  /// generalised least squares. Zero (default): white noise only.
  machine::Vector5d stroke_repeatability_sd = machine::Vector5d::Zero();
  /// The model's own uncertainty at the measured points (n × m, µm): column k the first-order deviation when uncertain
  /// model quantity k is off by its standard uncertainty (map_sensitivity: the error map's 43 components within
  /// `machine.uncertainty`). Non-empty: Σ gains M Mᵀ, common to all points (stroke_scatter.hpp). Empty (default): none.
  Eigen::MatrixXd model_uncertainty_um;
  /// ΔBIC an effect must beat (unit-free, on the natural-log BIC scale): significant when ΔBIC < −threshold, and a pair
  /// must improve on the best single effect by as much again. 10 is "very strong" evidence (Kass & Raftery), so that
  /// a library effect is not named on data that only mildly prefer it.
  double bic_threshold = 10.0;
  std::vector<std::string> candidates; ///< effect types to try; empty: every library effect not in the scene
  /// The user's own effects (a scene's custom_effects, effects/custom_effect.hpp, by name): tried beside the library's
  /// whenever `candidates` is empty (the names must be registered laws).
  std::vector<std::string> own_effects;
  /// Solve the parameters a user's law is proportional to (found numerically at the points, proportional_parameters.hpp)
  /// by variable projection inside the fit; false: every parameter in the nonlinear fit (the comparison's baseline).
  bool project_linear = true;
  int threads = 0;                  ///< threads of the predictions; 0: all hardware threads
  /// The scene's kinematic chain (null: the CFXZAY) and where the gear's datum face sits along its z (mm): the
  /// machine-element hypotheses follow its error components (EffectContribution::component_sensitivity_um), and the
  /// stroke scatter offsets its axes (stroke_sensitivity).
  const machine::KinematicChain* chain = nullptr;
  double datum_face_z_mm = 0.0;
  /// Called after each candidate explanation is fitted (single effects, then pairs) with (candidates fitted, candidates
  /// known so far): the total grows by the pairs once the single effects are ranked. From the calling thread; for
  /// progress display only, the diagnosis does not depend on it.
  std::function<void(long long done, long long total)> on_candidate_fitted;
  /// Called between the stages, within each set-up loop over the points (every 4096 points of a prediction, every 1024
  /// contact states), before each machine-element hypothesis' fit and at every residual evaluation of a fit (a fit on
  /// 10⁵ points takes seconds between reports): a Ctrl-C check that may throw to stop the diagnosis, as
  /// grinding::SimulationOptions::keep_going. May be empty; called from the work's threads (it must be thread-safe);
  /// the result does not depend on it.
  std::function<void()> keep_going;
  /// Fewest measured points (count) diagnose accepts: the noise estimate fits 6 terms per flank, and BIC with a
  /// handful of points rewards nothing.
  std::size_t min_points = 10;
  /// What is left after the chosen explanation counts as more than noise when Σ r²/σ² exceeds the χ² quantile of its
  /// degrees of freedom at this upper-tail probability (unit-free): the verdict then says part of the residual
  /// remains unexplained. 0.001: one false "unexplained" in a thousand pure-noise measurements.
  double unexplained_false_alarm = 1e-3;
  /// Single effects taken into pairs (count): whenever one is significant, every pair among the best ones the evidence
  /// favours (ΔBIC below −threshold, also those rejected alone as implausible), up to this many. 4 (six pairs): each
  /// joint fit costs as much as several single fits, and an effect ranked below fourth has not explained enough alone
  /// to be a needed partner. Every pair, not only the best with the others: a stand-in ranked first (thermal drift
  /// mimicking wear) would otherwise keep the true pair (wear + eccentricity) from ever being fitted.
  std::size_t pair_candidates = 4;
  /// Ridge added to the diagonal of JᵀJ before inverting it for the covariance, relative to max(1, trace) (unit-free,
  /// parameters scaled by their typical size). 1e-12: negligible for identifiable parameters, but a direction the data
  /// cannot see gets a huge variance instead of a singular matrix or a false zero.
  double covariance_ridge = 1e-12;
  /// Profile-likelihood walk of a nonlinear parameter: the largest number of steps on each side (count), the step
  /// doubling from the linearised σ. 8 steps reach 2⁷ = 128 σ, beyond which the bound is a box limit anyway.
  int profile_walk_steps = 8;
  /// Grid of the measurement plan on every unmeasured tooth and flank (count): rows along the profile, columns along
  /// the face width — the simulator's default topological grid (docs/grinding.md).
  int plan_rows = 7, plan_cols = 9;
  /// What the plan recommends measuring on the new teeth: grids (plan_rows × plan_cols and 2×, 3× denser), or traces
  /// as a gear measuring machine takes them — per flank, plan_profile_traces profile traces at evenly spaced face-width
  /// positions and plan_helix_traces helix traces at evenly spaced roll lengths of the evaluation ranges (ends
  /// included), plan_trace_points points each (and 2×, 3× the lines).
  enum class PlanLayout { Grid, Traces };
  PlanLayout plan_layout = PlanLayout::Grid;
  int plan_profile_traces = 3, plan_helix_traces = 3, plan_trace_points = 100;
  /// Expected ΔBIC gap (unit-free) a measurement option must reach, whichever of the two explanations is right, to be
  /// recommended. Once the expected gap is λ, the realised one scatters by about 2√λ (a non-central χ² difference):
  /// at 30 it falls below bic_threshold = 10 in about 3 % of measurements, so a followed plan decides. The gap is
  /// counted after both explanations are refitted on all points (a raw difference over-promises: the refit absorbs
  /// part of it — at 1.5 µm noise the teeth reaching 8σ raw left thermal drift vs wear undecided).
  double plan_target_delta_bic = 30.0;
  /// Teeth described one by one in the verdict (count): the best few; the plan lists them all.
  std::size_t plan_teeth_named = 3;
  /// Beyond the library: the largest change a real machine's component makes over one job (engineering judgement,
  /// docs/diagnosis.md): 100 µm for a length (a grinder's X growth from cold reaches tens of µm), 1000 µrad for an
  /// angle (3.4′: a swivel head slipping in its clamping), the largest value the law reaches over the job. A fit that
  /// needs more by over 2σ is no explanation.
  double plausible_change_um = 100.0, plausible_change_urad = 1000.0;
  /// Beyond the library: the largest slope, crowning or wear of one wheel flank's profile a hypothesis is tried with
  /// (µm; per stroke for the wear): only to tell a hypothesis the measured flanks cannot see (its largest plausible
  /// size moves them by < 1e-4 µm RMS) from one they can.
  double plausible_wheel_profile_um = 100.0;
  /// Beyond the library: the largest waviness amplitude a dressed wheel flank plausibly carries (µm); a fit that needs
  /// more by over 2σ is no explanation.
  double plausible_wave_um = 20.0;
  /// Two fields are "alike" — one equivalence class, a library explanation that can leave an element's field, an
  /// element kept out as the library explanation's own field — when this share (0 … 1, unit-free) of each lies in the
  /// span of the other's columns (set-up terms removed): 0.95, cos 18°, what the flanks measured cannot tell apart at a
  /// noise of a third of the field.
  double alike_share = 0.95;
  /// The hypothesis families tried beyond the library (hypothesis_family.hpp): the default list, to which a caller may
  /// add its own (one line: `options.families.push_back(std::make_shared<MyFamily>())`).
  HypothesisFamilies families = default_hypothesis_families();
  /// Hypotheses beyond the library shown in the ranked list (count).
  std::size_t hypotheses_listed = 10;
  /// Large measurements (count): a candidate's multi-start search runs on every k-th measured point, k the smallest
  /// stride leaving at most this many, and only its best start is then refined on all points, from which every value,
  /// RSS, ΔBIC and uncertainty comes (docs/diagnosis.md, "Large measurements"). 25 000: a full trace export of all teeth
  /// (210 000 points) is searched on every 9th point, ≈ 60 per 500-point trace; a grid of two teeth is not subsampled.
  /// 0: every start on all points.
  std::size_t fit_search_points = 25000;
  /// Smallest first step of that walk (unit-free, in units of the parameter's typical size): a parameter whose
  /// linearised σ is 0 still moves.
  double profile_min_step = 1e-6;
};

/// What the data fix of a thermal drift whose single values are not determined (FittedParameter::determined): its
/// growth along one axis between the first and the last measured point's grinding time, with 1σ by the delta method
/// from the linearised covariance (Candidate::linearised_sd and correlation: the trade between amplitude and time
/// constant, which leaves the growth nearly unchanged, cancels). "X grew by +5.5 ± 0.3 µm between 0.0 and 9.4 min".
struct DeterminedGrowth {
  std::string axis;           ///< "X" or "Z"
  double value_um = 0.0, sd_um = 0.0;
  double from_s = 0.0, to_s = 0.0;
};

/// A set-up value a named explanation needs and nobody gave (ParameterSpec::fitted false: an arbor span, a dressing
/// interval, a runout frequency): the effect's default was assumed.
struct AssumedValue {
  std::string effect, key; ///< "deflection", "arbor_span_mm"
  double value = 0.0;      ///< the default (the key's unit)
};

/// The pattern of what is left unexplained (set-up terms removed): the two largest named patterns
/// (docs/residual-patterns.md) over the measured flanks — their mean and range — and the RMS per tooth.
struct ResidualPattern {
  struct Spread {
    std::string pattern;                 ///< "profile slope", …
    double mean_um = 0.0, lo_um = 0.0, hi_um = 0.0;
  };
  std::vector<Spread> largest;           ///< the two that reach farthest, largest first (none: too few positions)
  int flanks = 0;                        ///< flanks the patterns were fitted on (count)
  std::vector<std::pair<int, double>> tooth_rms_um; ///< (tooth, RMS in µm), by tooth
};

/// What the data determine of the chosen library explanation when its single values are not all determined
/// (FittedParameter::determined; docs/diagnosis.md, "What the data determine, into the scene"): equally likely value
/// sets drawn from the fit's posterior. Every parameter the deviation depends on nonlinearly (a time constant) on a
/// grid over its allowed range — log-spaced when the range is positive, with a log-uniform prior — weighted by
/// exp(−ΔRSS/2σ̂²); the linear parameters (ParameterSpec::linear) from their Gaussian given it, within their allowed
/// ranges. So a draw is a whole explanation that fits the measurement, and what the data fix (a thermal drift's growth
/// over the measured window) is fixed in every draw, while what they leave open (its time constant) spans its range.
struct PosteriorDraws {
  /// Per effect of the chosen explanation (its order): draws × values, every value of the effect in parameter order
  /// (file units); the same row of every effect is one draw.
  std::vector<Eigen::MatrixXd> values;
  int grid_points = 0; ///< grid points per nonlinear parameter (count); 0: none, the draws are Gaussian
};

struct Diagnosis {
  int points = 0;
  double noise_um = 0.0;
  bool noise_estimated = false;
  double rms_before_um = 0.0;          ///< measured − model, as measured (µm)
  double rms_before_setup_um = 0.0;    ///< the same with the set-up terms removed: what effects must explain (µm)
  double rms_after_um = 0.0;           ///< what is left with the chosen explanation (or none), set-up removed (µm)
  SetupTerms setup;                    ///< set-up terms fitted with the chosen explanation (or with none)
  std::vector<Candidate> ranked;       ///< single effects, best ΔBIC first
  std::optional<Candidate> combination; ///< a significant pair, when one effect leaves too much
  std::optional<Candidate> chosen;      ///< what to add: the combination, else the best significant single effect
  /// Explanations (single effects or pairs, plausible) whose ΔBIC lies within the threshold of the chosen one's (or, when
  /// nothing is chosen, significant ones): the data cannot tell them from `chosen`. Non-empty: the verdict says
  /// "ambiguous between …", `chosen` is only the best of them and the plan says what to measure to decide.
  std::vector<Candidate> rivals;
  std::optional<MeasurementPlan> plan;  ///< between `chosen` and the best rival, when there is one
  /// A machine hypothesis named with an equivalence class: the plan between it and the best other member — not an
  /// ambiguity (their fields are alike on the measured flanks), but whether other teeth would tell them apart.
  std::optional<MeasurementPlan> equivalent_plan;
  /// Set-up values the named explanations (chosen, rivals, nearest) need and nobody gave: the effect's default.
  std::vector<AssumedValue> assumed;
  /// What the data do fix when single values of the chosen explanation are "not determined". Empty when every value
  /// is determined.
  std::vector<DeterminedGrowth> determined;
  /// The chosen library explanation drawn from its posterior when its single values are not all determined: what
  /// scene_with_effect.yaml carries instead of a standard uncertainty. None otherwise.
  std::optional<PosteriorDraws> draws;
  /// Why `chosen` is not to be added to the scene (scene_with_effect.yaml is then not written): ambiguous, a fitted
  /// parameter at the end of its allowed range (the fit pushed against its box: the value is no measurement), or the
  /// measurement's reference in doubt (reference_in_doubt). None: accepted, add it.
  std::optional<Decision> withheld;
  /// A measurement nobody said the reference of (no design_um column, no --measured-against), read as against the bare
  /// involute, whose residual is largely minus the scene's design: it looks evaluated against the drawing. The verdict
  /// opens with it; every finding rests on the file as read. None otherwise.
  std::optional<Decision> reference_in_doubt;
  /// True when nothing explains the residual although it is more than noise (the χ² tests of
  /// DiagnoseOptions::unexplained_false_alarm): `chosen` is then empty, `nearest` says what came closest and why it is
  /// no explanation, `residual_pattern` what is left.
  bool unexplained = false;
  /// The nearest library explanation when nothing from the library is named: the fit that leaves least (single or
  /// pair), with why it is no explanation — implausible, what it leaves more than noise, not significant, or (when a
  /// machine element is named instead) a value that is no measurement. None when nothing was fitted.
  std::optional<Candidate> nearest;
  std::optional<Decision> nearest_rejection;
  /// Why what is left with the chosen explanation (or none) is more than noise: the χ² test that says so, with its
  /// numbers. None: what is left is noise.
  std::optional<Decision> remainder_excess;
  /// Why the families beyond the library were tried although the library had an explanation: one of its values is no
  /// measurement (at_end_of_range, not_determined), its parts cancel (parts_cancel) or a library rival lies within the
  /// threshold (ambiguous). None when they were tried because the library named nothing, or not tried.
  std::optional<Decision> beyond_trigger;
  /// The best machine element when it is no explanation either (what it leaves is more than noise): with its rejection.
  std::optional<Candidate> nearest_element;
  /// A machine element that fits about as well as the library's explanation with that explanation's own field: the
  /// library's explanation stays named (element_kept_out).
  std::optional<Decision> element_kept_out;
  /// The pattern of what is left unexplained. None unless `unexplained`.
  std::optional<ResidualPattern> residual_pattern;
  /// Per point (µm): measured − model as measured; after: measured − model with `chosen` (exact simulation) with the
  /// set-up terms removed.
  std::vector<double> residual_before_um, residual_after_um;
  /// The test of "more than noise" after the chosen explanation (or none): Σ of the whitened residual²/σ² (unit-free)
  /// and its degrees of freedom (points − set-up terms − fitted parameters). Without stroke scatter the residual is
  /// its own whitened form.
  double chi2_after = 0.0, chi2_dof = 0.0;
  std::string verdict;                  ///< one paragraph for people, composed from the records above
  /// Beyond the library, tried when it names nothing (what is left noise or `unexplained`) or its explanation is no
  /// finding (`beyond_trigger`): every family's hypotheses (hypothesis_family.hpp) — the chain's
  /// error components changed by a constant, linearly in time, towards a steady state or (C axis) periodically in the
  /// table's turn, each wheel flank's profile and waviness, the wheel profile's wear — best ΔBIC first, rejected ones
  /// after. Empty when not tried.
  std::vector<Candidate> hypotheses;
  /// True when `chosen` is one of `hypotheses`: the verdict names a machine element and its law.
  bool beyond_library = false;
  /// Every decision record of this diagnosis, in the order the pipeline took them: the reference in doubt, the
  /// nearest's rejection, why the families were tried, the machine element kept out or rejected, what is left more than
  /// noise, why withheld (once: a withheld that is the reference in doubt is not listed twice; diagnosis.json's
  /// "decisions").
  std::vector<Decision> decisions() const;
};

/// The sentences of the records (verdict_text.cpp): "X grew by +5.5 ± 0.3 µm between 0.0 and 9.4 min", …
std::string to_text(const DeterminedGrowth& g);
std::string to_text(const AssumedValue& a);
std::string to_text(const ResidualPattern& p);

/// `model` is what the scene models (geometric errors and the scene's own effects); `in_scene` its effect types.
Diagnosis diagnose(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& points, const std::vector<std::string>& in_scene,
                   const DiagnoseOptions& options);

/// The plan that separates explanations a and b (each fitted to `points`; `residual_um` = measured − model there):
/// both explanations' predictions — their effects' first-order deviation plus their own set-up terms, refitted on the
/// measured points — on the grid of every tooth not measured, and their difference in units of noise_um; then a few
/// measurement options (the teeth that differ most, on the plan grid and denser ones) scored by the ΔBIC gap expected
/// after both are refitted on measured + new points, and the cheapest that resolves.
MeasurementPlan plan_measurement(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& points,
                                 const std::vector<double>& residual_um, const Candidate& a, const Candidate& b,
                                 double noise_um, const DiagnoseOptions& options);

/// The probe noise σ diagnose and compare accept when it is given (µm): below kMinNoiseUm no probe measures and the
/// fits' Σr²/σ² would overflow; above kMaxNoiseUm it is no measurement of a ground flank. 0 means "estimate it".
inline constexpr double kMinNoiseUm = limits::kMinNoiseUm, kMaxNoiseUm = limits::kMaxNoiseUm; // core/limits.hpp

/// The smallest σ an estimate gives (µm): the exports' resolution (3 decimals), so that noise-free data give a finite
/// σ nobody divides by zero with.
inline constexpr double kNoiseFloorUm = 1e-3;

/// Noise σ (µm) estimated from residuals. Measured lines (traces: kDenseLinePoints or more points sharing z or ξ on a
/// flank): from their own point-to-point scatter (line_noise_um), at least kNoiseFloorUm. Otherwise (grids, point
/// clouds): a quadratic surface in (roll length, z) fitted per flank, the pooled residual standard deviation; flanks
/// with fewer than 10 points are skipped; if none is left, 0.1 µm — a conservative probe figure.
double estimate_noise_um(const std::vector<MeasuredPoint>& points, const std::vector<double>& residual_um);

} // namespace geartopo::diagnosis
