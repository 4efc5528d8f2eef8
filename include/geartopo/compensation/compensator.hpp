// geartopo — compensation of the wheel's errors along the path (docs/compensation.md).
//
// paper: the seed paper's method (its Eq. 29, re-derived): at every pose the wheel-frame pose error twist E of the
//        actual wheel against the ideal one is driven to zero in the least-squares sense by axis corrections,
//        Δq ← Δq − pinv(J_M)·E(q + Δq), with J_M the 6×5 body Jacobian (jacobian.hpp; on another chain than the CFXZAY
//        J_twistg_theta of its own axes, chain_axes.hpp) and the errors re-evaluated at
//        the corrected command until the step vanishes. pinv mixes mm and rad exactly as the paper's formula does.
// flank: at every pose choose the corrections that minimise the predicted normal deviations FROM THE DESIGN of the
//        nominal contact points on both flanks of the space (the target is the drawing's part the motions must make at
//        each contact point, FlankDesign::motion_target_um: the profile part is dressed into the wheel) (equal weights along the contact lines, all modelled sources: pose and
//        wheel radius). Directions that do not change the ground surface — spin about the wheel axis, motion along
//        the helicoid's screw — have no effect on that objective; among equivalent corrections the smallest is taken
//        (minimum norm with rotary corrections scaled by the reference radius, so mm and rad weigh alike).
// cycle: the flank objective with what a profile grinder's cycle can move: X, Z and C at every pose, Y and A once for
//        the gear. The gear's Y and A minimise the flank deviations left over all poses after each pose's best X, Z, C
//        (one linear least-squares problem in two unknowns); then every pose is solved as in flank with them held.
// Units: mm, rad.
#pragma once

#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/machine/machine_model.hpp"

namespace geartopo::compensation {

enum class Method { Paper, Flank, Cycle };

struct CompensationOptions {
  Method method = Method::Flank;
  double step_mm = 2.0;      ///< path sampling of the correction table along each stroke
  int contact_points = 15;   ///< per flank along the contact line (flank method)
  int max_iterations = 12;   ///< Newton iterations per pose
  /// Axes the flank method may move at every pose (1 free, 0 held; X, Y, Z, A, C): all, or e.g. X alone for the
  /// radial infeed that grinds a designed helix crowning (docs/modifications.md).
  Eigen::Matrix<double, 5, 1> free_axes = Eigen::Matrix<double, 5, 1>::Ones();
};

/// The axes corrections are computed in and the strokes they are checked against: the machine model, where the gear's
/// datum face sits and the scene's chain. On the CFXZAY (or no chain) the setting's coordinates against the model's
/// strokes; on any other chain its own axes (ChainAxes) against its own strokes.
struct StrokeCheck {
  const machine::MachineModel& model;
  double datum_face_z_mm = 0.0;
  const machine::KinematicChain* chain = nullptr;
};

/// Corrections for every sample of the path. `process` is what the machine does for a given command (geometric
/// errors and any modelled effect).
CorrectionTable compute_corrections(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process,
                                    const StrokeCheck& strokes, const CompensationOptions& options);

/// How CompensatedProcess evaluates the wheel pose at a corrected command.
enum class CorrectedPose {
  /// The inner process at q + Δq: every joint whose axis the correction moves is recomputed (X, Y, A besides C, Z).
  Exact,
  /// The inner process at q with C and Z corrected, then the ideal motion of the X, Y, A corrections:
  /// wMg(q + Δq) = wMg(q′) · ideal(q′)⁻¹ · ideal(q′ + Δq_XYA), q′ = q + Δq_ZC. Exact for the ideal chain; what it
  /// leaves out is how the pose error E_w (wMg = E_w·ideal) changes over the µm and µrad of Δq_XYA: the slopes of the
  /// X, Y, A error tables times Δq, the squareness times ΔY, the Y slide's errors and the A axis' location turned by
  /// ΔA — products of an error and a correction, second order: 0.004 µm on the crowned default scene (motions up to
  /// 70 µm / 484 µrad), ≤ 0.011 µm with every component at up to 50 µm / 100 µrad (test_corrected_pose.cpp compares
  /// it with Exact). Along a stroke X, Y and A then stand still for the chain evaluator, which recomputes only C and
  /// Z: a modified or compensated gear costs 1.3× a plain one instead of 1.9× (docs/performance.md).
  HeldSlideErrors,
};

/// The machine running the corrected commands: command q + Δq(space, Z) for every path point — on another chain than
/// the CFXZAY its axes θ(q) + Δθ (the table's ChainAxes), the pose always exact there (HeldSlideErrors is the CFXZAY's).
class CompensatedProcess final : public grinding::GrindingProcess {
public:
  CompensatedProcess(const grinding::GrindingProcess& inner, const CorrectionTable& table,
                     CorrectedPose pose = CorrectedPose::HeldSlideErrors)
      : inner_(inner), table_(table), pose_(pose) {}

  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override;
  /// First order: the inner twist at the corrected command plus the ideal spatial Jacobian times the correction.
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override;
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    return inner_.wheel_radius_error_mm(v, corrected(pp));
  }
  bool changes_wheel_radius() const override { return inner_.changes_wheel_radius(); }

  grinding::PathPoint corrected(const grinding::PathPoint& pp) const;

private:
  const grinding::GrindingProcess& inner_;
  const CorrectionTable& table_;
  CorrectedPose pose_;
};

} // namespace geartopo::compensation
