// geartopo diagnosis — neighbours of scattered points within a multiple of the median nearest-neighbour distance
// (neighbour_search.hpp). Unit-free (normalised coordinates).
#include "residuals/neighbour_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geartopo::diagnosis::residuals {

std::vector<std::vector<std::size_t>> proximity_neighbours(const std::vector<double>& u, const std::vector<double>& w,
                                                           double link_factor) {
  const std::size_t n = u.size();
  std::vector<std::vector<std::size_t>> nb(n);
  if (n < 2) return nb;
  // Scattered points (a point cloud): buckets of about two points each in (u, w) ∈ [−1, 1]², so that both searches
  // look at a few buckets per point instead of all n points (a 20 000-point flank took 19 s that way).
  const long side = std::max(1L, static_cast<long>(std::sqrt(static_cast<double>(n) / 2.0)));
  const double h = 2.0 / static_cast<double>(side);
  const auto bucket = [&](double v) { return std::clamp(static_cast<long>((v + 1.0) / h), 0L, side - 1); };
  std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(side * side));
  for (std::size_t i = 0; i < n; ++i) grid[static_cast<std::size_t>(bucket(u[i]) * side + bucket(w[i]))].push_back(i);
  const auto dist = [&](std::size_t i, std::size_t k) { return std::hypot(u[i] - u[k], w[i] - w[k]); };
  // Calls f(k) for every point in the buckets within `ring` buckets of point i's, ring by ring from 0 to `rings`.
  const auto visit_ring = [&](std::size_t i, long ring, const auto& f) {
    const long bu = bucket(u[i]), bw = bucket(w[i]);
    for (long a = bu - ring; a <= bu + ring; ++a)
      for (long b = bw - ring; b <= bw + ring; ++b) {
        if (std::max(std::abs(a - bu), std::abs(b - bw)) != ring || a < 0 || b < 0 || a >= side || b >= side) continue;
        for (std::size_t k : grid[static_cast<std::size_t>(a * side + b)]) f(k);
      }
  };
  // Nearest neighbour: rings outward until the next ring cannot hold anything closer (a point in ring r is at least
  // (r − 1)·h away).
  std::vector<double> nn(n, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    for (long ring = 0; ring < side && !(nn[i] <= static_cast<double>(ring - 1) * h); ++ring)
      visit_ring(i, ring, [&](std::size_t k) {
        if (k != i) nn[i] = std::min(nn[i], dist(i, k));
      });
  std::vector<double> sorted = nn;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(n / 2), sorted.end());
  const double link = link_factor * sorted[n / 2];
  const long reach = std::min(side - 1, static_cast<long>(std::ceil(link / h)) + 1);
  for (std::size_t i = 0; i < n; ++i) {
    for (long ring = 0; ring <= reach; ++ring)
      visit_ring(i, ring, [&](std::size_t k) {
        if (k != i && dist(i, k) <= link) nb[i].push_back(k);
      });
    std::sort(nb[i].begin(), nb[i].end()); // the order of the former all-pairs scan
  }
  return nb;
}

} // namespace geartopo::diagnosis::residuals
