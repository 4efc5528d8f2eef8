// The closed loop over a series, synthetic (closed_loop.hpp).
#include "geartopo/series/closed_loop.hpp"

#include "geartopo/core/random.hpp"

#include <numeric>
#include <stdexcept>

namespace geartopo::series {

std::vector<ClosedLoopGear> run_closed_loop(const ClosedLoopInput& in) {
  if (in.states.empty()) throw std::invalid_argument("run_closed_loop: no gear");
  if (!in.truth_um) throw std::invalid_argument("run_closed_loop: no truth");
  if (!(in.scatter_um >= 0.0)) throw std::invalid_argument("run_closed_loop: the scatter must be ≥ 0");
  random::SplitMix64 rng(in.seed);
  std::vector<ClosedLoopGear> gears;
  std::vector<double> uncorrected; // what the loop learns from: measured − the known correction
  for (size_t k = 0; k < in.states.size(); ++k) {
    ClosedLoopGear g;
    if (k == 1 || k == 2) {
      g.correction_um = -std::accumulate(uncorrected.begin(), uncorrected.end(), 0.0) / static_cast<double>(k);
      g.model = "mean so far";
    } else if (k >= 3) {
      const std::vector<GearState> seen(in.states.begin(), in.states.begin() + static_cast<std::ptrdiff_t>(k));
      const SeriesFit fit = fit_series(seen, uncorrected, in.floor_um);
      g.correction_um = -predict(fit.chosen, in.states[k]).median_um;
      g.model = fit.chosen.name();
    }
    g.open_um = in.truth_um(in.states[k]) + in.scatter_um * rng.normal();
    g.closed_um = g.open_um + g.correction_um;
    uncorrected.push_back(g.closed_um - g.correction_um);
    gears.push_back(g);
  }
  return gears;
}

} // namespace geartopo::series
