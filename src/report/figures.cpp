#include "geartopo/report/figures.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/grinding/flank_mesh.hpp"
#include "geartopo/machine/error_component.hpp"
#include "geartopo/render/charts.hpp"
#include "geartopo/render/composite.hpp"
#include "geartopo/render/grid_view.hpp"
#include "geartopo/render/heat_map.hpp"
#include "geartopo/render/surface_view.hpp"
#include "geartopo/surfaces/gear_mesh.hpp"

#include <fmt/format.h>

#include <set>

#include <algorithm>
#include <cmath>
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
  g.v_axis = {"roll length ξ", "mm", {}, {}};
  g.size = {900, 700};
  return g;
}

std::pair<double, double> range_of(const std::vector<double>& v) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return {*lo, *hi};
}

std::optional<std::pair<double, double>> colour_of(const render::RenderResult& rr) {
  if (!rr.colour_range) return std::nullopt;
  return std::make_pair(rr.colour_range->min, rr.colour_range->max);
}

double max_abs(const std::vector<const grinding::FlankTopology*>& flanks) {
  double m = 1e-3;
  for (const auto* f : flanks)
    if (f)
      for (const auto& p : f->grid) m = std::max(m, std::abs(p.deviation_um));
  return m;
}

// A 2×2 (or n×2) composite of grid views of the focus teeth, one colour scale for all.
Figure topology_figure(const workbench::Workbench& wb, const std::vector<grinding::FlankTopology>& topo, const fs::path& dir,
                       const std::string& file, const std::string& title, const std::string& when, double scale_um) {
  render::Composite comp;
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
      const auto panel = dir / "panels" / fmt::format("{}_t{:02d}_{}.png", fs::path(file).stem().string(), tooth, gears::to_string(f));
      const auto rr = render::render_grid_topology(g, panel);
      for (const auto& p : ft->grid) shown.push_back(p.deviation_um);
      fig.colour_range_um = colour_of(rr);
      comp.panels.push_back({panel, fmt::format("{}: magnification ×{:.0f}", flank_name(tooth, f), render::grid_magnification(g))});
    }
  const auto size = render::render_composite(comp, dir / file);
  fig.width = size.width, fig.height = size.height;
  fig.data_range_um = range_of(shown);
  fig.caption = fmt::format("The nominal {}×{} grid (black) and the ground flank (blue) with the deviation magnified, values "
                            "at the nodes in µm, plus material positive. Rows run from root to tip over L_α, columns from "
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

std::string class_text(evaluation::Quantity q, double v, const evaluation::GearParameters& p) {
  if (evaluation::validity_refusal(p)) return "not classified";
  return "class " + evaluation::class_label(evaluation::tolerance_class(q, v, p));
}

// A gear-measuring-machine style chart: deviation across (µm), position along (mm), tolerance band, range marks.
fs::path trace_chart(const workbench::Workbench& wb, const workbench::IsoResult& iso, const grinding::FlankTopology& ft, bool profile,
                     const fs::path& file) {
  const auto& r = wb.setup.ranges();
  const auto& p = iso.parameters;
  render::LineChart c;
  c.size = {560, 760};
  render::Series s;
  s.name = "trace";
  for (const auto& pt : profile ? ft.profile : ft.helix) {
    s.x.push_back(pt.deviation_um);
    s.y.push_back(profile ? pt.roll_length_mm : pt.z_mm);
  }
  s.colour = render::colours::actual;
  c.series.push_back(s);
  const auto qT = profile ? evaluation::Quantity::ProfileTotal : evaluation::Quantity::HelixTotal;
  const bool classify = !evaluation::validity_refusal(p);
  const double T = classify ? evaluation::tolerance_um(qT, p, 5) : 0.0;
  if (classify) c.bands.push_back({render::Orientation::vertical, -0.5 * T, 0.5 * T, render::colours::tolerance, 0.22,
                                   fmt::format("±½ {} class 5", profile ? "F_αT" : "F_βT")});
  const double a = profile ? r.xi_eval_start_mm : r.z_eval_start_mm, b = profile ? r.xi_eval_end_mm : r.z_eval_end_mm;
  c.lines.push_back({render::Orientation::horizontal, a, render::colours::grey, 1.5, true, profile ? "L_α" : "L_β"});
  c.lines.push_back({render::Orientation::horizontal, b, render::colours::grey, 1.5, true, ""});
  c.lines.push_back({render::Orientation::vertical, 0.0, render::colours::black, 1.0, false, ""});
  const double extent = std::max({1.0, std::abs(s.x.empty() ? 0.0 : *std::max_element(s.x.begin(), s.x.end())),
                                  std::abs(s.x.empty() ? 0.0 : *std::min_element(s.x.begin(), s.x.end())), 0.6 * T});
  c.x = {"deviation (plus material)", "µm", -1.3 * extent, 1.3 * extent};
  c.y = {profile ? "roll length ξ" : "axial position z", "mm", {}, {}};
  c.title = fmt::format("{} {}", profile ? "Profile" : "Helix", flank_name(ft.tooth, ft.flank));
  if (const auto* fe = iso_flank(iso, ft.tooth, ft.flank)) {
    const auto& d = profile ? fe->profile : fe->helix;
    const std::string sym = profile ? "α" : "β";
    c.text.corner = render::Corner::bottom_right;
    c.text.lines = {
        fmt::format("F_{} {:6.2f} µm  {}", sym, d.total_um, class_text(qT, d.total_um, p)),
        fmt::format("f_f{} {:6.2f} µm  {}", sym, d.form_um,
                    class_text(profile ? evaluation::Quantity::ProfileForm : evaluation::Quantity::HelixForm, d.form_um, p)),
        fmt::format("f_H{} {:+6.2f} µm  {}", sym, d.slope_um,
                    class_text(profile ? evaluation::Quantity::ProfileSlope : evaluation::Quantity::HelixSlope, d.slope_um, p))};
  }
  c.legend = render::LegendPlace::top_left;
  render::render_line_chart(c, file);
  return file;
}

std::vector<Figure> trace_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir) {
  std::vector<Figure> out;
  for (int tooth : focus_teeth(wb)) {
    render::Composite comp;
    comp.title = fmt::format("Profile and helix traces, tooth {} (before compensation)", tooth);
    comp.columns = 4;
    for (bool profile : {true, false})
      for (Flank f : {Flank::Left, Flank::Right}) {
        const auto* ft = find(r.before, tooth, f);
        if (!ft) continue;
        const auto panel = dir / "panels" / fmt::format("trace_t{:02d}_{}_{}.png", tooth, profile ? "profile" : "helix", gears::to_string(f));
        comp.panels.push_back({trace_chart(wb, r.iso_before, *ft, profile, panel), ""});
      }
    const std::string file = fmt::format("traces_tooth{:02d}.png", tooth);
    const auto size = render::render_composite(comp, dir / file);
    out.push_back({file, "traces", comp.title,
                   "Gear-measuring-machine style charts: the trace over the whole active profile (mid face width) and over "
                   "the whole face width (middle of L_α); dashed lines mark the evaluation ranges, the green band ±½ of the "
                   "class-5 total tolerance; F, f_f and f_H with their classes.",
                   size.width, size.height, std::nullopt, std::nullopt});
  }
  return out;
}

