#include "geartopo/report/figures.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/grinding/flank_mesh.hpp"
#include "geartopo/machine/error_component.hpp"
#include "geartopo/render/charts.hpp"
#include "geartopo/render/composite.hpp"
#include "geartopo/render/grid_view.hpp"
#include "geartopo/render/heat_map.hpp"
#include "geartopo/render/image.hpp"
#include "geartopo/render/scale.hpp"
#include "geartopo/render/surface_view.hpp"
#include "geartopo/surfaces/gear_mesh.hpp"

#include <fmt/format.h>

#include <set>

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace geartopo::report {
namespace {

namespace fs = std::filesystem;
using geartopo::Flank;

const grinding::FlankTopology* find(const std::vector<grinding::FlankTopology>& topo, int tooth, Flank f) {
  for (const auto& ft : topo)
    if (ft.tooth == tooth && ft.flank == f) return &ft;
  return nullptr;
}

std::string flank_name(int tooth, Flank f) { return fmt::format("tooth {}, {} flank", tooth, gears::to_string(f)); }

// Grid matrices (rows × cols): u = z (mm), v = roll length (mm), deviation (µm).
render::GridTopology grid_of(const grinding::FlankTopology& ft, const std::string& title) {
  const int rows = ft.grid.back().row, cols = ft.grid.back().col;
  render::GridTopology g;
  g.title = title;
  g.u.resize(rows, cols), g.v.resize(rows, cols), g.deviation.resize(rows, cols);
  for (const auto& p : ft.grid) {
    g.u(p.row - 1, p.col - 1) = p.z_mm;
    g.v(p.row - 1, p.col - 1) = p.roll_length_mm;
    g.deviation(p.row - 1, p.col - 1) = p.deviation_um;
  }
  g.u_axis = {"axial position z from the datum face", "mm", {}, {}};
  g.v_axis = {"roll length L_y", "mm", {}, {}};
  g.size = {900, 700};
  g.font_px = 19; // two panels side by side are shown about 0.75 × on the page
  return g;
}

/// Composite titles and captions: the composites are shown scaled to the page (1400 px), so their text is larger.
constexpr int kCompositeFontPx = 22;

std::pair<double, double> range_of(const std::vector<double>& v) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return {*lo, *hi};
}

std::optional<std::pair<double, double>> colour_of(const render::RenderResult& rr) {
  if (!rr.colour_range) return std::nullopt;
  return std::make_pair(rr.colour_range->min, rr.colour_range->max);
}

// The largest |deviation| of the flanks (µm), not below the colour scale's resolution (0.01 µm): an ideal machine's
// rounding noise is not a deviation to scale a figure to.
double max_abs(const std::vector<const grinding::FlankTopology*>& flanks) {
  double m = render::ColourScale{}.resolution;
  for (const auto* f : flanks)
    if (f)
      for (const auto& p : f->grid) m = std::max(m, std::abs(p.deviation_um));
  return m;
}

// One magnification for every panel (before and after alike), so that equal offsets mean equal deviations: the
// automatic one of the panel with the largest deviation (the smallest of them), so that no panel overshoots.
double common_magnification(const std::vector<const grinding::FlankTopology*>& flanks) {
  double m = 0.0;
  for (const auto* f : flanks)
    if (f) {
      const double auto_m = render::grid_magnification(grid_of(*f, ""));
      m = m == 0.0 ? auto_m : std::min(m, auto_m);
    }
  return m;
}

// A 2×2 (or n×2) composite of grid views of the focus teeth, one colour scale for all.
Figure topology_figure(const workbench::Workbench& wb, const std::vector<grinding::FlankTopology>& topo, const fs::path& dir,
                       const std::string& file, const std::string& title, const std::string& when, double scale_um,
                       double magnification) {
  render::Composite comp;
  comp.font_px = kCompositeFontPx;
  comp.title = title;
  comp.columns = 2;
  Figure fig{file, "topology", title, "", 0, 0, std::nullopt, std::nullopt};
  std::vector<double> shown;
  for (int tooth : focus_teeth(wb))
    for (Flank f : {Flank::Left, Flank::Right}) {
      const auto* ft = find(topo, tooth, f);
      if (!ft) continue;
      auto g = grid_of(*ft, fmt::format("{} — {}", flank_name(tooth, f), when));
      g.scale.mode = render::RangeMode::fixed;
      g.scale.fixed = {-scale_um, scale_um};
      g.magnification = magnification;
      g.value_every = g.deviation.size() > 30 ? 2 : 1; // a 7 × 9 grid: values at 20 of the 63 nodes, readable
      const auto panel = dir / "panels" / fmt::format("{}_t{:02d}_{}.png", fs::path(file).stem().string(), tooth, gears::to_string(f));
      const auto rr = render::render_grid_topology(g, panel);
      for (const auto& p : ft->grid) shown.push_back(p.deviation_um);
      fig.colour_range_um = colour_of(rr);
      comp.panels.push_back({panel, ""});
    }
  comp.title = fmt::format("{} — all panels magnified ×{:.0f}", title, magnification);
  const auto size = render::render_composite(comp, dir / file);
  fig.width = size.width, fig.height = size.height;
  fig.data_range_um = range_of(shown);
  fig.caption = fmt::format("The nominal {}×{} grid (black) and the ground flank (blue) with the deviation magnified, values "
                            "at the nodes in µm (at every second node of a grid with more than 30), plus material positive. Rows run from root to tip over L_α, columns from "
                            "the datum face over L_β.",
                            wb.scene.grid.rows, wb.scene.grid.cols);
  return fig;
}

const evaluation::FlankEvaluation* iso_flank(const workbench::IsoResult& iso, int tooth, Flank f) {
  const auto side = f == Flank::Right ? geartopo::Flank::Right : geartopo::Flank::Left;
  for (const auto& fe : iso.evaluation.flanks)
    if (fe.tooth == tooth && fe.side == side) return &fe;
  return nullptr;
}


// A gear-measuring-machine style chart (Klingelnberg/Gleason/Wenzel printouts): deviation across (µm), position
// along (mm); the trace, its least-squares mean line over the evaluation range, the range marks, and the class's
// tolerance box: F_T wide around the trace's extremes over the range, with the f_HT limits (the steepest mean lines
// allowed) through the mean line's middle. Left flanks are mirrored (plus material to the left) so that a pair of
// charts shows the tooth as it stands between them. The scale is chosen from the data and the tolerance.
ChartRange trace_chart(const workbench::Workbench& wb, const workbench::IsoResult& iso, const grinding::FlankTopology& ft,
                       bool profile, int shown_class, const fs::path& file) {
  const auto& rg = wb.setup.ranges();
  const auto& p = iso.parameters;
  const double a = profile ? rg.xi_eval_start_mm : rg.z_eval_start_mm, b = profile ? rg.xi_eval_end_mm : rg.z_eval_end_mm;
  const double mid = 0.5 * (a + b);
  const double sign = ft.flank == Flank::Left ? -1.0 : 1.0; // drawn x = sign · deviation
  const std::string sym = profile ? "α" : "β";
  const auto& points = profile ? ft.profile : ft.helix;

  ChartRange out;
  out.panel = file.filename().string();
  std::vector<double> must_show; // deviations (µm, not mirrored) the scale has to contain
  render::Series trace;
  trace.name = "trace";
  trace.colour = render::colours::actual;
  double in_lo = std::numeric_limits<double>::infinity(), in_hi = -in_lo;
  // The trace (simulated along the normal) in the direction the ISO values, mean line and tolerances are reported in
  // (transverse by default: × 1/cos β_b), so that trace, mean line and box share one axis. With a designed
  // modification the chart is the measuring machine's: the flank as ground (deviation + design), the design line, and
  // the mean line and tolerance box following the design (the ISO values are of the deviation from it).
  const double reported_per_normal = evaluation::reported_per_normal(iso.evaluation.conventions);
  bool designed = false;
  for (const auto& pt : points) designed = designed || pt.design_um != 0.0;
  std::vector<double> design_s, design_um; // the design at the trace's positions, reported direction
  for (const auto& pt : points) {
    const double s = profile ? pt.roll_length_mm : pt.z_mm;
    const double dev_um = reported_per_normal * pt.deviation_um, design = reported_per_normal * pt.design_um;
    trace.x.push_back(sign * (dev_um + design));
    trace.y.push_back(s);
    must_show.push_back(dev_um + design);
    design_s.push_back(s);
    design_um.push_back(design);
    if (s >= a - 1e-9 && s <= b + 1e-9) in_lo = std::min(in_lo, dev_um), in_hi = std::max(in_hi, dev_um);
  }
  out.data_um = {*std::min_element(must_show.begin(), must_show.end()), *std::max_element(must_show.begin(), must_show.end())};
  if (!(in_lo <= in_hi)) in_lo = out.data_um.first, in_hi = out.data_um.second;
  // A line of the deviation space (value_at(s), µm) drawn over [a, b] on the design: two points without a design,
  // else one per trace position inside the range, with both ends.
  const auto design_at = [&](double s) {
    if (!designed) return 0.0;
    const auto it = std::lower_bound(design_s.begin(), design_s.end(), s);
    if (it == design_s.begin()) return design_um.front();
    if (it == design_s.end()) return design_um.back();
    const size_t k = static_cast<size_t>(it - design_s.begin());
    const double t = (s - design_s[k - 1]) / (design_s[k] - design_s[k - 1]);
    return (1.0 - t) * design_um[k - 1] + t * design_um[k];
  };
  const auto on_design = [&](render::Series& series, const std::function<double(double)>& value_at) {
    std::vector<double> at = {a};
    if (designed)
      for (double s : design_s)
        if (s > a && s < b) at.push_back(s);
    at.push_back(b);
    for (double s : at) {
      series.x.push_back(sign * (value_at(s) + design_at(s)));
      series.y.push_back(s);
      must_show.push_back(value_at(s) + design_at(s));
    }
  };

  render::LineChart c;
  c.size = {520, 640};
  c.font_px = 18; // shown at about 0.85 × beside its table: about 15 px text on the page
  c.series.push_back(trace);
  if (designed) {
    render::Series line;
    line.name = "design";
    line.colour = render::colours::grey;
    line.width = 1.5;
    on_design(line, [](double) { return 0.0; });
    c.series.push_back(line);
  }
  const auto* fe = iso_flank(iso, ft.tooth, ft.flank);
  const evaluation::TraceDeviations* dev = fe ? (profile ? &fe->profile : &fe->helix) : nullptr;
  if (dev) {
    const auto mean_at = [&](double s) { return dev->mean_line_mid_um + dev->mean_line_slope_um_per_mm * (s - mid); };
    render::Series mean;
    mean.name = "mean line";
    mean.colour = render::Rgb{200, 30, 30};
    mean.dashed = true;
    on_design(mean, mean_at);
    c.series.push_back(mean);
    if (!evaluation::validity_refusal(p)) {
      const double F_T = evaluation::tolerance_um(profile ? evaluation::Quantity::ProfileTotal : evaluation::Quantity::HelixTotal, p, shown_class);
      const double fH_T = evaluation::tolerance_um(profile ? evaluation::Quantity::ProfileSlope : evaluation::Quantity::HelixSlope, p, shown_class);
      const double centre = 0.5 * (in_lo + in_hi);
      out.tolerance_um = {centre - 0.5 * F_T, centre + 0.5 * F_T};
      render::Series box;
      box.name = fmt::format("F_{}T, f_H{}T class {}", sym, sym, shown_class);
      box.colour = render::Rgb{40, 140, 60};
      box.width = 2.0;
      // Lower edge from a to b, upper edge back from b to a, closed: each edge follows the design.
      render::Series lower, upper;
      on_design(lower, [&](double) { return out.tolerance_um.first; });
      on_design(upper, [&](double) { return out.tolerance_um.second; });
      box.x = lower.x;
      box.y = lower.y;
      box.x.insert(box.x.end(), upper.x.rbegin(), upper.x.rend());
      box.y.insert(box.y.end(), upper.y.rbegin(), upper.y.rend());
      box.x.push_back(lower.x.front());
      box.y.push_back(lower.y.front());
      c.series.push_back(box);
      // f_H limits: mean lines through the middle with a rise of ±f_HT over the range.
      for (double rise : {fH_T, -fH_T}) {
        render::Series lim;
        lim.colour = box.colour;
        lim.width = 1.2;
        lim.dashed = true;
        on_design(lim, [&](double s) { return mean_at(mid) + rise * (s - mid) / (b - a); });
        c.series.push_back(lim);
      }
      must_show.push_back(out.tolerance_um.first);
      must_show.push_back(out.tolerance_um.second);
      out.min_span_um = 2.0 * F_T;
    }
  }
  // The scale of the drawn (mirrored) values; it must hold the data and the whole tolerance box.
  std::vector<double> drawn;
  for (double v : must_show) drawn.push_back(sign * v);
  const auto scale = render::covering_scale(drawn.data(), drawn.size(), out.min_span_um, 6);
  const std::string direction(evaluation::to_string(iso.evaluation.conventions.direction));
  c.x = {ft.flank == Flank::Left ? "← plus material     deviation, " + direction + " [µm]"
                                 : "deviation, " + direction + " [µm]     plus material →",
         "", scale.range.min, scale.range.max};
  for (double t = scale.range.min; t <= scale.range.max + 1e-9 * scale.step; t += scale.step) {
    c.x_ticks.push_back(t);
    c.x_tick_labels.push_back(render::tick_label(sign * t, scale.step)); // labels show the deviation, not the mirrored value
  }
  out.axis_um = ft.flank == Flank::Left ? std::pair{-scale.range.max, -scale.range.min} : std::pair{scale.range.min, scale.range.max};
  c.lines.push_back({render::Orientation::horizontal, a, render::colours::grey, 1.5, true, profile ? "L_α" : "L_β"});
  c.lines.push_back({render::Orientation::horizontal, b, render::colours::grey, 1.5, true, ""});
  c.lines.push_back({render::Orientation::vertical, 0.0, render::colours::black, 1.0, false, ""});
  c.y = {profile ? "roll length L_y" : "axial position z", "mm", {}, {}};
  c.title = fmt::format("{}, {}", profile ? "Profile" : "Helix", flank_name(ft.tooth, ft.flank));
  c.legend = render::LegendPlace::none;
  render::render_line_chart(c, file);
  return out;
}

std::vector<Figure> trace_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r, int shown_class,
                                  const fs::path& dir) {
  std::vector<Figure> out;
  for (int tooth : focus_teeth(wb)) {
    render::Composite comp;
    comp.font_px = kCompositeFontPx;
    comp.columns = 2;
    Figure fig;
    for (bool profile : {true, false})
      for (Flank f : {Flank::Left, Flank::Right}) {
        const auto* ft = find(r.before, tooth, f);
        if (!ft) continue;
        const auto panel = dir / "panels" / fmt::format("trace_t{:02d}_{}_{}.png", tooth, profile ? "profile" : "helix", gears::to_string(f));
        fig.charts.push_back(trace_chart(wb, r.iso_before, *ft, profile, shown_class, panel));
        comp.panels.push_back({panel, ""});
      }
    fig.file = fmt::format("traces_tooth{:02d}.png", tooth);
    fig.section = "traces";
    fig.tooth = tooth;
    fig.title = fmt::format("Profile and helix traces, tooth {}", tooth);
    const auto size = render::render_composite(comp, dir / fig.file);
    fig.width = size.width, fig.height = size.height;
    const std::string boxes =
        evaluation::validity_refusal(r.iso_before.parameters)
            ? std::string("no tolerance box: ISO 1328-1:2013 does not apply to this gear")
            : fmt::format("green box: the class-{0} total tolerance F_T over the evaluation range, placed around the "
                          "trace's extremes (F does not depend on an offset); green dashed: the class-{0} f_HT limits "
                          "about the mean line's middle",
                          shown_class);
    fig.caption = fmt::format(
        "Measuring-machine layout: left flanks mirrored (plus material to the left), right flanks plus material to the "
        "right. Blue: the trace over the whole active profile (mid face width) or face width (middle of L_α); red "
        "dashed: its least-squares mean line over the evaluation range (grey dashed lines); {}. Each chart has its own "
        "scale.",
        boxes);
    out.push_back(std::move(fig));
  }
  return out;
}

