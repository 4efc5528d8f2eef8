// Shared by the diagnosis tests whose truth is computed WITHOUT the code under test (test_hidden_effects_independent,
// test_beyond_library): the default scene, measured points on a few teeth with the contact (nominal flank point and
// generating pose of the wheel path) of every point, built once per layout. What they share with the code under test
// and why that is fair is said in test_hidden_effects_independent.cpp. Units: µm, mm, s, rad.
#pragma once

#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace independent_truth {

using namespace geartopo;

inline const std::string kSceneFile = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

inline const workbench::Workbench& bench() {
  static const workbench::Workbench b(kSceneFile);
  return b;
}

/// Where and when a measured point was ground: its nominal flank point and the generating pose of the path.
struct Contact {
  gears::FlankPoint fp;
  grinding::PathPoint pp;
  double strokes_before = 0.0; ///< strokes completed before this point's stroke, plus the progress along it (0 … 1)
  double profile_fraction = 0.0; ///< 0 at the smallest measured roll length (root end), 1 at the largest (tip end)
  Flank flank = Flank::Left;     ///< the measured point's flank
};

/// A noise-free measurement of the scene as modelled (the simulator's exact deviation) on the given teeth, with the
/// contact of every point. Built once per layout, for the default scene unless another workbench is given.
struct Layout {
  std::vector<measurement::MeasuredPoint> points;
  std::vector<Contact> contacts;
};

/// The contacts of l.points (each point's nominal flank point and generating pose), and each one's profile fraction.
inline void add_contacts(Layout& l, const workbench::Workbench& b = bench()) {
  const auto& s = b.setup;
  const grinding::IdealProcess ideal;
  const grinding::FlankDeviation generating(s.flanks(), s.wheel(), s.path(), ideal);
  for (const auto& p : l.points) {
    Contact c;
    c.fp = s.flanks().at(p.tooth, p.flank, p.roll_length_mm, p.z_mm);
    c.flank = p.flank;
    const int space = grinding::space_of(p.tooth, p.flank, s.geometry().teeth());
    const double z0 = generating.at(p.tooth, p.flank, p.roll_length_mm, p.z_mm, grinding::Method::Linear).z_stroke_mm;
    c.pp = s.path().point(space, z0);
    c.strokes_before = s.path().stroke_index(space) + std::clamp(s.path().stroke_progress(space, z0), 0.0, 1.0);
    l.contacts.push_back(c);
  }
  double lo = 1e300, hi = -1e300;
  for (const auto& p : l.points) lo = std::min(lo, p.roll_length_mm), hi = std::max(hi, p.roll_length_mm);
  for (size_t i = 0; i < l.points.size(); ++i) l.contacts[i].profile_fraction = (l.points[i].roll_length_mm - lo) / (hi - lo);
}

inline Layout make_layout(const std::vector<int>& teeth, int rows, int cols, const workbench::Workbench& b = bench()) {
  const auto& s = b.setup;
  diagnosis::SynthOptions o;
  o.teeth = teeth;
  o.rows = rows;
  o.cols = cols;
  o.noise_um = 0.0;
  Layout l;
  l.points = measurement::measured_points(diagnosis::synthesize(s, b.process(), o), s.geometry(), "independent");
  add_contacts(l, b);
  return l;
}

/// Traces as a gear measuring machine takes them, on both flanks of each tooth: a profile trace of `points` roll
/// lengths evenly over the ISO profile evaluation range at each face-width position z (mm), and a helix trace of
/// `points` positions evenly over the helix evaluation range at each diameter d (mm); noise-free, the scene as
/// modelled (the simulator's exact deviation, as make_layout's), with their contacts.
inline Layout trace_layout(const std::vector<int>& teeth, const std::vector<double>& profile_z_mm,
                           const std::vector<double>& helix_d_mm, int points) {
  const auto& s = bench().setup;
  const auto& g = s.geometry();
  const auto& r = s.ranges();
  const auto at = [&](double a, double b, int k) { return a + (b - a) * k / (points - 1); };
  Layout l;
  const auto add = [&](int tooth, Flank flank, double roll, double z) {
    measurement::MeasuredPoint p;
    p.tooth = tooth, p.flank = flank, p.roll_length_mm = roll, p.z_mm = z, p.diameter_mm = g.diameter_at_roll_length(roll);
    l.points.push_back(p);
  };
  for (int tooth : teeth)
    for (Flank flank : {Flank::Left, Flank::Right}) {
      for (double z : profile_z_mm)
        for (int k = 0; k < points; ++k) add(tooth, flank, at(r.xi_eval_start_mm, r.xi_eval_end_mm, k), z);
      for (double d : helix_d_mm)
        for (int k = 0; k < points; ++k) add(tooth, flank, g.roll_length_at(d), at(r.z_eval_start_mm, r.z_eval_end_mm, k));
    }
  const auto model = diagnosis::predict(s, bench().process(), l.points, grinding::Method::Exact);
  for (size_t i = 0; i < l.points.size(); ++i) l.points[i].deviation_um = model[i];
  add_contacts(l);
  return l;
}

inline const Layout& two_teeth() { // teeth 1 and 18 (half a turn apart), 7 × 9 grid per flank, both flanks: 252 points
  static const Layout l = make_layout({1, 18}, 7, 9);
  return l;
}

inline const Layout& one_flank() { // tooth 1, its left flank only, 7 × 9 grid: 63 points
  static const Layout l = [] {
    const Layout both = make_layout({1}, 7, 9);
    Layout left;
    for (size_t i = 0; i < both.points.size(); ++i)
      if (both.points[i].flank == Flank::Left) left.points.push_back(both.points[i]), left.contacts.push_back(both.contacts[i]);
    return left;
  }();
  return l;
}

/// Normal deviation (µm, plus material positive) of the wheel moved by axis offsets δq at the contact.
inline double axis_offset_um(const Contact& c, const machine::AxisPose& dq) {
  machine::AxisPose q = c.pp.q;
  q.x += dq.x, q.y += dq.y, q.z += dq.z, q.a += dq.a, q.c += dq.c;
  const Eigen::Vector3d moved = machine::ideal_wMg(q) * (machine::ideal_wMg(c.pp.q).inverse() * c.fp.p);
  return 1e3 * (moved - c.fp.p).dot(c.fp.n);
}


} // namespace independent_truth