Figure pitch_figure(const workbench::Workbench& wb, const workbench::IsoResult& iso, const fs::path& dir) {
  render::BarChart c;
  c.title = "Single pitch deviation f_p,i and cumulative pitch F_p,i over tooth number";
  c.size = {1400, 700};
  const int z = wb.setup.geometry().teeth();
  for (int t = 1; t <= z; ++t) c.categories.push_back(std::to_string(t));
  c.x = {"tooth", "", {}, {}};
  c.y = {"pitch deviation", "µm", {}, {}};
  for (const auto* pe : {&iso.evaluation.pitch_left, &iso.evaluation.pitch_right}) {
    if (!*pe) continue;
    const std::string side(evaluation::to_string((*pe)->side));
    c.bars.push_back({"f_p,i " + side + " flanks", (*pe)->single_pitch_um, std::nullopt});
    render::Series s;
    s.name = "F_p,i " + side + " flanks";
    for (int t = 1; t <= z; ++t) s.x.push_back(t);
    s.y = (*pe)->index_um;
    s.marker = render::Marker::circle;
    c.lines.push_back(s);
  }
  if (c.bars.empty()) throw std::runtime_error("pitch figure: no pitch evaluation (not every tooth was simulated)");
  if (!evaluation::validity_refusal(iso.parameters)) {
    const double fpT = evaluation::tolerance_um(evaluation::Quantity::SinglePitch, iso.parameters, 5);
    c.ref_lines.push_back({render::Orientation::horizontal, fpT, render::colours::tolerance, 1.5, true, "±f_pT class 5"});
    c.ref_lines.push_back({render::Orientation::horizontal, -fpT, render::colours::tolerance, 1.5, true, ""});
  }
  c.legend = render::LegendPlace::above;
  render::render_bar_chart(c, dir / "pitch.png");
  return {"pitch.png", "pitch", c.title,
          "Bars: single pitch deviation of the pitch from tooth i to i+1 on the measuring circle (transverse arc, µm); "
          "lines: index (cumulative) deviation relative to tooth 1.",
          c.size.width, c.size.height, std::nullopt, std::nullopt};
}