// Pitch in two panels on one tooth axis: the single pitch deviations f_p,i (bars) against ±f_pT, and the index
// deviations F_p,i (lines) against F_pT. They are different quantities with different tolerances: on one axis the
// ±f_pT lines read as limits of the F_p,i curves (issue 17). F_pT bounds F_p = max − min (independent of an offset),
// so it is drawn as a band of that width centred on the middle of the F_p,i values, as runout's F_rT.
Figure pitch_figure(const workbench::Workbench& wb, const workbench::IsoResult& iso, int shown_class, const fs::path& dir) {
  const int z = wb.setup.geometry().teeth();
  const bool classify = !evaluation::validity_refusal(iso.parameters);
  render::BarChart single;
  single.title = "Single pitch deviation f_p,i";
  single.size = {1400, 520};
  for (int t = 1; t <= z; ++t) single.categories.push_back(std::to_string(t));
  single.x = {"tooth i (pitch from tooth i to i + 1)", "", {}, {}};
  single.y = {"f_p,i", "µm", {}, {}};
  render::LineChart index;
  index.title = "Index (cumulative) pitch deviation F_p,i, relative to tooth 1";
  index.size = {1400, 520};
  // The bars' tooth axis: teeth 1..z at whole numbers, half a pitch of margin; every tooth labelled up to 40 teeth,
  // every k-th beyond.
  index.x = {"tooth i", "", 0.5, z + 0.5};
  index.y = {"F_p,i", "µm", {}, {}};
  const int label_step = (z + 39) / 40;
  for (int t = 1; t <= z; t += label_step) {
    index.x_ticks.push_back(t);
    index.x_tick_labels.push_back(std::to_string(t));
  }
  double lo = 1e300, hi = -1e300;
  int colour = 0;
  for (const auto* pe : {&iso.evaluation.pitch_left, &iso.evaluation.pitch_right}) {
    if (!*pe) continue;
    const std::string side(evaluation::to_string((*pe)->side));
    single.bars.push_back({side + " flanks", (*pe)->single_pitch_um, render::series_colour(colour)});
    render::Series s;
    s.name = fmt::format("{} flanks, F_p = {:.2f} µm", side, (*pe)->F_p_um);
    s.colour = render::series_colour(colour++);
    for (int t = 1; t <= z; ++t) s.x.push_back(t);
    s.y = (*pe)->index_um;
    s.marker = render::Marker::circle;
    for (double v : s.y) lo = std::min(lo, v), hi = std::max(hi, v);
    index.series.push_back(s);
  }
  if (single.bars.empty()) throw std::runtime_error("pitch figure: no pitch evaluation (not every tooth was simulated)");
  if (classify) {
    const double fpT = evaluation::tolerance_um(evaluation::Quantity::SinglePitch, iso.parameters, shown_class);
    single.ref_lines.push_back({render::Orientation::horizontal, fpT, render::colours::tolerance, 1.5, true,
                                fmt::format("±f_pT class {}", shown_class)});
    single.ref_lines.push_back({render::Orientation::horizontal, -fpT, render::colours::tolerance, 1.5, true, ""});
    const double FpT = evaluation::tolerance_um(evaluation::Quantity::CumulativePitch, iso.parameters, shown_class);
    const double mid = 0.5 * (lo + hi);
    index.bands.push_back({render::Orientation::horizontal, mid - 0.5 * FpT, mid + 0.5 * FpT, render::colours::tolerance,
                           0.22, fmt::format("F_pT class {} = {:g} µm, centred on the values", shown_class, FpT)});
  }
  single.legend = render::LegendPlace::above;
  index.legend = render::LegendPlace::above;
  const fs::path single_png = dir / "panels" / "pitch_single.png", index_png = dir / "panels" / "pitch_index.png";
  render::render_bar_chart(single, single_png);
  render::render_line_chart(index, index_png);
  render::Composite comp;
  comp.title = "Pitch over tooth number";
  comp.font_px = kCompositeFontPx;
  comp.columns = 1;
  comp.panels = {{single_png, ""}, {index_png, ""}};
  const auto size = render::render_composite(comp, dir / "pitch.png");
  return {"pitch.png", "pitch", "Single and index (cumulative) pitch deviations over tooth number",
          fmt::format("Top: single pitch deviation f_p,i of the pitch from tooth i to i+1 on the measuring circle "
                      "(transverse arc, µm){}. Bottom: index deviation F_p,i relative to tooth 1{}.",
                      classify ? fmt::format(", with the class-{} limits ±f_pT", shown_class) : "",
                      classify ? fmt::format(", with the class-{} F_pT as a band of its width centred on the values "
                                             "(F_p = max − min does not depend on an offset)",
                                             shown_class)
                               : ""),
          size.width, size.height, std::nullopt, std::nullopt};
}

