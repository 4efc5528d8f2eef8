// geartopo diagnosis, private — diagnose() as a pipeline of stages (docs/diagnosis.md, "The pipeline"; drawn in
// docs/architecture.md). Every stage reads the const Context and the earlier stages' results and returns its own
// value; none changes another's result. The outcome (compose.cpp) assembles the Diagnosis from them and the verdict's
// sentences are composed from its records in one place (verdict_text.cpp).
//
//   Context ─► reference_in_doubt ─► fit_library ─► fit_pairs ─► judge_library ─► try_families ─► find_alternatives ─► make_plans ─►
//   (residual,   (read against     (each effect   (pairs of    (the pick        (the families    (rivals, look-alikes, (what to
//    noise,       the drawing?)     alone)         favoured     against the      beyond the       equivalence          measure)
//    set-up                      effects)     noise)           library)         classes)
//    terms)
//   ─► posterior_draws ─► compose
//      (what the data     (records,
//       determine)         verdict)
//
// Units: µm for residuals and fields; parameters in their own units (their keys).
#pragma once

#include "../effect_fit.hpp"
#include "../setup_terms.hpp"

#include "geartopo/diagnosis/decision.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"
#include "geartopo/diagnosis/hypothesis_family.hpp"

#include <Eigen/Dense>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::diagnosis::stages {

/// Per flank with at least 10 points: the point indices and the 6-term quadratic surface in (roll length, z), both
/// scaled to [−1, 1] (idx.size() × 6) — the basis of the noise estimate and of the structured-remainder test.
struct FlankSurface {
  std::vector<size_t> idx;
  Eigen::MatrixXd X;
};
std::vector<FlankSurface> flank_surfaces(const std::vector<MeasuredPoint>& pts);

/// What every stage reads, built once: the measurement against the model, its noise, its set-up terms and each
/// point's contact state (what every fit evaluates thousands of times).
class Context {
public:
  /// Checks the options and the points (std::invalid_argument naming the option), predicts the model at the points
  /// and estimates the noise when it is not given.
  Context(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
          const std::vector<MeasuredPoint>& points, const std::vector<std::string>& in_scene,
          const DiagnoseOptions& options);

  const grinding::GrindingSetup& setup;
  const grinding::GrindingProcess& model;
  const std::vector<MeasuredPoint>& points;
  const std::vector<std::string>& in_scene;
  const DiagnoseOptions& options;
  double n = 0.0;                          ///< points (count, as a real for the statistics)
  std::vector<double> residual_before_um;  ///< n: measured − model (exact simulation)
  Eigen::VectorXd before;                  ///< n: the same as a vector
  double noise_um = 0.0;
  bool noise_estimated = false;
  double rms_before_um = 0.0, rms_before_setup_um = 0.0;
  SetupTermModel setup_terms;              ///< with the options' stroke scatter and model uncertainty, if any
  EffectContribution at_points;            ///< the contact state of every point
  std::optional<FitSubsample> subsample;   ///< a large measurement's every k-th point, for the fits' starts
  std::vector<FlankSurface> surfaces;      ///< the structured-remainder test's surfaces
  double first_time_s = 0.0, last_time_s = 0.0; ///< the measured points' grinding times, earliest and latest

  const FitSubsample* search() const { return subsample ? &*subsample : nullptr; }
  /// ln n: BIC's charge per parameter.
  double ln_n() const;
};

/// Stage 0: a measurement nobody said the reference of (MeasuredPoint::reference_declared false: no design_um column,
/// no --measured-against) read as against the bare involute, whose residual is largely minus the scene's design: it
/// looks evaluated against the drawing (reference.cpp). None otherwise.
std::optional<Decision> reference_in_doubt(const Context& ctx);
/// The same for any residual (n, µm) with its set-up terms: compare's check (diagnosis::reference_in_doubt).
std::optional<Decision> reference_in_doubt(const std::vector<MeasuredPoint>& points, const Eigen::VectorXd& residual,
                                           const SetupTermModel& setup_terms, double noise_um);

