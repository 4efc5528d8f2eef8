// geartopo diagnosis — σ from the measured lines' own scatter and the crossings of profile and helix lines
// (line_noise.hpp, docs/residual-patterns.md "Noise"). Units: mm (ξ, z), µm.
#include "geartopo/diagnosis/residuals/line_noise.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace geartopo::diagnosis {
namespace {

constexpr double kSameLineMm = 1e-3; // points within 1 µm in z (or ξ) lie on one line
constexpr double kMadToSigma = 1.482602218505602; // 1/Φ⁻¹(3/4): MAD of N(0, σ²) is σ/1.4826

struct LinePoint {
  double x = 0.0, r = 0.0;
};
using Line = std::vector<LinePoint>;

/// The lines of a flank along ξ (profile: points sharing z) or along z (helix: points sharing ξ), each sorted by its
/// position, points at one position (within 1 nm) merged into the first. Dense lines only.
std::vector<std::pair<double, Line>> dense_lines(const FlankResiduals& f, bool profile) {
  std::map<long long, std::pair<double, Line>> by_key;
  for (const auto& p : f.points) {
    const double at = profile ? p.z_mm : p.xi_mm, x = profile ? p.xi_mm : p.z_mm;
    auto& [pos, line] = by_key[std::llround(at / kSameLineMm)];
    pos = at;
    line.push_back({x, p.residual_um});
  }
  std::vector<std::pair<double, Line>> out;
  for (auto& [key, entry] : by_key) {
    auto& line = entry.second;
    std::stable_sort(line.begin(), line.end(), [](const LinePoint& a, const LinePoint& b) { return a.x < b.x; });
    Line merged;
    for (const auto& q : line)
      if (merged.empty() || q.x - merged.back().x > 1e-6) merged.push_back(q);
    if (merged.size() >= kDenseLinePoints) out.emplace_back(entry.first, std::move(merged));
  }
  return out;
}

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

/// The line's normalised second differences with its one curvature removed (line_noise_um).
void add_differences(const Line& l, std::vector<double>& out) {
  std::vector<double> e, g;
  for (std::size_t i = 1; i + 1 < l.size(); ++i) {
    const double ha = l[i].x - l[i - 1].x, hb = l[i + 1].x - l[i].x, w = hb / (ha + hb);
    const double norm = std::sqrt(1.0 + w * w + (1.0 - w) * (1.0 - w));
    e.push_back((l[i].r - (w * l[i - 1].r + (1.0 - w) * l[i + 1].r)) / norm);
    g.push_back(-0.5 * ha * hb / norm); // e of f = x²/2 (f'' = 1): what one unit of curvature adds
  }
  std::vector<double> ratio(e.size());
  for (std::size_t i = 0; i < e.size(); ++i) ratio[i] = e[i] / g[i];
  const double curvature = median(ratio); // µm/mm²
  // One curvature fitted per line takes one degree of freedom from its m differences: without √(m/(m − 1)) a 38-point
  // line reads σ 1.4 % low — enough for a χ² test over 10⁵ points to call pure noise "more than noise".
  const double dof = e.size() > 1 ? std::sqrt(static_cast<double>(e.size()) / static_cast<double>(e.size() - 1)) : 1.0;
  for (std::size_t i = 0; i < e.size(); ++i) out.push_back(dof * (e[i] - curvature * g[i]));
}

double interpolate(const Line& l, double x) {
  const auto hi = std::lower_bound(l.begin(), l.end(), x, [](const LinePoint& p, double v) { return p.x < v; });
  if (hi == l.begin()) return hi->r;
  if (hi == l.end()) return l.back().r;
  const auto lo = hi - 1;
  const double t = (x - lo->x) / (hi->x - lo->x);
  return lo->r + t * (hi->r - lo->r);
}

} // namespace

LineNoise line_noise_um(std::span<const FlankResiduals> flanks) {
  LineNoise out;
  std::vector<double> d;
  for (const auto& f : flanks)
    for (const bool profile : {true, false})
      for (const auto& [pos, line] : dense_lines(f, profile)) {
        add_differences(line, d);
        ++out.lines;
      }
  out.differences = d.size();
  if (d.empty()) return out;
  const double m = median(d);
  for (auto& v : d) v = std::abs(v - m);
  out.sigma_um = kMadToSigma * median(std::move(d));
  return out;
}

DenseLineCount dense_line_count(const FlankResiduals& f) { return {dense_lines(f, true).size(), dense_lines(f, false).size()}; }

std::vector<LineCrossing> line_crossings(const FlankResiduals& f) {
  std::vector<LineCrossing> out;
  const auto profiles = dense_lines(f, true), helices = dense_lines(f, false);
  for (const auto& [z, pl] : profiles)
    for (const auto& [xi, hl] : helices) {
      if (xi < pl.front().x || xi > pl.back().x || z < hl.front().x || z > hl.back().x) continue;
      out.push_back({xi, z, interpolate(pl, xi), interpolate(hl, z)});
    }
  return out;
}

} // namespace geartopo::diagnosis