// Runout: the radial position r_s of a ball in each tooth space (ISO 1328-1 F_r = max − min), with the tolerance of
// the class the trace charts use drawn as a band of width F_rT around the middle of the values (F_r, like F, does not
// depend on an offset).
std::optional<Figure> runout_figure(const workbench::IsoResult& iso, int shown_class, const fs::path& dir) {
  if (!iso.evaluation.runout) return std::nullopt;
  const auto& ro = *iso.evaluation.runout;
  render::BarChart c;
  c.title = fmt::format("Runout: radial ball position per tooth space, F_r = {:.2f} µm", ro.F_r_um);
  c.size = {1400, 600};
  c.font_px = 17;
  for (size_t s = 1; s <= ro.radial_um.size(); ++s) c.categories.push_back(std::to_string(s));
  c.x = {"tooth space s (between teeth s and s + 1)", "", {}, {}};
  c.y = {"radial position r_s, outwards", "µm", {}, {}};
  c.bars.push_back({"r_s", ro.radial_um, render::series_colour(0)});
  if (!evaluation::validity_refusal(iso.parameters)) {
    const auto [lo, hi] = std::minmax_element(ro.radial_um.begin(), ro.radial_um.end());
    const double mid = 0.5 * (*lo + *hi);
    const double T = evaluation::tolerance_um(evaluation::Quantity::Runout, iso.parameters, shown_class);
    c.bands.push_back({render::Orientation::horizontal, mid - 0.5 * T, mid + 0.5 * T, render::colours::tolerance, 0.22,
                       fmt::format("F_rT class {} = {:g} µm, centred on the values", shown_class, T)});
    c.legend = render::LegendPlace::above;
  } else {
    c.legend = render::LegendPlace::none;
  }
  render::render_bar_chart(c, dir / "runout.png");
  return Figure{"runout.png", "runout", "Runout",
                "The radial displacement of a ball of the pitch-measuring diameter in every tooth space, from the left and "
                "right flank deviations at mid face width (docs/iso1328.md, runout); F_r is their range.",
                c.size.width, c.size.height, std::nullopt, std::nullopt};
}