/// The progress callback's counts (DiagnoseOptions::on_candidate_fitted): fits done and known so far.
struct FitProgress {
  const DiagnoseOptions& options;
  long long done = 0, known = 0;
  void fitted() {
    if (options.on_candidate_fitted) options.on_candidate_fitted(++done, known);
  }
};

/// Stage 1: every library effect not in the scene fitted alone.
struct LibraryFits {
  std::vector<Candidate> ranked;                     ///< best ΔBIC first, rejected ones after
  std::map<std::string, std::vector<double>> values; ///< each type's fitted values: the pairs' warm starts
};
LibraryFits fit_library(const Context& ctx, FitProgress& progress);

/// Stage 2: pairs, when the best single effect is significant — every pair among the favoured ones, and the best with
/// each partner the linearised joint fit points to. The pick is the best significant pair, else the best single.
struct PairFits {
  std::vector<Candidate> pairs;         ///< every pair fitted, taken or not
  std::optional<Candidate> combination; ///< the best pair that beats the best single effect by the threshold
  std::optional<Candidate> pick;        ///< the library's explanation before it is judged against the noise
};
PairFits fit_pairs(const Context& ctx, const LibraryFits& library, FitProgress& progress);

/// What is left with an explanation (or none) and whether it is more than noise.
struct Remainder {
  Eigen::VectorXd raw;     ///< measured − model − explanation, as measured (n, µm)
  Eigen::VectorXd removed; ///< the same with the set-up terms removed, as shown (n, µm)
  Eigen::VectorXd judged;  ///< what the tests of "more than noise" see: the whitened remainder (= removed without
                           ///< stroke scatter)
  double dof = 1.0;        ///< degrees of freedom left (count)
  std::optional<Decision> excess; ///< the χ² test that says it is more than noise; none: noise
  double rms_um(double n) const { return std::sqrt(removed.squaredNorm() / n); }
};
/// By the exact simulation with the explanation's effects or changes (none: the model alone), and two χ² tests, each
/// at half the false-alarm probability: all of what is left, and its smooth part per flank.
Remainder remainder_with(const Context& ctx, const Candidate* explanation);

/// Stage 3: the library's pick against the noise.
struct LibraryJudgement {
  std::optional<Candidate> pick;          ///< the pick, when what it leaves is noise (rms_after_um set)
  std::optional<Candidate> refused;       ///< the pick refused because what it leaves is more than noise
  Remainder remainder;                    ///< with the kept pick, or with none
  std::optional<Candidate> nearest;       ///< no pick: the refused one, else the best fit by ΔBIC
  std::optional<Decision> nearest_rejection; ///< why the nearest is no explanation
  bool unexplained = false;               ///< no pick and what is left is more than noise
  /// Why the kept pick is no finding: a value that is no measurement, its parts cancelling, or a rival of the library
  /// within the threshold (ambiguous); the families are then tried beside it (try_families).
  std::optional<Decision> not_measured;
};
LibraryJudgement judge_library(const Context& ctx, const LibraryFits& library, const PairFits& pairs);

/// The library's explanations (single effects and pairs) the data cannot tell from the pick (alternatives.cpp): best
/// ΔBIC first, other physics before the pick with a partner.
std::vector<Candidate> library_rivals(const Context& ctx, const LibraryFits& library, const PairFits& pairs,
                                      const Candidate& pick);

/// The columns of a library explanation's fitted parameters at its fitted values (n × P, µm per file unit, set-up
/// terms removed): central differences of its first-order deviation.
Eigen::MatrixXd library_columns(const Context& ctx, const Candidate& c);
/// An explanation's first-order field at its fitted values (n, µm, set-up terms removed).
Eigen::VectorXd explanation_field(const Context& ctx, const Candidate& c);
/// How much of a field lies in the span of B's columns (0 … 1): ‖B·β‖ / ‖f‖ with β the least-squares fit of f by B.
double share_of_field_in_span(const Eigen::VectorXd& f, const Eigen::MatrixXd& B);

