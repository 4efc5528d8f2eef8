// geartopo — the deviation the wheel leaves at one point of a nominal flank (docs/grinding.md).
//
// exact:  the ground flank is the envelope of the wheel at its actual poses. Along the flank's normal line
//         P + t n (n out of the material), the wheel at stroke position Z first enters at t_in(Z); the material left is
//         t < min_Z t_in(Z). The deviation (plus material positive) is that minimum. Z is searched continuously
//         around the nominal generating position Z₀ = z − z_c(ξ), so there are no scallops from a pose step: first
//         by the vertex of the parabola through three depths (4 poses per point) — or through two depths and the
//         depth's curvature along Z when a TopologyPlan knows it from the ideal process (3 poses per point) — and by
//         Brent's method (±0.5 mm, then ±4 mm) wherever the depth is not locally quadratic enough to trust a vertex.
// linear: the first-order deviation n·(δp + δθ × P) − δR(v)/√(1 + R′(v)²) of the pose error twist and the radial
//         wheel-radius error (moved onto the wheel's normal) at the generating pose (envelope theorem: moving the contact along the stroke changes it only to second order).
// Units: mm in, mm out (callers convert to µm).
#pragma once

#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/grinding/form_wheel.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/wheel_path.hpp"

namespace geartopo::grinding {

enum class Method { Exact, Linear };

/// The space whose grinding makes the given flank: right flank of tooth j → space j; left flank → space j − 1.
int space_of(int tooth, geartopo::Flank flank, int teeth);

/// Everything the first-order (linear) deviation at a flank point needs that the process does not change: the
/// generating pose and the contact geometry. The process's errors enter only through its twist and wheel-radius error
/// at `pp` (linear_deviation_mm), so a caller evaluating many processes at the same points (a fit) computes this once.
struct LinearContact {
  PathPoint pp;                   ///< generating pose: space, nominal stroke Z₀, time, commanded axes
  Eigen::Vector3d p;              ///< flank point, workpiece frame w (mm)
  Eigen::Vector3d n;              ///< unit flank normal out of the material, w
  double v = 0.0;                 ///< wheel axial coordinate of the contact (mm)
  double normal_per_radial = 0.0; ///< the wheel surface's normal displacement per radial change at v (form_wheel.hpp)
};

/// The first-order deviation (mm) n·(δp + δθ × P) − δR(v)·normal_per_radial(v) of `process` at a contact.
double linear_deviation_mm(const LinearContact& c, const GrindingProcess& process);

struct DeviationResult {
  double deviation_mm = 0.0;
  double z_stroke_mm = 0.0; ///< stroke position Z of the deepest cut (exact) or of the generating pose (linear)
};

/// Throws std::runtime_error when a deviation is not finite: the wheel at its actual poses never reaches the point's
/// normal line (errors large enough to move the wheel's profile off it), so no ground surface exists there. The
/// message names the point; callers scan their results in a fixed order so the message does not depend on threads.
void require_reached(double deviation, int tooth, geartopo::Flank flank, double diameter_mm, double z_mm);

class FlankDeviation {
public:
  FlankDeviation(const gears::InvoluteHelicoid& flanks, const FormWheel& wheel, const WheelPath& path,
                 const GrindingProcess& process)
      : flanks_(flanks), wheel_(wheel), path_(path), process_(process) {}

  /// The deviation of the ground flank from the DESIGN at a point (plus material positive, mm): the material left
  /// along the bare involute's normal line, less the drawing's design value there (FormWheel::design(); 0 without
  /// modifications). Linear: the first-order deviation of the process from the wheel's nominal (dressed) surface,
  /// plus the profile part dressed into it, less the design.
  DeviationResult at(int tooth, geartopo::Flank flank, double roll_length_mm, double z_mm, Method method) const;

  /// The process-independent part of the linear model at a point: at(…, Method::Linear) is
  /// {linear_deviation_mm(linear_contact(…), process), linear_contact(…).pp.z_stroke_mm}.
  LinearContact linear_contact(int tooth, geartopo::Flank flank, double roll_length_mm, double z_mm) const;

