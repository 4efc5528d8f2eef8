// geartopo diagnosis, private — neighbours of scattered points in the plane, for grouping failing points of a point
// cloud into regions (docs/residual-patterns.md, "Grouping"). Plain types only: the search structure stays in
// neighbour_search.cpp. Coordinates are the normalised (u, w) ∈ [−1, 1]² (unit-free).
#pragma once

#include <cstddef>
#include <vector>

namespace geartopo::diagnosis::residuals {

/// For every point i of (u[i], w[i]): the indices k ≠ i, ascending, with distance ≤ link_factor × the median over all
/// points of the nearest-neighbour distance (median: the (n/2)-th smallest, 0-based). u and w have the same length.
/// Fewer than 2 points: every list empty. O(n log n) plus the size of the output.
std::vector<std::vector<std::size_t>> proximity_neighbours(const std::vector<double>& u, const std::vector<double>& w,
                                                           double link_factor);

} // namespace geartopo::diagnosis::residuals
