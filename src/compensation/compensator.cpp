#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/limits.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/core/parallel.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/jacobian.hpp"
#include "geartopo/machine/twist.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace geartopo::compensation {
namespace {

using machine::Pose;
using machine::Vector5d;
using machine::Vector6d;

/// The path point commanded with the correction dq of the axes `axes` (the setting's own on the CFXZAY: q + dq).
grinding::PathPoint with_correction(const ChainAxes& axes, grinding::PathPoint pp, const Vector5d& dq) {
  pp.q = axes.corrected_setting(pp.q, dq);
  return pp;
}

// Exact pose error of the actual wheel against the ideal pose at the nominal command: (translation; rotation vector),
// in w (left: actual = E·ideal) or in g (right: actual = ideal·E).
Vector6d error_w(const Pose& actual, const Pose& ideal) { return machine::pose_error_twist(actual * ideal.inverse()); }
Vector6d error_g(const Pose& actual, const Pose& ideal) { return machine::pose_error_twist(ideal.inverse() * actual); }

struct PoseResult {
  Vector5d dq = Vector5d::Zero();
  double residual_um = 0.0;
};

PoseResult paper_at(const ChainAxes& axes, const grinding::GrindingProcess& process, const grinding::PathPoint& pp,
                    int iterations) {
  const Pose ideal = machine::ideal_wMg(pp.q);
  PoseResult r;
  Vector6d e = Vector6d::Zero();
  for (int it = 0; it < iterations; ++it) {
    const grinding::PathPoint c = with_correction(axes, pp, r.dq);
    e = error_g(process.actual_wMg(c), ideal);
    const machine::Matrix65 J = axes.J_twistg(c.q);
    // Eq. 29: pinv(J) = (JᵀJ)⁻¹Jᵀ for a full-column-rank J, here through an orthogonal decomposition.
    const Vector5d step = Eigen::MatrixXd(J).completeOrthogonalDecomposition().solve(Eigen::VectorXd(e));
    r.dq -= step;
    if (step.head<3>().norm() < 1e-9 && step.tail<2>().norm() < 1e-12) break;
  }
  e = error_g(process.actual_wMg(with_correction(axes, pp, r.dq)), ideal);
  r.residual_um = units::um_from_mm(e.head<3>().norm());
  return r;
}

struct ContactPoint {
  Eigen::Matrix<double, 1, 6> a; // d(normal deviation)/d(twist in w): [nᵀ, (P × n)ᵀ]
  Eigen::Vector3d p;
  double target_mm = 0.0; // the design's helix part at the point: what the axis motions must leave there
};

// Nominal contact points of both flanks of space s with the wheel at stroke position Z (points of the contact line
// beyond the face width count too: the design's value there is its terms extrapolated, a table's held at its edge).
std::vector<ContactPoint> contact_points(const grinding::GrindingSetup& setup, int space, double z, int n) {
  const auto& g = setup.geometry();
  const auto& r = setup.ranges();
  const auto& design = setup.wheel().design();
  std::vector<ContactPoint> pts;
  const int next = space % g.teeth() + 1;
  for (auto [tooth, flank] : {std::pair{space, geartopo::Flank::Right}, std::pair{next, geartopo::Flank::Left}})
    for (int i = 0; i < n; ++i) {
      const double xi = r.xi_active_start_mm + (r.xi_active_end_mm - r.xi_active_start_mm) * i / (n - 1);
      const double z_point = z + setup.wheel().contact_offset_mm(flank, xi);
      const auto fp = setup.flanks().at(tooth, flank, xi, z_point);
      ContactPoint c;
      c.a << fp.n.transpose(), fp.p.cross(fp.n).transpose();
      c.p = fp.p;
      c.target_mm = units::mm_from_um(design.motion_target_um(flank, xi, z_point));
      pts.push_back(c);
    }
  return pts;
}

/// Axes a method may move at every pose: all five, or (cycle) X, Z and C with Y and A held at the gear's values.
using AxisMask = Eigen::Matrix<double, 5, 1>; // 1 free, 0 held

/// The flank objective at one pose: the nominal contact points of both flanks of the space, their normal-deviation
/// rows A (m×6, per unit twist in w) and the scaling D of the corrections (rotary ones weigh like a displacement at
/// the reference radius, so mm and rad weigh alike).
struct FlankObjective {
  FlankObjective(const ChainAxes& axes, const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process,
                 const grinding::PathPoint& pp, const CompensationOptions& o)
      : axes(axes), setup(setup), process(process), pp(pp), pts(contact_points(setup, pp.space, pp.z_stroke_mm, o.contact_points)),
        A(static_cast<long>(pts.size()), 6), ideal(machine::ideal_wMg(pp.q)), gMw(ideal.inverse()),
        L(0.5 * setup.geometry().reference_diameter_mm()), D((Vector5d() << 1.0, 1.0, 1.0, L, L).finished()) {
    for (long i = 0; i < A.rows(); ++i) A.row(i) = pts[static_cast<size_t>(i)].a;
  }