  /// The exact deviation by Brent's search alone, Z to within z_tol_mm: the reference for the parabolic shortcut of
  /// at() (tests/grinding/test_exact_search.cpp) and its fallback (with kBrentTolMm).
  DeviationResult exact_by_brent(int tooth, geartopo::Flank flank, double roll_length_mm, double z_mm, double z_tol_mm) const;

  static constexpr double kBrentTolMm = 1e-4;          ///< Z tolerance of the fallback search
  static constexpr double kParabolaReachMm = 0.45;     ///< farthest vertex from Z₀ trusted (Brent's first window is ±0.5)
  static constexpr double kParabolaAgreementMm = 1e-7; ///< |depth at vertex − parabola's prediction| that is trusted
  /// Largest excess of the 3-pose vertex's depth over the minimum of the parabola through all three depths that is
  /// trusted (1e-8 µm); beyond it the 4-pose search decides (flank_deviation.cpp).
  static constexpr double kKnownCurvatureExcessMm = 1e-11;
  static constexpr double kCurvatureStepMm = 0.05; ///< h: the depths at Z₀ ± h of both searches and of the curvature

  /// Where the wheel at pose wMg first enters along P + t n (t in mm); +∞ if it misses near the flank. Newton's
  /// method from t_start_mm (a depth known to be close saves steps), to within kNewtonTolMm of the root (a proven
  /// bound when the process never changes the wheel's radius; else until a step is below 1e-12 mm).
  double entry_depth(const gears::FlankPoint& fp, const machine::Pose& wMg, const PathPoint& pp,
                     double t_start_mm = 0.0) const;
  static constexpr double kNewtonTolMm = 1e-13; ///< |entry depth − root| guaranteed at the end (1e-10 µm)

  /// A flank point with what the search around it needs: the space that grinds it and its nominal stroke Z₀. It
  /// depends on the geometry alone, not on the process: simulations of many processes on the same points compute it
  /// once (TopologyPlan, topology_plan.hpp).
  struct Target {
    int space;
    gears::FlankPoint fp;
    double z0;
    /// c = d²(entry depth)/dZ² near Z₀ (1/mm), the geometry's (the ideal process's: machine errors of µm and µrad
    /// change it by ~1e-4 relative); 0 when not known. When known, at() asks 3 poses instead of 4.
    double depth_curvature_per_mm = 0.0;
    /// The drawing's design at the point (gears/flank_modifications.hpp), mm: the whole value, and its profile part,
    /// which the wheel is dressed with (so the linear model's nominal surface already carries it).
    double design_mm = 0.0, design_profile_mm = 0.0;
  };
  Target target(int tooth, geartopo::Flank flank, double roll_length_mm, double z_mm) const;
  /// The second difference (f(Z₀ + h) + f(Z₀ − h) − 2 f(Z₀))/h² of this process's entry depth f, h =
  /// kCurvatureStepMm: on an IdealProcess, the curvature a Target stores (TopologyPlan). 0 where a depth is not
  /// finite or the difference is not positive (the target then keeps the 4-pose search).
  double depth_curvature_per_mm(const Target& t) const;
  /// at() for a target computed before (bit for bit the same result).
  DeviationResult at(const Target& t, Method method) const;
  LinearContact linear_contact(const Target& t) const;

private:
  /// The material left along the bare involute's normal (exact) or the first-order deviation from the nominal surface
  /// (linear), before the design is taken off.
  DeviationResult from_involute(const Target& t, Method method) const;
  /// Entry depth with the wheel at stroke position Z, Newton from t_start_mm.
  double depth_at(const Target& t, double z_stroke_mm, double t_start_mm) const;
  DeviationResult brent_search(const Target& t, double z_tol_mm) const;
  /// The 4-pose search given the depths at Z₀ − h, Z₀, Z₀ + h; Brent's where its vertex is not trusted.
  DeviationResult four_pose_search(const Target& t, double f_m, double f_0, double f_p) const;

  const gears::InvoluteHelicoid& flanks_;
  const FormWheel& wheel_;
  const WheelPath& path_;
  const GrindingProcess& process_;
};

} // namespace geartopo::grinding
