// geartopo — a family of explanations beyond the library (docs/adding-an-effect.md, "Adding a hypothesis family";
// docs/diagnosis.md, "Beyond the library"). A family enumerates hypotheses (a component changed under a law, one wheel
// flank's profile, …), says how each one's field at the measured contact states is linear in a few coefficients — the
// columns X (n × p) with field = X β — and reads fitted coefficients and their covariance back into a finding (values
// with σ, a sentence, why it is implausible). diagnose fits every family's hypotheses by least squares on the residual
// with the set-up terms removed (one projection per hypothesis: hundreds in a fraction of a second on 10⁵ points),
// ranks them by ΔBIC and names the best with its equivalence class. A family is one class in one file and one line in
// families/family_list.hpp; a caller can add its own to DiagnoseOptions::families. Units: µm for fields; each
// coefficient in the unit its columns are per.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"

#include <Eigen/Dense>

#include <functional>
#include <optional>
#include <string_view>
#include <vector>

namespace geartopo::diagnosis {

class SetupTermModel; // private: the set-up terms a measurement carries (src/diagnosis/setup_terms.hpp)

/// What every family sees at a set of points (the measured ones, or a plan's new ones): the setup, each point's contact
/// state, and what the states give every family alike, computed on first use and kept — the first-order sensitivity
/// to each of the chain's error components, the grinding times, the C angles. Not thread-safe (one diagnosis uses it
/// from one thread; the columns themselves are computed in parallel).
class ContactStates {
public:
  /// `terms`: the set-up terms at these points (null for a plan's new points, where nothing is judged); `teeth`: the
  /// points' teeth (empty when not known); `keep_going` (may be empty): the Ctrl-C check of the sensitivity's chunks.
  ContactStates(const grinding::GrindingSetup& setup, const EffectContribution& at, const SetupTermModel* terms,
                int threads, const std::vector<int>& teeth = {}, std::function<void()> keep_going = {});

  const grinding::GrindingSetup& setup() const { return setup_; }
  const EffectContribution& at() const { return at_; }
  std::size_t size() const { return at_.size(); }
  int threads() const { return threads_; }
  /// n × 43 (µm per mm or rad of each component): EffectContribution::component_sensitivity_um.
  const Eigen::MatrixXd& component_sensitivity_um() const;
  const Eigen::VectorXd& time_s() const; ///< n: each point's grinding time (s since the first stroke began)
  const Eigen::VectorXd& c_rad() const; ///< n: each point's commanded C angle (rad)
  /// The job's duration (s): the last stroke's end, or the last point's time if later. A drift's reach is judged over it.
  double job_s() const;
  /// How many different teeth the points are on (count; 0 when not known): how often they sample the table's turn.
  int teeth_measured() const { return teeth_measured_; }
  /// Columns with the set-up terms removed (and whitened, with stroke scatter): what they can explain (n × p). The
  /// columns unchanged when these states have no set-up terms.
  Eigen::MatrixXd judged(const Eigen::MatrixXd& X) const;
  /// The deviation of effects at these points (n, µm): EffectContribution::deviation_um.
  Eigen::VectorXd deviation_um(const std::vector<const effects::Effect*>& effects) const;

private:
  const grinding::GrindingSetup& setup_;
  const EffectContribution& at_;
  const SetupTermModel* terms_;
  int threads_;
  int teeth_measured_ = 0;
  std::function<void()> keep_going_;
  mutable std::optional<Eigen::MatrixXd> sensitivity_;
  mutable std::optional<Eigen::VectorXd> time_, c_;
};

/// A least-squares fit of one hypothesis' columns to the residual (set-up terms removed).
struct LinearFit {
  Eigen::VectorXd beta; ///< p: the coefficients
  Eigen::MatrixXd cov;  ///< p × p: σ̂² (X'ᵀX')⁻¹, σ̂² = RSS/ν of the whitened residual
  double rss = 0.0;     ///< µm²
};

class HypothesisFamily {
public:
  virtual ~HypothesisFamily() = default;
  /// Its name in diagnosis.json and the docs: "component_constant", "wheel_flank_waviness", …
  virtual std::string_view name() const = 0;
  /// Its hypotheses at these points, unfitted: Candidates with their changes or effects (and wheel_flank) set, in the
  /// order they are listed when their ΔBIC ties. `in_scene` is not yet filtered: diagnose skips a hypothesis whose
  /// scene_name the scene models already.
  virtual std::vector<Candidate> enumerate(const ContactStates& states, const DiagnoseOptions& options) const = 0;
  /// Its field's columns at these points (n × p, µm per unit of each coefficient): the field is X β.
  virtual Eigen::MatrixXd columns(const Candidate& hypothesis, const ContactStates& states) const = 0;
  /// The largest plausible size of each coefficient (p, its unit): a hypothesis that moves the judged data by less
  /// than 1e-4 µm RMS at these sizes is invisible on these flanks and is not tried.
  virtual Eigen::VectorXd plausible_size(const Candidate& hypothesis, const ContactStates& states,
                                         const DiagnoseOptions& options) const = 0;
  /// The finding: `hypothesis` with its fitted values (changes' sizes, effects' values), parameters with σ,
  /// description and, when implausible, its rejection. Scores (ΔBIC, RMS, correlation) are filled in by diagnose.
  virtual Candidate finding(Candidate hypothesis, const LinearFit& fit, const ContactStates& states,
                            const DiagnoseOptions& options) const = 0;
  /// The library effect whose parameters this family fits one side or one grid point at a time
  /// ("wheel_flank_profile"), empty for none: diagnose does not try that effect as a library candidate of its own.
  virtual std::string_view effect_type() const { return {}; }
  /// Parameters chosen from a grid rather than fitted (a time constant, a wave count): each is charged ln n in the
  /// ΔBIC like a fitted one.
  virtual int grid_parameters() const { return 0; }
  /// The name a scene lists it under when it models it already (Workbench::effect_types: an effect's type, a change
  /// as "E_AOA linear_in_time").
  virtual std::string scene_name(const Candidate& hypothesis) const;
  /// Which of its fitted hypotheses to list (`mine`, in enumeration order; `all`: every family's, for comparisons such
  /// as a steady state against the same component's constant law), possibly amended (a grid's 1σ range). A family
  /// fitted on a grid keeps its best grid point here. Default: all of them.
  virtual std::vector<Candidate> select(std::vector<Candidate> mine, const std::vector<Candidate>& all,
                                        const DiagnoseOptions& options) const;
};

/// A hypothesis' field at these points (n, µm): its family's columns times its coefficients.
Eigen::VectorXd hypothesis_field(const Candidate& hypothesis, const ContactStates& states);

} // namespace geartopo::diagnosis
