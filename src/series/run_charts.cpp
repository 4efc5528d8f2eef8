// The run charts of a series (run_charts.hpp).
#include "geartopo/series/run_charts.hpp"

#include "run_charts_detail.hpp"

#include "geartopo/render/charts.hpp"

#include <fmt/format.h>

#include <cmath>

namespace geartopo::series {
namespace {

/// The least-squares straight line through (k, y_k), k = 1 … n: its values at 1 and n.
std::pair<double, double> trend_ends(const std::vector<double>& y) {
  const double n = static_cast<double>(y.size()), kbar = (n + 1.0) / 2.0;
  double ybar = 0.0, sxy = 0.0, sxx = 0.0;
  for (double v : y) ybar += v / n;
  for (size_t k = 0; k < y.size(); ++k) {
    const double dk = static_cast<double>(k + 1) - kbar;
    sxy += dk * (y[k] - ybar), sxx += dk * dk;
  }
  const double slope = sxx > 0.0 ? sxy / sxx : 0.0;
  return {ybar + slope * (1.0 - kbar), ybar + slope * (n - kbar)};
}

render::LineChart run_chart(const SeriesQuantity& q, const SeriesResult& r) {
  render::LineChart c;
  const size_t n = q.values_um.size();
  c.title = fmt::format("{} over the series", q.label);
  c.x = {"gear (in the order ground)", "", 0.5, static_cast<double>(n) + 1.5};
  c.y = {q.label, "µm", {}, {}};
  for (size_t k = 1; k <= n + 1; ++k) { // whole gears; the last place is the next gear's
    c.x_ticks.push_back(static_cast<double>(k));
    c.x_tick_labels.push_back(k <= n ? std::to_string(k) : std::string("next"));
  }
  render::Series measured{"measured", {}, q.values_um, render::series_colour(0), 1.5, render::Marker::circle};
  double mean = 0.0;
  for (size_t k = 0; k < n; ++k) measured.x.push_back(static_cast<double>(k + 1)), mean += q.values_um[k] / n;
  c.series.push_back(measured);
  const auto [t0, t1] = trend_ends(q.values_um);
  c.series.push_back({"straight-line trend", {1.0, static_cast<double>(n)}, {t0, t1}, render::colours::grey, 1.5,
                      render::Marker::none, 7.0, true});
  c.lines.push_back({render::Orientation::horizontal, mean, render::colours::grey, 1.0, true, fmt::format("mean {:.2f}", mean)});
  if (q.fit) {
    render::Series law{"law: " + q.fit->chosen.name(), {}, {}, render::series_colour(1), 2.0};
    for (size_t k = 0; k < n; ++k) law.x.push_back(static_cast<double>(k + 1)), law.y.push_back(predict(q.fit->chosen, r.states[k]).median_um);
    law.x.push_back(static_cast<double>(n + 1)), law.y.push_back(q.next->median_um);
    c.series.push_back(law);
    const double x = static_cast<double>(n + 1);
    c.series.push_back({"next gear, 95 %", {x, x}, {q.next->lower95_um, q.next->upper95_um}, render::series_colour(3), 3.0,
                        render::Marker::plus});
  }
  if (const auto band = tolerance_band(q, r)) c.bands.push_back(*band);
  if (q.fit)
    for (const auto& p : q.fit->chosen.parameters)
      c.text.lines.push_back(p.determined ? fmt::format("{} = {:.4g} ± {:.2g}", p.name, p.value, p.sigma)
                                          : fmt::format("{}: not determined", p.name));
  if (q.loss && q.loss->gears_median)
    c.text.lines.push_back(fmt::format("limit expected left {} gears ahead (95 %: {} … {})", *q.loss->gears_median,
                                       *q.loss->gears_early,
                                       q.loss->gears_late ? std::to_string(*q.loss->gears_late) : std::string("later")));
  c.legend = render::LegendPlace::above;
  return c;
}

} // namespace

std::optional<render::Band> tolerance_band(const SeriesQuantity& q, const SeriesResult& r) {
  if (!q.limit_um) return std::nullopt;
  return render::Band{render::Orientation::horizontal, two_sided_limit(q) ? -*q.limit_um : 0.0, *q.limit_um, render::colours::tolerance,
                      0.22, q.iso ? fmt::format("class {} tolerance", *r.drawing_class) : std::string("allowance range")};
}

std::vector<std::filesystem::path> write_run_charts(const SeriesResult& r, const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& q : r.quantities) {
    bool finite = !q.values_um.empty();
    for (double v : q.values_um) finite = finite && std::isfinite(v);
    if (!finite) continue;
    files.push_back(dir / fmt::format("run_chart_{}.png", q.key));
    render::render_line_chart(run_chart(q, r), files.back());
  }
  return files;
}

} // namespace geartopo::series
