#include "geartopo/surfaces/gear_mesh.hpp"

#include "geartopo/gears/involute.hpp"
#include "geartopo/gears/involute_helicoid.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace geartopo::surfaces {
namespace {

struct Polar {
  double r, phi;
};

void check(const GearMeshOptions& o) {
  if (o.flank_points < 2 || o.tip_points < 2 || o.fillet_points < 2 || o.root_points < 2 || o.slices < 2)
    throw std::invalid_argument("gear_mesh: every point count must be >= 2");
}

// One transverse section at z = 0, all teeth, in increasing polar angle (counter-clockwise about +z), so that a
// fan from the axis triangulates the end faces.
std::vector<Polar> section(const gears::GearGeometry& g, const GearMeshOptions& o) {
  const gears::InvoluteHelicoid flanks(g);
  const int z = g.teeth();
  const double pitch = 2.0 * std::numbers::pi / z;
  const double ra = 0.5 * g.tip_diameter_mm(), rf = 0.5 * g.root_diameter_mm(), rF = 0.5 * g.root_form_diameter_mm();
  const double xi_form = g.roll_length_at(g.root_form_diameter_mm());
  const double xi_tip = g.roll_length_at(g.tip_diameter_mm());
  // Half tooth angle at the form circle, and a fillet that ends 20 % of the space width into the space.
  const double psi_form = g.base_half_angle() - gears::involute(g.transverse_pressure_angle_at(2.0 * rF));
  const double fillet_turn = 0.2 * (pitch - 2.0 * psi_form);

  auto flank_polar = [&](int tooth, geartopo::Flank f, double xi) {
    const Eigen::Vector3d p = flanks.at(tooth, f, xi, 0.0).p;
    return Polar{std::hypot(p.x(), p.y()), std::atan2(p.y(), p.x())};
  };
  auto fillet = [&](double phi_form, double outward, double t) { // t = 0 at the form circle, 1 at the root circle
    const double q = 0.5 * std::numbers::pi * t;
    return Polar{rF - (rF - rf) * std::sin(q), phi_form + outward * fillet_turn * (1.0 - std::cos(q))};
  };

  std::vector<Polar> pts;
  pts.reserve(static_cast<size_t>(section_point_count(g, o)));
  for (int tooth = 1; tooth <= z; ++tooth) {
    const double centre = pitch * (tooth - 1);
    const double phi_lf = centre - psi_form, phi_rf = centre + psi_form;
    for (int i = o.fillet_points - 1; i >= 1; --i) pts.push_back(fillet(phi_lf, -1.0, double(i) / (o.fillet_points - 1)));
    for (int i = 0; i < o.flank_points; ++i)
      pts.push_back(flank_polar(tooth, geartopo::Flank::Left, xi_form + (xi_tip - xi_form) * i / (o.flank_points - 1)));
    const double phi_la = pts.back().phi;
    const Polar right_tip = flank_polar(tooth, geartopo::Flank::Right, xi_tip);
    for (int i = 1; i < o.tip_points - 1; ++i)
      pts.push_back({ra, phi_la + (right_tip.phi - phi_la) * i / (o.tip_points - 1)});
    for (int i = o.flank_points - 1; i >= 0; --i)
      pts.push_back(flank_polar(tooth, geartopo::Flank::Right, xi_form + (xi_tip - xi_form) * i / (o.flank_points - 1)));
    for (int i = 1; i < o.fillet_points; ++i) pts.push_back(fillet(phi_rf, +1.0, double(i) / (o.fillet_points - 1)));
    const double root_from = phi_rf + fillet_turn, root_to = centre + pitch - psi_form - fillet_turn;
    for (int i = 1; i < o.root_points - 1; ++i)
      pts.push_back({rf, root_from + (root_to - root_from) * i / (o.root_points - 1)});
  }
  return pts;
}

} // namespace

int section_point_count(const gears::GearGeometry& g, const GearMeshOptions& o) {
  return g.teeth() * (2 * (o.fillet_points - 1) + 2 * o.flank_points + (o.tip_points - 2) + (o.root_points - 2));
}

TriangleMesh gear_mesh(const gears::GearGeometry& g, const GearMeshOptions& o) {
  check(o);
  const std::vector<Polar> sec = section(g, o);
  const int n = static_cast<int>(sec.size());
  const int slices = o.slices;
  const double b = g.spec().face_width_mm;
  const double k = g.twist_rad_per_mm();

  TriangleMesh mesh;
  mesh.vertices.resize(3, n * slices + 2);
  for (int s = 0; s < slices; ++s) {
    const double z = b * s / (slices - 1);
    for (int i = 0; i < n; ++i) {
      const double phi = sec[i].phi + k * z; // the helicoid: the z = 0 section turned by (2 tan β / d)·z
      mesh.vertices.col(s * n + i) << sec[i].r * std::cos(phi), sec[i].r * std::sin(phi), z;
    }
  }
  const int c0 = n * slices, c1 = c0 + 1; // centres of the datum face and of the far face
  mesh.vertices.col(c0) << 0.0, 0.0, 0.0;
  mesh.vertices.col(c1) << 0.0, 0.0, b;

  mesh.faces.resize(3, 2 * n * (slices - 1) + 2 * n);
  int f = 0;
  for (int s = 0; s + 1 < slices; ++s) {
    for (int i = 0; i < n; ++i) {
      const int i1 = (i + 1) % n;
      const int a = s * n + i, bb = s * n + i1, c = (s + 1) * n + i1, d = (s + 1) * n + i;
      mesh.faces.col(f++) << a, bb, c; // (e_θ) × (e_θ + e_z) points along +e_r: outwards
      mesh.faces.col(f++) << a, c, d;
    }
  }
  const int last = (slices - 1) * n;
  for (int i = 0; i < n; ++i) {
    const int i1 = (i + 1) % n;
    mesh.faces.col(f++) << c0, i1, i;               // datum face, normal −z
    mesh.faces.col(f++) << c1, last + i, last + i1; // far face, normal +z
  }
  return mesh;
}

} // namespace geartopo::surfaces