  /// Predicted normal deviations from the design at the contact points (m, mm) with the corrections dq: the pose
  /// error and the wheel radius error of the process at the corrected command, less the design's helix part.
  Eigen::VectorXd deviations(const Vector5d& dq) const {
    const grinding::PathPoint c = with_correction(axes, pp, dq);
    const Vector6d t = error_w(process.actual_wMg(c), ideal);
    Eigen::VectorXd d = A * t;
    for (long i = 0; i < A.rows(); ++i) {
      const auto& point = pts[static_cast<size_t>(i)];
      const double v = (gMw * point.p).y();
      d(i) -= process.wheel_radius_error_mm(v, c) * setup.wheel().normal_per_radial(v) + point.target_mm;
    }
    return d;
  }

  const ChainAxes& axes;
  const grinding::GrindingSetup& setup;
  const grinding::GrindingProcess& process;
  const grinding::PathPoint& pp;
  std::vector<ContactPoint> pts;
  Eigen::Matrix<double, Eigen::Dynamic, 6> A; // m×6
  Pose ideal, gMw;
  double L;
  Vector5d D;
};

PoseResult flank_at(const ChainAxes& axes, const grinding::GrindingSetup& setup,
                    const grinding::GrindingProcess& process, const grinding::PathPoint& pp,
                    const CompensationOptions& o, const Vector5d& start, const AxisMask& free) {
  const FlankObjective f(axes, setup, process, pp, o);
  const auto& A = f.A;
  const auto& D = f.D;
  const double L = f.L;
  const Pose& ideal = f.ideal;
  const long m = A.rows();
  auto deviations = [&f](const Vector5d& dq) { return f.deviations(dq); };
  // Gauss–Newton in the scaled variables u = D·Δq with the ideal Jacobians (the errors are small), in two levels:
  // (1) the step removes the predicted flank deviations (least squares over both contact lines);
  // (2) the freedom that leaves the flanks unchanged (null space of level 1: the screw, and whatever else does not
  //     touch the contact lines) is spent on the wheel's pose error without its spin about the wheel axis, which no
  //     axis can correct and which does not change the surface — so a pure C offset gets a pure C correction;
  // (3) what is still free is resolved by minimum norm.
  // Every decomposition in this file runs on dynamic matrices (MatrixXd): one instantiation of each algorithm
  // instead of one per fixed shape — at -O3 each fixed-size instantiation costs seconds of compile time, more than the
  // SVD of an m×5 matrix costs at run time.
  // Held axes get zero columns: their directions fall into the null space and keep their start value.
  const Eigen::MatrixXd M = A * axes.J_twistw(pp.q) * D.cwiseInverse().asDiagonal() * free.asDiagonal(); // m×5
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  int rank = 0;
  while (rank < sv.size() && sv(rank) > 1e-9 * sv(0)) ++rank;
  const Eigen::MatrixXd V = svd.matrixV();
  const Eigen::MatrixXd N = V.rightCols(5 - rank); // 5×(5−rank): directions that leave every contact point in place
  // Wheel-frame pose error weights: translations 1, rotations L, spin about the wheel axis (g's y) 0.
  const Vector6d S = (Vector6d() << 1.0, 1.0, 1.0, L, 0.0, L).finished();
  const machine::Matrix65 G =
      S.asDiagonal() * axes.J_twistg(pp.q) * D.cwiseInverse().asDiagonal() * free.asDiagonal(); // 6×5

  PoseResult r;
  r.dq = start;
  Eigen::VectorXd d = deviations(r.dq);
  for (int it = 0; it < o.max_iterations; ++it) {
    // Level 1: u = V Σ⁺ Uᵀ d over the first `rank` singular directions.
    Vector5d u = Vector5d::Zero();
    for (int k = 0; k < rank; ++k) u += V.col(k) * (svd.matrixU().col(k).dot(d) / sv(k));
    if (N.cols() > 0) {
      const Vector6d e = S.cwiseProduct(error_g(process.actual_wMg(with_correction(axes, pp, r.dq)), ideal));
      const Eigen::MatrixXd GN = G * N; // 6×(5−rank)
      u += N * GN.completeOrthogonalDecomposition().solve(Eigen::VectorXd(e - G * u));
    }
    const Vector5d step = D.cwiseInverse().cwiseProduct(u);
    r.dq -= step;
    d = deviations(r.dq);
    if (step.head<3>().norm() < 1e-9 && step.tail<2>().norm() < 1e-12) break;
  }
  r.residual_um = units::um_from_mm(std::sqrt(d.squaredNorm() / static_cast<double>(m)));
  return r;
}

/// Contribution of one pose to the gear-level normal equations of the held axes (Y, A) in the scaled variables
/// u = D·Δq: with the pose axes P = {X, Z, C} free, the best pose correction leaves P⊥(d0 + M_G u_G), P⊥ the
/// projector off the range of M_P (m×3), so the gear's u_G minimises Σ ‖P⊥ d0 + P⊥ M_G u_G‖².
struct GearTerms {
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero(); ///< Σ M_Gᵀ P⊥ M_G
  Eigen::Vector2d b = Eigen::Vector2d::Zero(); ///< Σ M_Gᵀ P⊥ d0
};

GearTerms gear_terms_at(const ChainAxes& axes, const grinding::GrindingSetup& setup,
                        const grinding::GrindingProcess& process, const grinding::PathPoint& pp,
                        const CompensationOptions& o) {
  const FlankObjective f(axes, setup, process, pp, o);
  const long m = f.A.rows();
  const Eigen::VectorXd d0 = f.deviations(Vector5d::Zero());
  const Eigen::Matrix<double, Eigen::Dynamic, 5> M = f.A * axes.J_twistw(pp.q) * f.D.cwiseInverse().asDiagonal();
  Eigen::Matrix<double, Eigen::Dynamic, 3> MP(m, 3);
  MP << M.col(0), M.col(2), M.col(4);
  Eigen::Matrix<double, Eigen::Dynamic, 2> MG(m, 2);
  MG << M.col(1), M.col(3);
  // P⊥ x = x − Q (Qᵀ x) over the rank of M_P (Z and C are nearly the same motion on a helicoid: rank-revealing QR).
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr{Eigen::MatrixXd(MP)};
  const Eigen::Index rank = qr.rank();
  const Eigen::MatrixXd Q = Eigen::MatrixXd(qr.householderQ()).leftCols(rank);
  const Eigen::Matrix<double, Eigen::Dynamic, 2> PG = MG - Q * (Q.transpose() * MG);
  const Eigen::VectorXd Pd = d0 - Q * (Q.transpose() * d0);
  GearTerms g;
  g.H = MG.transpose() * PG;
  g.b = MG.transpose() * Pd;
  return g;
}

} // namespace

