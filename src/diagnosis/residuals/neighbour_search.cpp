// geartopo diagnosis — neighbours of scattered points within a multiple of the median nearest-neighbour distance
// (neighbour_search.hpp), by CGAL's k-d tree: k-nearest-neighbour queries for the distances, fuzzy-sphere range queries
// for the neighbours, O(n log n) plus the output instead of all pairs. Unit-free (normalised coordinates).
//
// The only CGAL translation unit of geartopo (CGAL compiles it with -frounding-math; linked PRIVATE, so that flag
// stays here). CGAL finds the candidates; the decisions (nearest distance, "within the link") are taken here with
// std::hypot, the same arithmetic as the all-pairs scan this replaces, so the neighbour sets are identical.
#include "residuals/neighbour_search.hpp"

#include <CGAL/Kd_tree.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Search_traits_2.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace geartopo::diagnosis::residuals {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_2;
using PointMap = CGAL::Pointer_property_map<Point>::type;
// The tree stores point indices; the property map gives their coordinates.
using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_2<Kernel>>;
using KNearest = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = KNearest::Tree;
using Sphere = CGAL::Fuzzy_sphere<Traits>;

/// Range queries ask for a radius larger by this relative margin (and the exact hypot test decides): CGAL compares
/// squared distances, which can round differently from hypot at the boundary.
constexpr double kRadiusMargin = 1e-9;

} // namespace

std::vector<std::vector<std::size_t>> proximity_neighbours(const std::vector<double>& u, const std::vector<double>& w,
                                                           double link_factor) {
  if (u.size() != w.size())
    throw std::invalid_argument("proximity neighbours: u and w differ in length");
  const std::size_t n = u.size();
  std::vector<std::vector<std::size_t>> nb(n);
  if (n < 2) return nb;
  std::vector<Point> points;
  points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) points.emplace_back(u[i], w[i]);
  const PointMap map = CGAL::make_property_map(points);
  const Traits traits(map);
  Tree tree(boost::counting_iterator<std::size_t>(0), boost::counting_iterator<std::size_t>(n), Tree::Splitter(),
            traits);
  tree.build(); // once, before the queries (a lazily built tree is built by the first query)
  const auto dist = [&](std::size_t i, std::size_t k) { return std::hypot(u[i] - u[k], w[i] - w[k]); };

  // Nearest neighbour of every point: the 2 nearest stored points include the point itself (or a coincident twin).
  const KNearest::Distance metric(map);
  std::vector<double> nn(n, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i) {
    const KNearest search(tree, points[i], 2, 0.0, true, metric);
    for (const auto& [k, squared] : search)
      if (k != i) nn[i] = std::min(nn[i], dist(i, k));
  }
  std::vector<double> sorted = nn;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(n / 2), sorted.end());
  const double link = link_factor * sorted[n / 2];

  std::vector<std::size_t> found;
  for (std::size_t i = 0; i < n; ++i) {
    found.clear();
    tree.search(std::back_inserter(found), Sphere(points[i], link * (1.0 + kRadiusMargin), 0.0, traits));
    for (std::size_t k : found)
      if (k != i && dist(i, k) <= link) nb[i].push_back(k);
    std::sort(nb[i].begin(), nb[i].end()); // ascending, the order of the former all-pairs scan
  }
  return nb;
}

} // namespace geartopo::diagnosis::residuals
