#include "geartopo/measurement/measured_points.hpp"

#include "geartopo/core/input_error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace geartopo::measurement {

namespace {
// A position as a message shows it: to 0.1 µm, or in 6 significant digits when absurd (1e300 mm, not 301 digits).
std::string mm_text(double v) { return std::abs(v) < 1e6 ? fmt::format("{:.4f}", v) : fmt::format("{:.6g}", v); }
} // namespace

std::vector<MeasuredPoint> measured_points(const std::vector<grinding::TopologyRow>& rows, const gears::GearGeometry& g,
                                           const std::string& source) {
  const double slack = 1e-3;
  const double d_lo = g.root_form_diameter_mm() - slack, d_hi = g.tip_diameter_mm() + slack;
  const double b = g.spec().face_width_mm;
  std::vector<MeasuredPoint> out;
  out.reserve(rows.size());
  for (const auto& r : rows) {
    if (r.diameter_mm < d_lo || r.diameter_mm > d_hi)
      throw InputError(source, r.line, 0, "diameter_mm",
                       fmt::format("{} mm is off the flank (active profile {:.4f} … {:.4f} mm)", mm_text(r.diameter_mm),
                                   g.root_form_diameter_mm(), g.tip_diameter_mm()));
    if (r.z_mm < -slack || r.z_mm > b + slack)
      throw InputError(source, r.line, 0, "z_mm", fmt::format("{} mm is off the flank (face width 0 … {} mm)", mm_text(r.z_mm), b));
    MeasuredPoint p;
    p.tooth = r.tooth;
    p.flank = r.flank;
    p.row = r.row;
    p.col = r.col;
    p.diameter_mm = std::clamp(r.diameter_mm, g.root_form_diameter_mm(), g.tip_diameter_mm());
    p.roll_length_mm = g.roll_length_at(p.diameter_mm);
    p.z_mm = std::clamp(r.z_mm, 0.0, b);
    p.deviation_um = r.deviation_um;
    p.design_um = r.design_um;
    p.line = r.line;
    out.push_back(p);
  }
  return out;
}

std::string_view to_string(MeasuredAgainst against) {
  switch (against) {
  case MeasuredAgainst::as_file: return "file";
  case MeasuredAgainst::design: return "design";
  case MeasuredAgainst::involute: return "involute";
  }
  return "file";
}

std::optional<MeasuredAgainst> parse_measured_against(std::string_view word) {
  if (word == "design") return MeasuredAgainst::design;
  if (word == "involute") return MeasuredAgainst::involute;
  return std::nullopt;
}

void refer_to_design(std::vector<MeasuredPoint>& points, const gears::FlankDesign& design) {
  for (auto& p : points) {
    const double d = design.at_um(p.flank, p.roll_length_mm, p.z_mm);
    p.deviation_um += p.design_um - d;
    p.design_um = d;
  }
}

void refer_to_design(std::vector<grinding::FlankTopology>& traces, const gears::FlankDesign& design) {
  for (auto& ft : traces)
    for (auto* trace : {&ft.profile, &ft.helix})
      for (auto& p : *trace) {
        const double d = design.at_um(ft.flank, p.roll_length_mm, p.z_mm);
        p.deviation_um += p.design_um - d;
        p.design_um = d;
      }
}

std::vector<MeasuredPoint> read_measurement(const std::string& file, const gears::GearGeometry& g) {
  return measured_points(grinding::read_topology_csv(std::filesystem::path(file), g.teeth()), g, file);
}

std::vector<MeasuredPoint> trace_points(const std::vector<grinding::FlankTopology>& traces, const gears::GearGeometry& g,
                                        const std::string& source) {
  // As topology rows without grid indices: one set of flank checks for every format.
  std::vector<grinding::TopologyRow> rows;
  for (const auto& ft : traces)
    for (const auto* trace : {&ft.profile, &ft.helix})
      for (const auto& p : *trace)
        rows.push_back({ft.tooth, ft.flank, 0, 0, p.diameter_mm, p.z_mm, p.deviation_um, p.line, p.design_um});
  return measured_points(rows, g, source);
}

std::vector<MeasuredPoint> read_traces_measurement(const std::string& file, const gears::GearGeometry& g) {
  return trace_points(grinding::read_traces_csv(std::filesystem::path(file), g.teeth()), g, file);
}

} // namespace geartopo::measurement