Figure machine_figure(const workbench::Workbench& wb, const fs::path& dir) {
  render::Composite comp;
  comp.title = "Geometric error components against axis position (representative unless the scene says measured)";
  comp.columns = 2;
  const auto& st = wb.machine.strokes();
  const std::pair<double, double> spans[] = {{st.x_mm.min, st.x_mm.max}, {st.y_mm.min, st.y_mm.max}, {st.z_mm.min, st.z_mm.max},
                                             {st.a_deg.min, st.a_deg.max}, {0.0, 360.0}};
  for (int ax = 0; ax < machine::kAxisCount; ++ax) {
    const auto axis = machine::kAxes[static_cast<size_t>(ax)];
    const bool rotary = machine::is_rotary(axis);
    for (int kind = 0; kind < 2; ++kind) { // 0: δ (µm), 1: ε (µrad)
      render::LineChart c;
      c.size = {800, 420};
      c.title = fmt::format("{} axis: {} errors", machine::axis_name(axis), kind == 0 ? "linear" : "angular");
      c.x = {fmt::format("{} position", machine::axis_name(axis)), rotary ? "°" : "mm", {}, {}};
      c.y = {kind == 0 ? "δ" : "ε", kind == 0 ? "µm" : "µrad", {}, {}};
      for (int k = 0; k < 3; ++k) {
        const auto id = machine::motion_component(axis, 3 * kind + k);
        render::Series s;
        s.name = std::string(machine::info(id).symbol);
        for (int i = 0; i <= 100; ++i) {
          const double pos = spans[ax].first + (spans[ax].second - spans[ax].first) * i / 100.0;
          s.x.push_back(pos);
          s.y.push_back((kind == 0 ? units::kUmPerMm : units::kUradPerRad) * wb.machine.source(id).value(rotary ? units::rad_from_deg(pos) : pos));
        }
        c.series.push_back(s);
      }
      c.legend = render::LegendPlace::top_right;
      const auto panel = dir / "panels" / fmt::format("machine_{}_{}.png", machine::axis_name(axis), kind == 0 ? "linear" : "angular");
      render::render_line_chart(c, panel);
      comp.panels.push_back({panel, ""});
    }
  }
  const auto size = render::render_composite(comp, dir / "machine_errors.png");
  return {"machine_errors.png", "machine", comp.title,
          "The six motion errors of each axis over its stroke, as the scene's tables, polynomials or constants give them "
          "(docs/error-components.md for signs).",
          size.width, size.height, std::nullopt, std::nullopt};
}

