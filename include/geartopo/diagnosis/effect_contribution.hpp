// geartopo — the first-order deviation physical effects add at fixed measured points (µm), for many values of their
// parameters: a diagnosis fit evaluates it thousands of times at the same points. What the effects' parameters do not
// change — each point's generating pose (space, stroke position, time stamp, commanded axes), its flank point and
// normal, the wheel contact and the machine's axis Jacobian there — is computed once; an evaluation is then the
// effects' own hooks at the stored poses and a few dot products per point (docs/diagnosis.md, "How a fit evaluates
// an effect"). Units: mm and rad inside, µm out.
#pragma once

#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/effects/effect.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/wheel_path.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/machine_data.hpp" // Matrix65

#include <Eigen/Core>

#include <functional>

#include <memory>
#include <span>
#include <vector>

namespace geartopo::diagnosis {

using measurement::MeasuredPoint; ///< what diagnosis works on: measured points, read by the measurement library

class EffectContribution {
public:
  /// The set-up must outlive this object; `points` are copied into per-point state (no reference kept). `chain`: the
  /// scene's kinematic chain, with the gear's datum face at its z = datum_face_z_mm (null: the CFXZAY). `keep_going`
  /// (may be empty): a Ctrl-C check before every 1024 points (10⁶ contacts take seconds); it may throw to stop.
  EffectContribution(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& points, int threads = 0,
                     const machine::KinematicChain* chain = nullptr, double datum_face_z_mm = 0.0,
                     const std::function<void()>& keep_going = {});

  /// The effects' first-order deviation at every point (n, µm) over the ideal machine, referred to the nominal flank
  /// at the mean allowance: the same quantity as
  ///   predict(setup, effects::EffectsProcess(grinding::IdealProcess{}, effects, chain, datum_face_z_mm), points,
  ///           grinding::Method::Linear)
  /// and equal to it to rounding (the sums are associated differently: tests/diagnosis/test_effect_contribution.cpp).
  /// The effects must be bound to the same set-up. Results do not depend on `threads`.
  Eigen::VectorXd evaluate_um(const std::vector<std::unique_ptr<effects::Effect>>& effects, int threads = 0) const;

  /// The effects' first-order deviation alone (n, µm): evaluate_um without the mean-allowance offset, which it adds
  /// to this. Effects add independently, so a fit may evaluate each of its effects on its own and sum.
  Eigen::VectorXd deviation_um(std::span<const effects::Effect* const> effects, int threads = 0) const;
  /// The constant evaluate_um adds (µm): the gear's mean-allowance offset from the nominal flank.
  double offset_um() const { return offset_um_; }

  std::size_t size() const { return points_.size(); }
  /// The same state at a subset of the points, in the order given (each index < size()): what a fit on a subsample of
  /// the points evaluates (diagnosis/effect_fit.hpp, FitSubsample). Nothing is recomputed; the values are copied.
  EffectContribution rows(std::span<const std::size_t> indices) const;

  /// The first-order deviation at every point per unit change of each of the chain's 43 error components, at the
  /// point's generating pose (n × 43; µm per mm for lengths, per rad for angles): wᵀ J_twistw_e(q)
  /// (machine/first_order.hpp; on another chain than the CFXZAY its own error Jacobian at its axes θ(q), moved to the
  /// datum as ChainProcess::error_twist_w does) — what a constant change δe_k adds is column k · δe_k. Results do not
  /// depend on `threads`.
  Eigen::MatrixXd component_sensitivity_um(int threads = 0, const std::function<void()>& keep_going = {}) const;
  /// The generating path point of point i (its space, stroke position, time and commanded axes).
  const grinding::PathPoint& path_point(std::size_t i) const { return points_[i].pp; }
  /// The wheel axial coordinate of point i's contact (mm).
  double wheel_axial_mm(std::size_t i) const { return points_[i].v; }

private:
  EffectContribution() = default;
  /// Per point (≈ 170 bytes): the deviation is d = a_qᵀ δq + wᵀ ξ − δR(v)·normal_per_radial with
  ///   w = (n; P × n)          so that n·(δp + δθ × P) = wᵀ (δp; δθ) for a pose-error twist ξ = (δp; δθ) in w,
  ///   a_q = J_twistw_q(q)ᵀ w  the deviation per unit command offset of each axis (X, Y, Z mm; A, C rad); on another
  ///                           chain its own axes' (J_twistw_theta at θ(q), moved to the datum: J_twistw_axes).
  struct PointState {
    grinding::PathPoint pp;         ///< generating pose: the effects' hooks are evaluated here
    machine::Vector5d a_q;          ///< 5: mm per axis unit
    machine::Vector6d w;            ///< 6: (n; P × n)
    double v = 0.0;                 ///< wheel axial coordinate of the contact (mm)
    double normal_per_radial = 0.0; ///< normal displacement of the wheel surface per radial change at v
  };
  /// The spatial twist per unit of each of the machine's axes at q (6×5): J_twistw_q, or the chain's J_twistw_theta.
  machine::Matrix65 J_twistw_axes(const machine::AxisPose& q) const;
  /// wheel_radius_errors_mm of an effect that evaluates in batches, at every point (mm), in chunks of fixed points.
  std::vector<double> batched_radius_mm(const effects::Effect& e, int threads) const;

  std::vector<PointState> points_;
  double offset_um_ = 0.0; ///< mean_allowance_offset_um of the gear
  const machine::KinematicChain* chain_ = nullptr; ///< null or the CFXZAY: the closed form of machine/first_order.hpp
  double datum_face_z_mm_ = 0.0;
};

} // namespace geartopo::diagnosis