// The position-independent components (squareness, axis-line location: ISO 230-1, 230-7) of one quantity as bars, in
// the chain's symbols (µm or µrad).
fs::path machine_constants_panel(const workbench::Workbench& wb, machine::Quantity quantity, const fs::path& dir) {
  const machine::KinematicChain& chain = *wb.scene.machine.chain;
  const bool length = quantity == machine::Quantity::Length;
  render::BarChart c;
  c.size = {800, 420};
  c.font_px = 17;
  c.title = length ? "Constants: axis-line offsets" : "Constants: squareness and axis-line tilts";
  c.x = {"component", "", {}, {}};
  c.y = {length ? "E" : "S, E", length ? "µm" : "µrad", {}, {}};
  render::BarSeries bars{length ? "offset" : "angle", {}, render::series_colour(length ? 0 : 1)};
  for (int k = 0; k < machine::kComponentCount; ++k) {
    const auto id = machine::component_at(k);
    const machine::ComponentInfo& i = chain.info(id);
    if (i.position_dependent || i.quantity != quantity) continue;
    c.categories.emplace_back(i.symbol);
    bars.values.push_back((length ? units::kUmPerMm : units::kUradPerRad) * wb.machine.source(id).value(0.0));
  }
  c.bars.push_back(std::move(bars));
  c.legend = render::LegendPlace::none;
  const auto panel = dir / "panels" / fmt::format("machine_constants_{}.png", length ? "linear" : "angular");
  render::render_bar_chart(c, panel);
  return panel;
}