CorrectionTable compute_corrections(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process,
                                    const StrokeCheck& strokes, const CompensationOptions& o) {
  // 0 or NaN made the path's sample count undefined (ceil(len / 0) cast to int), 1e-9 mm billions of poses.
  limits::require(limits::step_mm_refusal(o.step_mm), "compute_corrections: step_mm");
  const std::vector<grinding::PathPoint> samples = setup.path().sample(o.step_mm);
  // The axes the corrections move: the setting's on the CFXZAY, the chain's own on any other (chain_axes.hpp).
  const ChainAxes axes{strokes.chain, strokes.datum_face_z_mm};
  // Cycle: first the gear's Y and A (one linear least-squares problem over every pose), then every pose with them held.
  Vector5d gear_start = Vector5d::Zero();
  if (o.method == Method::Cycle) {
    std::vector<GearTerms> terms(samples.size());
    geartopo::parallel_for(static_cast<int>(samples.size()), 0, [&](int i) {
      terms[static_cast<size_t>(i)] = gear_terms_at(axes, setup, process, samples[static_cast<size_t>(i)], o);
    });
    GearTerms sum; // summed in path order: the same result at any thread count
    for (const auto& t : terms) sum.H += t.H, sum.b += t.b;
    const Eigen::Vector2d u = -Eigen::MatrixXd(sum.H).completeOrthogonalDecomposition().solve(Eigen::VectorXd(sum.b));
    const double L = 0.5 * setup.geometry().reference_diameter_mm();
    gear_start(1) = u(0);     // Y (mm)
    gear_start(3) = u(1) / L; // A (rad)
  }
  const AxisMask cycle_axes = (AxisMask() << 1.0, 0.0, 1.0, 0.0, 1.0).finished();
  std::vector<CorrectionRow> rows(samples.size());
  geartopo::parallel_for(static_cast<int>(samples.size()), 0, [&](int i) {
    const auto& pp = samples[static_cast<size_t>(i)];
    const PoseResult r = o.method == Method::Paper ? paper_at(axes, process, pp, o.max_iterations)
                         : o.method == Method::Cycle
                             ? flank_at(axes, setup, process, pp, o, gear_start, cycle_axes)
                             : flank_at(axes, setup, process, pp, o, Vector5d::Zero(), o.free_axes);
    CorrectionRow& row = rows[static_cast<size_t>(i)];
    row.space = pp.space;
    row.z_stroke_mm = pp.z_stroke_mm;
    row.time_s = pp.time_s;
    row.correction = r.dq;
    row.residual_um = r.residual_um;
    if (axes.is_setting()) {
      row.machine_axes = pp.q;
      row.machine_axes.z += strokes.datum_face_z_mm;
      row.within_strokes = strokes.model.within_strokes(machine::AxisPose::from_vector(row.machine_axes.vector() + r.dq));
    } else { // the chain's own axes against its own strokes
      row.machine_axes = machine::AxisPose::from_vector(axes.axes(pp.q));
      row.within_strokes = axes.within_strokes(row.machine_axes.vector() + r.dq);
    }
  });
  return CorrectionTable(std::move(rows), axes);
}

