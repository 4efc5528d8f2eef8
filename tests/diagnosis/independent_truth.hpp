// Shared by the diagnosis tests whose truth is computed WITHOUT the code under test (test_hidden_effects_independent,
// test_beyond_library): the default scene, measured points on a few teeth with the contact (nominal flank point and
// generating pose of the wheel path) of every point, built once per layout. What they share with the code under test
// and why that is fair is said in test_hidden_effects_independent.cpp. Units: µm, mm, s, rad.
#pragma once

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
/// contact of every point. Built once per layout.
struct Layout {
  std::vector<measurement::MeasuredPoint> points;
  std::vector<Contact> contacts;
};

inline Layout make_layout(const std::vector<int>& teeth, int rows, int cols) {
  const auto& s = bench().setup;
  diagnosis::SynthOptions o;
  o.teeth = teeth;
  o.rows = rows;
  o.cols = cols;
  o.noise_um = 0.0;
  Layout l;
  l.points = measurement::measured_points(diagnosis::synthesize(s, bench().process(), o), s.geometry(), "independent");
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