Figure machine_figure(const workbench::Workbench& wb, const fs::path& dir) {
  render::Composite comp;
  comp.font_px = kCompositeFontPx;
  const machine::KinematicChain& chain = *wb.scene.machine.chain; // its own axis letters and component symbols
  // Motion errors are drawn over each axis' stroke only when the scene gives one: ten flat panels say nothing.
  bool any_motion = false;
  for (int k = 0; k < machine::kComponentCount; ++k) {
    const auto id = machine::component_at(k);
    any_motion = any_motion || (machine::info(id).position_dependent && !wb.machine.source(id).is_zero());
  }
  // (as long as the title without the chain's name was: a longer one runs off the composite's edges)
  comp.title = any_motion ? fmt::format("{} chain: the scene's error components against axis position; its constants", chain.name())
                          : fmt::format("{} chain: the scene's constant error components (no motion errors given)", chain.name());
  comp.columns = 2;
  const auto& st = wb.machine.strokes();
  const std::pair<double, double> spans[] = {{st.x_mm.min, st.x_mm.max}, {st.y_mm.min, st.y_mm.max}, {st.z_mm.min, st.z_mm.max},
                                             {st.a_deg.min, st.a_deg.max}, {0.0, 360.0}};
  for (int ax = 0; any_motion && ax < machine::kAxisCount; ++ax) {
    const auto axis = machine::kAxes[static_cast<size_t>(ax)];
    const bool rotary = chain.is_rotary(axis);
    const std::string name(chain.axis_name(axis));
    for (int kind = 0; kind < 2; ++kind) { // 0: δ (µm), 1: ε (µrad)
      render::LineChart c;
      c.size = {800, 420};
      c.font_px = 17;
      c.title = fmt::format("{} axis: {} errors", name, kind == 0 ? "linear" : "angular");
      c.x = {fmt::format("{} position", name), rotary ? "°" : "mm", {}, {}};
      c.y = {kind == 0 ? "δ" : "ε", kind == 0 ? "µm" : "µrad", {}, {}};
      for (int k = 0; k < 3; ++k) {
        const auto id = machine::motion_component(axis, 3 * kind + k);
        render::Series s;
        s.name = std::string(chain.info(id).symbol);
        for (int i = 0; i <= 100; ++i) {
          const double pos = spans[ax].first + (spans[ax].second - spans[ax].first) * i / 100.0;
          s.x.push_back(pos);
          s.y.push_back((kind == 0 ? units::kUmPerMm : units::kUradPerRad) * wb.machine.source(id).value(rotary ? units::rad_from_deg(pos) : pos));
        }
        c.series.push_back(s);
      }
      c.legend = render::LegendPlace::above; // inside, the legend covered the curves' ends
      const auto panel = dir / "panels" / fmt::format("machine_{}_{}.png", name, kind == 0 ? "linear" : "angular");
      render::render_line_chart(c, panel);
      comp.panels.push_back({panel, ""});
    }
  }
  for (const auto q : {machine::Quantity::Length, machine::Quantity::Angle})
    comp.panels.push_back({machine_constants_panel(wb, q, dir), ""});
  const auto size = render::render_composite(comp, dir / "machine_errors.png");
  return {"machine_errors.png", "machine", comp.title,
          fmt::format("{}The position-independent components{}: squareness S and the rotary axis lines' location E "
                      "(ISO 230-1, 230-7; docs/error-components.md for signs).",
                      any_motion ? "The six motion errors of each axis over its stroke, as the scene's tables, "
                                   "polynomials or constants give them. "
                                 : "The scene gives no motion error (every δ and ε is zero over every stroke). ",
                      any_motion ? " (bottom)" : ""),
          size.width, size.height, std::nullopt, std::nullopt};
}

Figure alignment_figure(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir) {
  render::LineChart c;
  c.title = "Middle tooth-alignment curve: before (solid) and the nominal model corrected by itself (dashed, ≈ 0)";
  c.size = {1200, 700};
  c.x = {"axial position z from the datum face", "mm", {}, {}};
  c.y = {"deviation", "µm", {}, {}};
  size_t colour = 0;
  for (int tooth : focus_teeth(wb))
    for (Flank f : {Flank::Left, Flank::Right}) {
      const auto* b = find(r.before, tooth, f);
      const auto* a = find(r.after, tooth, f);
      if (!b || !a) continue;
      const int mid = (b->grid.back().row + 1) / 2;
      render::Series sb, sa;
      sb.name = fmt::format("tooth {} {}", tooth, gears::to_string(f)); // dashed "after" twin: same colour, no entry
      for (const auto* src : {b, a})
        for (const auto& p : src->grid)
          if (p.row == mid) (src == b ? sb : sa).x.push_back(p.z_mm), (src == b ? sb : sa).y.push_back(p.deviation_um);
      sb.colour = sa.colour = render::series_colour(colour++);
      sb.marker = sa.marker = render::Marker::circle;
      sa.dashed = true;
      c.series.push_back(sb);
      c.series.push_back(sa);
    }
  c.lines.push_back({render::Orientation::horizontal, 0.0, render::colours::black, 1.0, false, ""});
  c.legend = render::LegendPlace::above;
  render::render_line_chart(c, dir / "alignment_curve.png");
  return {"alignment_curve.png", "compensation", c.title,
          fmt::format("Tooth-alignment curve {} of {} (mid profile) at the {} profile curves over the face width, before (solid) and, "
                      "dashed, the nominal after-state: the model corrected by itself with the flank method, ≈ 0 by "
                      "construction and not a result (the predicted after-state is the prediction figure); one colour per flank.",
                      (wb.scene.grid.rows + 1) / 2, wb.scene.grid.rows, wb.scene.grid.cols),
          c.size.width, c.size.height, std::nullopt, std::nullopt};
}

