// The figure of the closed loop over a series, synthetic (run_charts.hpp).
#include "geartopo/series/closed_loop.hpp"
#include "geartopo/series/run_charts.hpp"

#include "run_charts_detail.hpp"

#include "geartopo/render/charts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace geartopo::series {
namespace {

constexpr std::size_t kLeastGears = 12;
constexpr std::uint64_t kSeed = 41;

/// The range of the law's values over the series' gears, µm.
double law_range(const SeriesQuantity& q, const SeriesResult& r) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& s : r.states) {
    const double v = predict(q.fit->chosen, s).median_um;
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  return hi - lo;
}

/// The series' states, then one step (mean interval, one gear's strokes, no re-dress) per gear up to `count`.
std::vector<GearState> stepped_states(const SeriesResult& r, std::size_t count) {
  std::vector<GearState> s = r.states;
  while (s.size() < count) {
    GearState g = s.back();
    g.time_h += r.step.time_h, g.strokes_since_dressing += r.step.strokes_since_dressing;
    s.push_back(g);
  }
  return s;
}

double rms(const std::vector<ClosedLoopGear>& g, double ClosedLoopGear::*m, std::size_t from) {
  double s = 0.0;
  for (std::size_t k = from; k < g.size(); ++k) s += g[k].*m * (g[k].*m);
  return std::sqrt(s / static_cast<double>(g.size() - from));
}

render::LineChart loop_chart(const SeriesQuantity& q, const SeriesResult& r, const std::vector<ClosedLoopGear>& loop) {
  render::LineChart c;
  const std::size_t n = loop.size();
  c.title = fmt::format("Closed loop over the series (SYNTHETIC): {}", q.label);
  c.x = {"gear (in the order ground)", "", 0.5, static_cast<double>(n) + 0.5};
  c.y = {fmt::format("{}", q.label), "µm", {}, {}};
  for (std::size_t k = 1; k <= n; ++k) c.x_ticks.push_back(static_cast<double>(k)), c.x_tick_labels.push_back(std::to_string(k));
  render::Series open{"open loop: no corrections", {}, {}, render::series_colour(0), 1.5, render::Marker::circle};
  render::Series closed{"closed loop: gear k's diagnosis corrects gear k+1", {}, {}, render::series_colour(1), 2.0,
                        render::Marker::square};
  render::Series correction{"correction applied", {}, {}, render::colours::grey, 1.5, render::Marker::none, 7.0, true};
  for (std::size_t k = 0; k < n; ++k) {
    const double x = static_cast<double>(k + 1);
    open.x.push_back(x), open.y.push_back(loop[k].open_um);
    closed.x.push_back(x), closed.y.push_back(loop[k].closed_um);
    correction.x.push_back(x), correction.y.push_back(loop[k].correction_um);
  }
  c.series = {open, closed, correction};
  c.lines.push_back({render::Orientation::horizontal, 0.0, render::colours::grey, 1.0, false, ""});
  if (const auto band = tolerance_band(q, r)) c.bands.push_back(*band);
  const std::size_t from = std::min<std::size_t>(3, n - 1);
  c.text.corner = render::Corner::bottom_left;
  c.text.lines = {fmt::format("synthetic: truth = law fitted to the {} measured gears ({}),", r.states.size(),
                              q.fit->chosen.name()),
                  fmt::format("scatter σ = {:.2g} µm drawn (seed {}); gears {} … {} stepped on", q.fit->chosen.sigma_um,
                              kSeed, r.states.size() + 1, n),
                  fmt::format("RMS from gear {}: open {:.2f} µm, closed {:.2f} µm", from + 1,
                              rms(loop, &ClosedLoopGear::open_um, from), rms(loop, &ClosedLoopGear::closed_um, from))};
  if (r.states.size() >= n) c.text.lines[1] = fmt::format("scatter σ = {:.2g} µm drawn (seed {})", q.fit->chosen.sigma_um, kSeed);
  c.legend = render::LegendPlace::above;
  return c;
}

} // namespace

std::optional<std::size_t> closed_loop_quantity(const SeriesResult& r) {
  std::optional<std::size_t> best, thickness;
  double widest = 0.0;
  for (std::size_t i = 0; i < r.quantities.size(); ++i) {
    const auto& q = r.quantities[i];
    if (!q.fit) continue;
    if (q.key == "thickness_deviation_um") thickness = i;
    if (q.fit->chosen.laws.empty()) continue;
    const double range = law_range(q, r);
    if (range > widest) widest = range, best = i;
  }
  return best ? best : thickness;
}

std::optional<std::filesystem::path> write_closed_loop_figure(const SeriesResult& r, const std::filesystem::path& dir) {
  const auto which = closed_loop_quantity(r);
  if (!which) return std::nullopt;
  const SeriesQuantity& q = r.quantities[*which];
  ClosedLoopInput in;
  in.states = stepped_states(r, std::max(kLeastGears, r.states.size()));
  const LawFit law = q.fit->chosen;
  in.truth_um = [law](const GearState& s) { return predict(law, s).median_um; };
  in.scatter_um = law.sigma_um;
  in.floor_um = std::max(q.floor_um, 1e-3);
  in.seed = kSeed;
  const auto file = dir / "closed_loop_synthetic.png";
  render::render_line_chart(loop_chart(q, r, run_closed_loop(in)), file);
  return file;
}

} // namespace geartopo::series