Figure alignment_figure(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir) {
  render::LineChart c;
  c.title = "Middle tooth-alignment curve before and after compensation";
  c.size = {1200, 700};
  c.x = {"profile curve (column, from the datum face)", "", {}, {}};
  c.y = {"deviation", "µm", {}, {}};
  size_t colour = 0;
  for (int tooth : focus_teeth(wb))
    for (Flank f : {Flank::Left, Flank::Right}) {
      const auto* b = find(r.before, tooth, f);
      const auto* a = find(r.after, tooth, f);
      if (!b || !a) continue;
      const int mid = (b->grid.back().row + 1) / 2;
      render::Series sb, sa;
      sb.name = flank_name(tooth, f) + ", before";
      sa.name = flank_name(tooth, f) + ", after";
      for (const auto* src : {b, a})
        for (const auto& p : src->grid)
          if (p.row == mid) (src == b ? sb : sa).x.push_back(p.col), (src == b ? sb : sa).y.push_back(p.deviation_um);
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
          fmt::format("Tooth-alignment curve {} of {} (mid profile) across the {} profile curves, before (solid) and after "
                      "(dashed) the flank-method compensation.",
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
        h.y = {"roll length ξ", "mm", {}, {}};
        h.size = {700, 520};
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
    c.size = {1000, 600};
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
    l.size = {800, 600};
    render::Series s;
    s.name = "residual RMS";
    s.marker = render::Marker::circle;
    s.x = {0.0};
    s.y = {d.rms_before_um};
    std::string steps = "0: scene model";
    if (d.chosen) {
      s.x.push_back(1.0);
      s.y.push_back(d.chosen->rms_after_um);
      steps += "   1: + " + d.chosen->name();
    }
    l.series.push_back(s);
    l.lines.push_back({render::Orientation::horizontal, d.noise_um, render::colours::grey, 1.5, true, "noise σ"});
    l.lines.push_back({render::Orientation::horizontal, 1.5 * d.noise_um, render::colours::tolerance, 1.5, true, "1.5 σ"});
    l.x = {"step", "", -0.3, std::max(1.3, static_cast<double>(s.x.size()) - 0.7)};
    l.y = {"RMS", "µm", 0.0, 1.2 * std::max(d.rms_before_um, 1.6 * d.noise_um)};
    l.text.corner = render::Corner::top_right;
    l.text.lines = {steps};
    render::render_line_chart(l, dir / "panels" / "diagnosis_rms.png");

    render::Composite comp;
    comp.title = "Diagnosis: which physical effect is missing";
    comp.columns = 2;
    comp.panels = {{dir / "panels" / "diagnosis_candidates.png", ""}, {dir / "panels" / "diagnosis_rms.png", ""}};
    const auto size = render::render_composite(comp, dir / "diagnosis.png");
    out.push_back({"diagnosis.png", "measurement", comp.title, d.verdict, size.width, size.height, std::nullopt, std::nullopt});
  }
  return out;
}

Figure gear_figure(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir) {
  render::SurfaceView v;
  v.title = "The ground gear, flanks coloured by deviation (before compensation)";
  v.size = {1200, 1000};
  surfaces::GearMeshOptions mo;
  mo.flank_points = 6, mo.slices = 9;
  const auto gm = surfaces::gear_mesh(wb.setup.geometry(), mo);
  v.meshes.push_back({gm.vertices, gm.faces, Eigen::VectorXd(), render::colours::light_grey, 1.0, false});
  std::vector<double> shown;
  for (const auto& ft : r.before) {
    const auto fm = grinding::flank_mesh(wb.setup.flanks(), ft);
    // Lift the coloured flank a hair off the grey gear so that it is drawn on top.
    Eigen::Matrix3Xd verts = fm.vertices;
    for (Eigen::Index i = 0; i < verts.cols(); ++i) {
      Eigen::Vector3d radial(verts(0, i), verts(1, i), 0.0);
      verts.col(i) += 0.05 * radial.normalized();
    }
    v.meshes.push_back({verts, fm.faces, fm.vertex_values, render::colours::light_grey, 1.0, false});
    for (Eigen::Index i = 0; i < fm.vertex_values.size(); ++i) shown.push_back(fm.vertex_values(i));
  }
  v.view_direction = Eigen::Vector3d(-0.35, -0.25, 1.0); // from the datum face side, a little oblique
  v.view_up = Eigen::Vector3d(0.0, 1.0, 0.0);
  v.caption = fmt::format("seen from the datum face; colour = normal deviation of the {} grid, µm, plus material positive",
                          grid_label(r));
  const auto rr = render::render_surface_view(v, dir / "gear_3d.png");
  return {"gear_3d.png", "gear", v.title, v.caption, v.size.width, v.size.height, range_of(shown), colour_of(rr)};
}

} // namespace

std::vector<int> focus_teeth(const workbench::Workbench& wb) {
  if (!wb.scene.grid.teeth.empty()) return wb.scene.grid.teeth;
  const int z = wb.setup.geometry().teeth();
  return {1, z / 2 + 1};
}

std::vector<Figure> render_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const fs::path& dir) {
  fs::create_directories(dir / "panels");
  std::vector<Figure> figs;
  std::vector<const grinding::FlankTopology*> focus;
  for (int t : focus_teeth(wb))
    for (Flank f : {Flank::Left, Flank::Right}) focus.push_back(find(r.before, t, f));
  const double scale = max_abs(focus);
  figs.push_back(topology_figure(wb, r.before, dir, "topology_before.png", "Flank topology before compensation", "before", scale));
  for (auto& f : trace_figures(wb, r, dir)) figs.push_back(std::move(f));
  figs.push_back(pitch_figure(wb, r.iso_before, dir));
  figs.push_back(machine_figure(wb, dir));
  Figure after = topology_figure(wb, r.after, dir, "topology_after.png", "Flank topology after compensation (same colour scale)",
                                 "after", scale);
  after.section = "compensation";
  after.shared_scale = true;
  figs.push_back(after);
  figs.push_back(alignment_figure(wb, r, dir));
  if (r.prediction) figs.push_back(prediction_figure(*r.prediction, dir)); // prediction_report.cpp
  if (r.measurement)
    for (auto& f : measurement_figures(*r.measurement, dir)) figs.push_back(std::move(f));
  figs.push_back(gear_figure(wb, r, dir));
  return figs;
}

} // namespace geartopo::report