std::vector<Figure> measurement_figures(const pipeline::MeasurementResult& m, const fs::path& dir) {
  std::vector<Figure> out;
  // Heat maps need the grid layout of a topology file.
  // Heat maps place each row and column by its points (a missing node is an empty cell), so every row 1..rows and
  // column 1..cols of each flank needs at least one point; anything else (point clouds, a grid with a whole row or
  // column missing) gets no heat maps — the diagnosis charts below still show.
  bool gridded = true;
  for (const auto& p : m.points) gridded = gridded && p.row > 0 && p.col > 0;
  for (size_t f = 0; gridded && f < m.before.flanks.size(); ++f) {
    std::set<int> rows, cols;
    for (size_t i : m.before.flank_point_index[f]) rows.insert(m.points[i].row), cols.insert(m.points[i].col);
    gridded = static_cast<int>(rows.size()) == *rows.rbegin() && static_cast<int>(cols.size()) == *cols.rbegin();
  }
  double vmax = 1e-3, rmax = 1e-3;
  for (size_t i = 0; i < m.points.size(); ++i)
    vmax = std::max({vmax, std::abs(m.points[i].deviation_um), std::abs(m.before.model_um[i])}),
    rmax = std::max(rmax, std::abs(m.before.residual_um[i]));
  if (gridded) {
    render::Composite comp;
    comp.font_px = kCompositeFontPx;
    comp.title = "Measured vs model, and the residual with the regions where the model fails";
    comp.columns = 3;
    std::vector<double> shown;
    std::optional<std::pair<double, double>> used;
    for (size_t f = 0; f < m.before.flanks.size(); ++f) {
      const auto& idx = m.before.flank_point_index[f];
      int rows = 0, cols = 0;
      for (size_t i : idx) rows = std::max(rows, m.points[i].row), cols = std::max(cols, m.points[i].col);
      Eigen::MatrixXd meas = Eigen::MatrixXd::Constant(rows, cols, std::nan("")), model = meas, resid = meas;
      Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> marked = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(rows, cols, false);
      std::vector<double> xc(static_cast<size_t>(cols)), yc(static_cast<size_t>(rows));
      for (size_t i : idx) {
        const auto& p = m.points[i];
        meas(p.row - 1, p.col - 1) = p.deviation_um;
        model(p.row - 1, p.col - 1) = m.before.model_um[i];
        resid(p.row - 1, p.col - 1) = m.before.residual_um[i];
        marked(p.row - 1, p.col - 1) = std::abs(m.before.residual_um[i]) > 3.0 * m.before.noise_um;
        xc[static_cast<size_t>(p.col - 1)] = p.z_mm;
        yc[static_cast<size_t>(p.row - 1)] = p.roll_length_mm;
        shown.push_back(m.before.residual_um[i]);
      }
      const std::string name = flank_name(m.before.flanks[f].tooth, m.before.flanks[f].side == geartopo::Flank::Right ? Flank::Right : Flank::Left);
      const std::pair<const char*, const Eigen::MatrixXd*> maps[] = {{"measured", &meas}, {"model", &model}, {"residual", &resid}};
      for (const auto& [what, mat] : maps) {
        render::HeatMap h;
        h.title = fmt::format("{}: {}", name, what);
        h.values = *mat;
        h.x_centres = xc;
        h.y_centres = yc;
        h.x = {"z", "mm", {}, {}};
        h.y = {"roll length L_y", "mm", {}, {}};
        h.size = {700, 520};
        h.font_px = 18;
        h.scale.mode = render::RangeMode::fixed;
        const double lim = std::string(what) == "residual" ? rmax : vmax;
        h.scale.fixed = {-lim, lim};
        if (std::string(what) == "residual") {
          h.marked = marked;
          h.marked_label = "|residual| > 3σ";
        }
        const auto panel = dir / "panels" / fmt::format("measured_f{}_{}.png", f, what);
        const auto rr = render::render_heat_map(h, panel);
        if (std::string(what) == "residual") used = colour_of(rr);
        comp.panels.push_back({panel, ""});
      }
    }
    const auto size = render::render_composite(comp, dir / "measured_vs_model.png");
    out.push_back({"measured_vs_model.png", "measurement", comp.title,
                   fmt::format("Each measured flank: measured deviation, the model's prediction at the same points, and the "
                               "residual (measured − model, µm); outlined cells exceed 3σ of the noise ({:.2f} µm).",
                               m.before.noise_um),
                   size.width, size.height, range_of(shown), used});
  }

  // Diagnosis: explained fraction per candidate, and the residual RMS as the found effects are added.
  const auto& d = m.diagnosis;
  if (!d.ranked.empty()) {
    render::BarChart c;
    c.title = "Candidate effects: share of the residual each explains (ranked by ΔBIC)";
    c.size = {1300, 600};
    c.font_px = 18; // one column, shown at about its own size: labels of seven candidates fit side by side
    std::vector<double> explained;
    for (const auto& cand : d.ranked) {
      c.categories.push_back(cand.name());
      explained.push_back(100.0 * cand.explained_fraction);
    }
    c.bars.push_back({"explained share of the residual", explained, std::nullopt});
    c.x = {"effect", "", {}, {}};
    c.y = {"explained", "%", 0.0, 100.0};
    c.legend = render::LegendPlace::none;
    for (size_t i = 0; i < d.ranked.size(); ++i)
      c.annotations.push_back({static_cast<double>(i + 1), std::max(5.0, explained[i]) + 4.0, // categories sit at 1 … n
                               fmt::format("ΔBIC {:.0f}{}", d.ranked[i].delta_bic, d.ranked[i].significant ? "" : " (n.s.)"),
                               render::colours::text, render::HAlign::centre});
    render::render_bar_chart(c, dir / "panels" / "diagnosis_candidates.png");

    render::LineChart l;
    l.title = "Residual RMS as the found effects are added";
    l.size = {1300, 480};
    l.font_px = 18;
    render::Series s;
    s.name = "residual RMS";
    s.marker = render::Marker::circle;
    s.x = {0.0};
    s.y = {d.rms_before_um};
    if (d.chosen) {
      s.x.push_back(1.0);
      s.y.push_back(d.chosen->rms_after_um);
    }
    l.series.push_back(s);
    l.lines.push_back({render::Orientation::horizontal, d.noise_um, render::colours::grey, 1.5, true, "noise σ"});
    l.lines.push_back({render::Orientation::horizontal, 1.5 * d.noise_um, render::colours::tolerance, 1.5, true, "1.5 σ"});
    l.x = {"step", "", -0.3, std::max(1.3, static_cast<double>(s.x.size()) - 0.7)};
    for (size_t k = 0; k < s.x.size(); ++k) { // the steps are discrete: one tick each, named
      l.x_ticks.push_back(static_cast<double>(k));
      l.x_tick_labels.push_back(k == 0 ? "0: scene model" : fmt::format("{}: + {}", k, d.chosen->name()));
    }
    l.y = {"RMS", "µm", 0.0, 1.2 * std::max(d.rms_before_um, 1.6 * d.noise_um)};
    render::render_line_chart(l, dir / "panels" / "diagnosis_rms.png");

    render::Composite comp;
    comp.font_px = kCompositeFontPx;
    comp.title = "Diagnosis: which physical effect is missing";
    comp.columns = 1;
    comp.panels = {{dir / "panels" / "diagnosis_candidates.png", ""}, {dir / "panels" / "diagnosis_rms.png", ""}};
    const auto size = render::render_composite(comp, dir / "diagnosis.png");
    // The verdict itself stands once, under the candidate table on the page; the caption says what is drawn.
    out.push_back({"diagnosis.png", "measurement", comp.title,
                   "Top: the share of the model-vs-measurement residual each candidate effect explains when fitted, with "
                   "its ΔBIC (negative: the effect is worth its parameters; n.s. = not significant). Bottom: the residual "
                   "RMS of the scene model and after adding the chosen effect, against the noise σ.",
                   size.width, size.height, std::nullopt, std::nullopt});
  }
  return out;
}