/// Stage 4: the families beyond the library, tried when the library names nothing (what is left noise or not), or its
/// pick is no finding (LibraryJudgement::not_measured); what their best hypothesis does to the library's explanation.
struct BeyondLibrary {
  enum class Outcome {
    not_tried,       ///< the library's explanation stands, or nothing is left to explain
    not_usable,      ///< the best hypothesis is rejected, not significant, or worse than the pick by the threshold
    named,           ///< the best hypothesis is named (it leaves noise)
    rival,           ///< it fits as well as the pick with another field: a rival
    kept_out,        ///< it fits about as well with the pick's own field: the pick stays named
    rejected,        ///< it would be named but leaves more than noise (nothing explained): the nearest element
    not_noise,       ///< it would replace the pick but leaves more than noise: the pick stays named
  };
  Outcome outcome = Outcome::not_tried;
  std::vector<Candidate> hypotheses;     ///< every family's hypotheses, ranked (the best first)
  std::optional<Candidate> best;         ///< the best hypothesis as named, rival or rejected (rms_after, rejection)
  std::optional<Remainder> remainder;    ///< what the best leaves (named, rejected, not_noise)
  std::optional<Decision> kept_out;      ///< outcome kept_out: with ΔBIC and the share of the field the pick can make
  std::unique_ptr<ContactStates> states; ///< the measured points' contact states the families used
  bool tried() const { return outcome != Outcome::not_tried; }
};
BeyondLibrary try_families(const Context& ctx, const LibraryJudgement& judgement);

/// Every family's hypotheses fitted to the residual, ranked: plausible ones by ΔBIC, then rejected ones
/// (families/fit_hypotheses.cpp).
std::vector<Candidate> fit_hypotheses(const Context& ctx, const ContactStates& states);

/// Stage 5: what competes with the named explanation — rivals the data cannot tell from it, the library explanations
/// that can leave a named element's field, and the best hypothesis' equivalence class.
struct Alternatives {
  std::vector<Candidate> rivals;                ///< best ΔBIC first, another physics before a nested one
  std::vector<std::string> equivalent;          ///< the best hypothesis' equivalence class (names)
  /// The equivalence class of each listed hypothesis after the best (index as in BeyondLibrary::hypotheses, [0]
  /// empty), among the listed ones; empty for one that is in an earlier one's class: one row each (hypothesis_rows).
  std::vector<std::vector<std::string>> listed_classes;
  std::optional<Candidate> equivalent_member;   ///< its best other member, for the plan that would separate them
  std::vector<std::string> library_equivalent;  ///< a named element's library look-alikes (names)
  /// Each user's own effect's look-alikes (Candidate::look_alikes), by its name.
  std::map<std::string, std::vector<std::pair<std::string, double>>> own_look_alikes;
};
Alternatives find_alternatives(const Context& ctx, const LibraryFits& library, const PairFits& pairs,
                               const LibraryJudgement& judgement, const BeyondLibrary& beyond);

/// Stage 6: what to measure to tell the named explanation from its best rival, and from its best equivalent member.
struct Plans {
  std::optional<MeasurementPlan> plan, equivalent_plan;
};
Plans make_plans(const Context& ctx, const std::optional<Candidate>& chosen, const Alternatives& alternatives);

/// Stage 7: what the data determine of the chosen library explanation when its single values are not all
/// determined — its posterior as equally likely value sets (posterior.cpp); none otherwise.
std::optional<PosteriorDraws> posterior_draws(const Context& ctx, const std::optional<Candidate>& chosen);

/// Stage 8: the Diagnosis with its records, from every stage's result; the verdict composed from them.
Diagnosis compose(const Context& ctx, std::optional<Decision> reference, const LibraryFits& library,
                  const PairFits& pairs, const LibraryJudgement& judgement, const BeyondLibrary& beyond,
                  const Alternatives& alternatives, Plans plans, std::optional<PosteriorDraws> draws);

/// The verdict paragraph from a Diagnosis' records (verdict_text.cpp), the one place the sentences are made.
std::string verdict_text(const Diagnosis& d, const DiagnoseOptions& options);

/// Why an explanation's single values are no measurement: one at the end of its allowed range, or one the data do
/// not determine; none when every fitted value is measured.
std::optional<Decision> not_measured(const Candidate& c);
/// A fitted value at the end of its allowed range (the first such), none when none is.
std::optional<Decision> at_the_end_of_its_range(const Candidate& c);

} // namespace geartopo::diagnosis::stages