machine::Pose CompensatedProcess::actual_wMg(const grinding::PathPoint& pp) const {
  const Vector5d dq = table_.at(pp.space, pp.z_stroke_mm);
  if (pose_ == CorrectedPose::Exact || !table_.axes().is_setting())
    return inner_.actual_wMg(with_correction(table_.axes(), pp, dq));
  // q′ = q + Δq on Z and C (the axes a stroke moves anyway), then the ideal motion of X, Y, A from q′ (header).
  grinding::PathPoint moved = pp;
  moved.q.z += dq(2);
  moved.q.c += dq(4);
  const machine::Pose wMg = inner_.actual_wMg(moved);
  if (dq(0) == 0.0 && dq(1) == 0.0 && dq(3) == 0.0) return wMg;
  return wMg * machine::ideal_xya_motion_gMg(moved.q.y, dq(0), dq(1), dq(3));
}

grinding::PathPoint CompensatedProcess::corrected(const grinding::PathPoint& pp) const {
  return with_correction(table_.axes(), pp, table_.at(pp.space, pp.z_stroke_mm));
}

machine::Vector6d CompensatedProcess::error_twist_w(const grinding::PathPoint& pp) const {
  const Vector5d dq = table_.at(pp.space, pp.z_stroke_mm);
  const grinding::PathPoint c = with_correction(table_.axes(), pp, dq);
  return inner_.error_twist_w(c) + table_.axes().J_twistw(pp.q) * dq;
}

} // namespace geartopo::compensation