/// How far the coloured flanks stand off the grey gear in the 3D view (mm). The coloured mesh has only the grid's
/// nodes: its flat facets lie inside the convex flank by up to the sagitta s²/(8ρ) of a row spacing s over the
/// involute's curvature radius ρ (= roll length, least at the root end), plus the same across a column spacing over the
/// helix's curvature (≈ sin²β / r at the reference radius). Default gear: 10.5²/(8 · 83) + 17²·0.25/(8 · 283) ≈
/// 0.2 mm. The lift is 1.5 × that (at least 0.05 mm), under a pixel at the figure's scale.
double flank_lift_mm(const grinding::FlankTopology& ft, const gears::GearGeometry& g) {
  const int rows = ft.grid.back().row, cols = ft.grid.back().col;
  double xi_lo = std::numeric_limits<double>::infinity(), xi_hi = -xi_lo, z_lo = xi_lo, z_hi = -xi_lo;
  for (const auto& p : ft.grid)
    xi_lo = std::min(xi_lo, p.roll_length_mm), xi_hi = std::max(xi_hi, p.roll_length_mm), z_lo = std::min(z_lo, p.z_mm),
    z_hi = std::max(z_hi, p.z_mm);
  const double s_xi = (xi_hi - xi_lo) / std::max(rows - 1, 1), s_z = (z_hi - z_lo) / std::max(cols - 1, 1);
  const double sin_beta = std::sin(g.spec().helix_angle_rad);
  const double sag = s_xi * s_xi / (8.0 * std::max(xi_lo, 1.0)) +
                     s_z * s_z * sin_beta * sin_beta / (8.0 * 0.5 * g.reference_diameter_mm());
  return std::max(0.05, 1.5 * sag);
}

