// geartopo — residual against the process variables, as a figure (residual_follows_figure.hpp). Units: µm.
#include "geartopo/report/residual_follows_figure.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/render/charts.hpp"
#include "geartopo/render/composite.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geartopo::report {

void render_residual_follows(const diagnosis::ResidualFollows& follows,
                             const std::vector<measurement::MeasuredPoint>& pts, const std::filesystem::path& png,
                             const std::filesystem::path& panel_dir) {
  if (follows.variables.empty()) throw std::invalid_argument("residual figure: no process variable varies over the points");
  output::create_folders_for(panel_dir); // in the staging folder while an output folder is open
  render::Composite comp;
  comp.title = "What the residual follows (set-up terms removed)";
  comp.columns = 2;
  comp.font_px = 22;
  const auto& r = follows.residual_setup_removed_um;
  for (size_t k = 0; k < follows.variables.size(); ++k) {
    const auto& d = follows.variables[k];
    render::LineChart c;
    c.title = d.once_per_revolution
                  ? fmt::format("{}: {:.2f} ± {:.2f} µm at {:.0f} ± {:.0f}° (ΔBIC {:.0f}{})", d.variable, d.slope_um,
                                d.slope_sd_um, d.phase_deg, d.phase_sd_deg, d.delta_bic, d.significant ? "" : ", not significant")
                  : fmt::format("{}: {:+.3g} ± {:.2g} µm/{} (ΔBIC {:.0f}{})", d.variable, d.slope_um, d.slope_sd_um,
                                d.unit, d.delta_bic, d.significant ? "" : ", not significant");
    c.x = {d.variable, d.unit, std::nullopt, std::nullopt};
    if (d.once_per_revolution) c.x.min = 0.0, c.x.max = 360.0; // C is commanded in [0, 360)
    c.y = {"residual", "µm", std::nullopt, std::nullopt};
    c.size = {900, 560};
    for (const Flank side : {Flank::Left, Flank::Right}) {
      render::Series s;
      s.name = side == Flank::Left ? "left flanks" : "right flanks";
      s.marker = side == Flank::Left ? render::Marker::circle : render::Marker::square;
      s.marker_size = 5.0;
      s.colour = render::series_colour(side == Flank::Left ? 0 : 1);
      for (size_t i = 0; i < pts.size(); ++i)
        if (pts[i].flank == side) { // markers only: a NaN after each point breaks the polyline (render::Series)
          s.x.insert(s.x.end(), {d.values[i], std::nan("")});
          s.y.insert(s.y.end(), {r[i], std::nan("")});
        }
      if (!s.x.empty()) c.series.push_back(std::move(s));
    }
    // The fitted dependence over the variable's range (the set-up terms removed from it too, so only its shape).
    render::Series fit;
    fit.name = d.once_per_revolution ? fmt::format("{:+.2f} µm · cos(γ − {:.0f}°)", d.slope_um, d.phase_deg)
                                     : fmt::format("{:+.3g} µm/{}", d.slope_um, d.unit);
    fit.colour = render::colours::text;
    fit.width = 2.0;
    const double mid = 0.5 * (d.lo + d.hi);
    for (int j = 0; j <= 60; ++j) {
      const double x = d.lo + (d.hi - d.lo) * j / 60.0;
      fit.x.push_back(x);
      fit.y.push_back(d.once_per_revolution ? d.slope_um * std::cos((x - d.phase_deg) * std::numbers::pi / 180.0)
                                            : d.slope_um * (x - mid));
    }
    c.series.push_back(std::move(fit));
    c.legend = render::LegendPlace::above;
    const auto panel = panel_dir / fmt::format("residual_vs_{}.png", k);
    render::render_line_chart(c, panel);
    comp.panels.push_back({panel, ""});
  }
  render::render_composite(comp, png);
}

} // namespace geartopo::report
