// geartopo diagnosis — RMS and max |residual| per flank, tooth, side and overall (residual_summary.hpp,
// docs/residual-patterns.md section 4). Units: µm (residuals), mm (ξ, z).
#include "geartopo/diagnosis/residuals/residual_summary.hpp"

#include "residuals/residual_fit.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <map>

namespace geartopo::diagnosis {

using namespace residuals;

namespace {

struct Accumulator {
  std::size_t n = 0;
  double sum_sq = 0.0;
  ResidualStats best;
  void add(int tooth, Flank side, double xi, double z, double r) {
    ++n;
    sum_sq += r * r;
    if (n == 1 || std::abs(r) > best.max_abs_um) {
      best.max_abs_um = std::abs(r);
      best.extreme_um = r;
      best.extreme_tooth = tooth;
      best.extreme_side = side;
      best.extreme_xi_mm = xi;
      best.extreme_z_mm = z;
    }
  }
  void add(const Accumulator& o) {
    if (o.n == 0) return;
    if (n == 0 || o.best.max_abs_um > best.max_abs_um) best = o.best;
    n += o.n;
    sum_sq += o.sum_sq;
  }
  ResidualStats stats() const {
    ResidualStats s = best;
    s.points = n;
    s.rms_um = n ? std::sqrt(sum_sq / static_cast<double>(n)) : 0.0;
    return s;
  }
};

} // namespace

ResidualSummary summarize_residuals(std::span<const FlankResiduals> flanks) {
  constexpr std::string_view what = "residual summary";
  if (flanks.empty()) refuse(what, "no flanks");
  std::map<std::pair<int, int>, std::pair<Accumulator, std::size_t>> per_flank; // (tooth, 0 left / 1 right)
  for (const auto& f : flanks) {
    const Prepared p = prepare(f, what);
    const std::pair<int, int> key{f.tooth, f.side == Flank::Left ? 0 : 1};
    if (per_flank.count(key)) refuse(what, fmt::format("{} given twice", flank_name(f.tooth, f.side)));
    Accumulator a;
    for (std::size_t i = 0; i < p.size(); ++i) a.add(f.tooth, f.side, p.xi[i], p.z[i], p.r[i]);
    per_flank.emplace(key, std::make_pair(a, p.outside));
  }
  ResidualSummary out;
  std::map<int, Accumulator> per_tooth;
  std::array<Accumulator, 2> per_side;
  std::array<std::size_t, 2> side_flanks{0, 0};
  Accumulator all;
  for (const auto& [key, v] : per_flank) {
    const Flank side = key.second == 0 ? Flank::Left : Flank::Right;
    out.flanks.push_back({key.first, side, v.second, v.first.stats()});
    per_tooth[key.first].add(v.first);
    per_side[static_cast<std::size_t>(key.second)].add(v.first);
    ++side_flanks[static_cast<std::size_t>(key.second)];
    all.add(v.first);
  }
  for (const auto& [tooth, a] : per_tooth) out.teeth.push_back({tooth, a.stats()});
  for (std::size_t s = 0; s < 2; ++s)
    if (side_flanks[s]) out.sides.push_back({s == 0 ? Flank::Left : Flank::Right, side_flanks[s], per_side[s].stats()});
  out.overall = all.stats();
  return out;
}

} // namespace geartopo::diagnosis