Figure gear_figure(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir) {
  render::SurfaceView v;
  v.title = "The ground gear, flanks coloured by deviation (before compensation)";
  v.size = {1200, 1000};
  surfaces::GearMeshOptions mo;
  mo.flank_points = 16, mo.slices = 25; // grey facets within a few µm of the true flank, under the lifted colour
  const auto gm = surfaces::gear_mesh(wb.setup.geometry(), mo);
  v.meshes.push_back({gm.vertices, gm.faces, Eigen::VectorXd(), render::colours::light_grey, 1.0, false});
  std::vector<double> shown;
  Eigen::Vector3d tooth1_sum = Eigen::Vector3d::Zero();
  double tooth1_count = 0.0, datum_z = std::numeric_limits<double>::infinity();
  for (const auto& ft : r.before) {
    const auto fm = grinding::flank_mesh(wb.setup.flanks(), ft);
    if (ft.tooth == 1) tooth1_sum += fm.vertices.rowwise().sum(), tooth1_count += static_cast<double>(fm.vertices.cols());
    datum_z = std::min(datum_z, fm.vertices.row(2).minCoeff());
    // Lift the coloured flank off the grey gear along its outward normal (flank_mesh orients its faces out of the
    // material), so that the grey facets, chords of the curved flank, cannot show through it. A radial lift does not
    // separate them near the root, where the flank runs almost radially (grey streaks on one flank side).
    Eigen::Matrix3Xd normals = Eigen::Matrix3Xd::Zero(3, fm.vertices.cols()); // 3 × V, area-weighted
    for (Eigen::Index f = 0; f < fm.faces.cols(); ++f) {
      const Eigen::Vector3d a = fm.vertices.col(fm.faces(0, f)), b = fm.vertices.col(fm.faces(1, f)), c = fm.vertices.col(fm.faces(2, f));
      const Eigen::Vector3d n = (b - a).cross(c - a);
      for (int k = 0; k < 3; ++k) normals.col(fm.faces(k, f)) += n;
    }
    const double lift = flank_lift_mm(ft, wb.setup.geometry());
    Eigen::Matrix3Xd verts = fm.vertices;
    for (Eigen::Index i = 0; i < verts.cols(); ++i)
      if (normals.col(i).norm() > 0.0) verts.col(i) += lift * normals.col(i).normalized();
    v.meshes.push_back({verts, fm.faces, fm.vertex_values, render::colours::light_grey, 1.0, false});
    for (Eigen::Index i = 0; i < fm.vertex_values.size(); ++i) shown.push_back(fm.vertex_values(i));
  }
  if (tooth1_count > 0) { // mark tooth 1 over its tip, on the datum face the view looks at
    Eigen::Vector3d at = tooth1_sum / tooth1_count;
    Eigen::Vector2d radial(at.x(), at.y());
    radial *= 0.5 * wb.setup.geometry().tip_diameter_mm() / std::max(radial.norm(), 1e-9);
    v.labels.push_back({Eigen::Vector3d(radial.x(), radial.y(), datum_z), "tooth 1"});
  }
  v.view_direction = Eigen::Vector3d(-0.35, -0.25, 1.0); // from the datum face side, a little oblique
  v.view_up = Eigen::Vector3d(0.0, 1.0, 0.0);
  v.caption = fmt::format("seen from the datum face; colour = normal deviation of the {} grid, µm, plus material positive",
                          grid_label(r));
  const auto rr = render::render_surface_view(v, dir / "gear_3d.png");
  return {"gear_3d.png", "gear", v.title, v.caption, v.size.width, v.size.height, range_of(shown), colour_of(rr)};
}

} // namespace

int shown_tolerance_class(const workbench::Workbench& wb, const pipeline::PipelineResult& r) {
  if (wb.scene.report.tolerance_class) return *wb.scene.report.tolerance_class;
  const auto& achieved = r.iso_before.evaluation.classification.overall;
  return achieved ? std::clamp(*achieved, evaluation::kFinestClass, evaluation::kCoarsestClass) : 5;
}

std::vector<int> focus_teeth(const workbench::Workbench& wb) {
  if (!wb.scene.grid.teeth.empty()) return wb.scene.grid.teeth;
  const int z = wb.setup.geometry().teeth();
  return {1, z / 2 + 1};
}

namespace {

/// The scale and magnification of both topology figures: from the focus teeth before compensation.
std::pair<double, double> topology_scale(const workbench::Workbench& wb, const pipeline::PipelineResult& r) {
  std::vector<const grinding::FlankTopology*> focus;
  for (int t : focus_teeth(wb))
    for (Flank f : {Flank::Left, Flank::Right}) focus.push_back(find(r.before, t, f));
  return {max_abs(focus), common_magnification(focus)};
}

} // namespace

std::vector<Figure> render_before_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir) {
  output::create_folders_for(dir / "panels"); // in the staging folder while an output folder is open
  // Each PNG is encoded on another thread while the next figure renders (render/image.hpp); all written on return.
  render::BackgroundPngWrites png_writes;
  std::vector<Figure> figs;
  const auto [scale, magnification] = topology_scale(wb, r);
  figs.push_back(topology_figure(wb, r.before, dir, "topology_before.png", "Flank topology before compensation", "before", scale,
                                 magnification));
  for (auto& f : trace_figures(wb, r, shown_tolerance_class(wb, r), dir)) figs.push_back(std::move(f));
  // Pitch needs every tooth of a side (run --teeth 1,18 simulates two): no figure then, the page says why (notes).
  if (r.iso_before.evaluation.pitch_left || r.iso_before.evaluation.pitch_right)
    figs.push_back(pitch_figure(wb, r.iso_before, shown_tolerance_class(wb, r), dir));
  if (auto ro = runout_figure(r.iso_before, shown_tolerance_class(wb, r), dir)) figs.push_back(std::move(*ro));
  figs.push_back(machine_figure(wb, dir));
  figs.push_back(gear_figure(wb, r, dir));
  png_writes.finish();
  return figs;
}

std::vector<Figure> render_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir,
                                   std::vector<Figure> before) {
  if (before.empty()) before = render_before_figures(wb, r, dir);
  output::create_folders_for(dir / "panels"); // in the staging folder while an output folder is open
  render::BackgroundPngWrites png_writes;
  // The page's order: the figures before compensation, then these, and the 3D gear (the last before) last.
  std::vector<Figure> figs(before.begin(), before.end() - 1);
  const auto [scale, magnification] = topology_scale(wb, r);
  Figure after = topology_figure(wb, r.after, dir, "topology_after.png",
                                 "Nominal (the model corrected by itself, ≈ 0 by construction): not a result", "nominal after",
                                 scale, magnification);
  after.section = "compensation";
  after.shared_scale = true;
  figs.push_back(after);
  figs.push_back(alignment_figure(wb, r, dir));
  if (r.prediction) figs.push_back(prediction_figure(*r.prediction, dir)); // prediction_report.cpp
  if (r.measurement)
    for (auto& f : measurement_figures(*r.measurement, dir)) figs.push_back(std::move(f));
  figs.push_back(before.back());
  png_writes.finish();
  return figs;
}

} // namespace geartopo::report
