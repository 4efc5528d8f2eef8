// geartopo diagnosis — failing regions of one flank's residual, named in gear terms (failing_regions.hpp,
// docs/residual-patterns.md section 3). Units: mm (ξ, z), µm (residuals, σ).
#include "geartopo/diagnosis/residuals/failing_regions.hpp"

#include "residuals/neighbour_search.hpp"
#include "residuals/residual_fit.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace geartopo::diagnosis {

using namespace residuals;

namespace {

/// Region tendencies: a fitted change counts when it exceeds this many standard errors and this fraction of the
/// region's mean |residual|.
constexpr double kTendencySigmas = 3.0;
constexpr double kTendencyFraction = 0.25;

ProfileZone profile_zone(double lo, double hi) {
  constexpr double t = 1.0 / 3.0, eps = 1e-9;
  const double span = hi - lo, centre = 0.5 * (lo + hi);
  if (span >= 1.5 && std::abs(centre) <= 0.25) return ProfileZone::Whole;
  if (hi <= -t + eps) return ProfileZone::RootThird;
  if (lo >= t - eps) return ProfileZone::TipThird;
  if (lo >= -t - eps && hi <= t + eps) return ProfileZone::Middle;
  if (hi <= eps) return ProfileZone::RootHalf;
  if (lo >= -eps) return ProfileZone::TipHalf;
  return centre < 0 ? ProfileZone::RootHalf : ProfileZone::TipHalf;
}

AxialZone axial_zone(double lo, double hi) {
  switch (profile_zone(lo, hi)) { // same rule: root ↔ datum face (w = −1), tip ↔ far face (w = +1)
  case ProfileZone::RootThird: return AxialZone::DatumFaceEnd;
  case ProfileZone::Middle: return AxialZone::Middle;
  case ProfileZone::TipThird: return AxialZone::FarFaceEnd;
  case ProfileZone::RootHalf: return AxialZone::DatumFaceHalf;
  case ProfileZone::TipHalf: return AxialZone::FarFaceHalf;
  case ProfileZone::Whole: return AxialZone::Whole;
  }
  return AxialZone::Whole;
}

/// Scattered points are connected within this multiple of the median nearest-neighbour distance: far enough to bridge
/// the gaps of an irregular layout, near enough that a passing band a few points wide still separates regions.
constexpr double kLinkFactor = 3.0;

/// Neighbour lists of the in-range points: 8-neighbours when the points form a (mostly filled) grid, else all points
/// within kLinkFactor × the median nearest-neighbour distance in (u, w) (neighbour_search.hpp).
std::vector<std::vector<std::size_t>> neighbours(const Prepared& p, const FlankResiduals& f) {
  const std::size_t n = p.size();
  std::vector<std::vector<std::size_t>> nb(n);
  const auto dxi = distinct(p.xi, 1e-6 * (f.xi_end_mm - f.xi_start_mm));
  const auto dz = distinct(p.z, 1e-6 * (f.z_end_mm - f.z_start_mm));
  const auto cell_of = [](const std::vector<double>& d, double v) {
    auto it = std::upper_bound(d.begin(), d.end(), v); // the cluster whose first value is ≤ v
    return static_cast<long>(it - d.begin()) - 1;
  };
  if (dxi.size() * dz.size() <= 2 * n) {
    std::map<std::pair<long, long>, std::size_t> cells;
    bool unique = true;
    std::vector<std::pair<long, long>> at(n);
    for (std::size_t i = 0; i < n && unique; ++i) {
      at[i] = {cell_of(dxi, p.xi[i]), cell_of(dz, p.z[i])};
      unique = cells.emplace(at[i], i).second;
    }
    if (unique) {
      for (std::size_t i = 0; i < n; ++i)
        for (long di = -1; di <= 1; ++di)
          for (long dk = -1; dk <= 1; ++dk) {
            if (di == 0 && dk == 0) continue;
            auto it = cells.find({at[i].first + di, at[i].second + dk});
            if (it != cells.end()) nb[i].push_back(it->second);
          }
      return nb;
    }
  }
  // Scattered points (a point cloud).
  return proximity_neighbours(p.u, p.w, kLinkFactor);
}

} // namespace

std::string_view to_string(ProfileZone z) {
  switch (z) {
  case ProfileZone::RootThird: return "root third";
  case ProfileZone::Middle: return "middle of the profile";
  case ProfileZone::TipThird: return "tip third";
  case ProfileZone::RootHalf: return "root half";
  case ProfileZone::TipHalf: return "tip half";
  case ProfileZone::Whole: return "whole profile";
  }
  return "?";
}

std::string_view to_string(AxialZone z) {
  switch (z) {
  case AxialZone::DatumFaceEnd: return "near the datum face";
  case AxialZone::Middle: return "mid face width";
  case AxialZone::FarFaceEnd: return "near the far face";
  case AxialZone::DatumFaceHalf: return "half towards the datum face";
  case AxialZone::FarFaceHalf: return "half towards the far face";
  case AxialZone::Whole: return "whole face width";
  }
  return "?";
}

namespace {

/// A region's extent in the scaled coordinates (u along the profile, w along the face width, 0 … 1).
struct Extent {
  double ulo = 1e300, uhi = -1e300, wlo = 1e300, whi = -1e300;
};

/// The region of `members` (local indices, ascending) with its sign: points, extent, mean, extreme and zones.
FailingRegion measure_region(const FlankResiduals& flank, const Prepared& p, const std::vector<std::size_t>& members,
                             int sign, Extent& e, double& mean_abs) {
  FailingRegion g;
  g.tooth = flank.tooth;
  g.side = flank.side;
  g.sign = sign;
  double sum = 0.0, sum_abs = 0.0;
  g.xi_min_mm = g.z_min_mm = 1e300;
  g.xi_max_mm = g.z_max_mm = -1e300;
  std::size_t ext = members.front();
  for (std::size_t i : members) {
    g.point_indices.push_back(p.index[i]);
    if (std::abs(p.r[i]) > std::abs(p.r[ext])) ext = i;
    sum += p.r[i];
    sum_abs += std::abs(p.r[i]);
    e.ulo = std::min(e.ulo, p.u[i]), e.uhi = std::max(e.uhi, p.u[i]);
    e.wlo = std::min(e.wlo, p.w[i]), e.whi = std::max(e.whi, p.w[i]);
    g.xi_min_mm = std::min(g.xi_min_mm, p.xi[i]), g.xi_max_mm = std::max(g.xi_max_mm, p.xi[i]);
    g.z_min_mm = std::min(g.z_min_mm, p.z[i]), g.z_max_mm = std::max(g.z_max_mm, p.z[i]);
  }
  const double m = static_cast<double>(members.size());
  g.mean_um = sum / m;
  mean_abs = sum_abs / m;
  g.extreme_um = p.r[ext];
  g.extreme_index = p.index[ext];
  g.extreme_xi_mm = p.xi[ext];
  g.extreme_z_mm = p.z[ext];
  g.profile_zone = profile_zone(e.ulo, e.uhi);
  g.axial_zone = axial_zone(e.wlo, e.whi);
  return g;
}

/// Tendency: plane fit of |residual| (= sign · residual) over the region, in mm about the region's centre — growing
/// towards the tip or root, the far or datum face, or a peak the plane does not follow.
void fit_tendency(FailingRegion& g, const Prepared& p, const std::vector<std::size_t>& members, const Extent& e,
                  double mean_abs, double sigma) {
  const double span_xi = g.xi_max_mm - g.xi_min_mm, span_z = g.z_max_mm - g.z_min_mm;
  const double cxi = 0.5 * (g.xi_min_mm + g.xi_max_mm), cz = 0.5 * (g.z_min_mm + g.z_max_mm);
  bool use_xi = span_xi > 1e-9, use_z = span_z > 1e-9;
  const auto mi = static_cast<Eigen::Index>(members.size());
  Eigen::VectorXd ya(mi);
  for (Eigen::Index i = 0; i < mi; ++i) ya(i) = g.sign * p.r[members[static_cast<std::size_t>(i)]];
  std::optional<LsFit> plane;
  for (int attempt = 0; attempt < 3; ++attempt) {
    Eigen::MatrixXd X(mi, 1 + (use_xi ? 1 : 0) + (use_z ? 1 : 0));
    for (Eigen::Index i = 0; i < mi; ++i) {
      const std::size_t l = members[static_cast<std::size_t>(i)];
      Eigen::Index c = 0;
      X(i, c++) = 1.0;
      if (use_xi) X(i, c++) = (p.xi[l] - cxi) / std::max(span_xi, 1e-300);
      if (use_z) X(i, c++) = (p.z[l] - cz) / std::max(span_z, 1e-300);
    }
    plane = least_squares(X, ya);
    if (plane) break;
    // Not determined (too few points, or they lie on a slanted line): drop the direction of smaller relative extent.
    if (use_xi && use_z) {
      if ((e.uhi - e.ulo) < (e.whi - e.wlo)) use_xi = false;
      else use_z = false;
    } else {
      use_xi = use_z = false;
    }
  }
  if (!plane) return;
  Eigen::Index c = 1;
  const auto judge = [&](double& change) {
    change = plane->coef(c);
    const double se = sigma * std::sqrt(plane->cov_unit(c, c));
    ++c;
    return std::abs(change) > kTendencySigmas * se && std::abs(change) > kTendencyFraction * mean_abs;
  };
  if (use_xi && judge(g.change_along_profile_um))
    g.profile_growth = g.change_along_profile_um > 0 ? ProfileGrowth::TowardsTip : ProfileGrowth::TowardsRoot;
  if (use_z && judge(g.change_along_face_um))
    g.axial_growth = g.change_along_face_um > 0 ? AxialGrowth::TowardsFarFace : AxialGrowth::TowardsDatumFace;
  const double rms_plane = std::sqrt(plane->rss / static_cast<double>(mi));
  g.peaked = g.profile_growth == ProfileGrowth::None && g.axial_growth == AxialGrowth::None && mi >= 4 &&
             rms_plane > std::max(2.0 * sigma, kTendencyFraction * mean_abs);
}

/// The region in words: where, thicker or thinner, and how (uniform, growing towards …, a local bump or hollow).
void put_into_words(FailingRegion& g, std::size_t points) {
  const std::string where = g.profile_zone == ProfileZone::Whole && g.axial_zone == AxialZone::Whole
                                ? std::string("whole flank")
                                : fmt::format("{}, {}", to_string(g.profile_zone), to_string(g.axial_zone));
  const std::string thick = g.sign > 0 ? "thicker (plus material)" : "thinner (minus material)";
  std::string trend;
  if (g.profile_growth != ProfileGrowth::None || g.axial_growth != AxialGrowth::None) {
    std::vector<std::string> dirs;
    if (g.profile_growth != ProfileGrowth::None)
      dirs.emplace_back(g.profile_growth == ProfileGrowth::TowardsTip ? "the tip" : "the root");
    if (g.axial_growth != AxialGrowth::None)
      dirs.emplace_back(g.axial_growth == AxialGrowth::TowardsFarFace ? "the far face" : "the datum face");
    trend = "growing towards " + dirs.front() + (dirs.size() > 1 ? " and " + dirs.back() : "");
  } else if (g.peaked) {
    trend = g.sign > 0 ? "local bump" : "local hollow";
  } else {
    trend = "uniform";
  }
  const std::string extreme = fmt::format("extreme {} at L_y = {:.2f} mm, z = {:.2f} mm", signed_um(g.extreme_um, 1),
                                          g.extreme_xi_mm, g.extreme_z_mm);
  const std::string count = fmt::format("{} point{}", points, points == 1 ? "" : "s");
  if (trend == "uniform") {
    g.words = fmt::format("{}, uniform {}, {}", where, signed_um(g.mean_um, 1), thick);
    g.sentence = fmt::format("{}, {}: uniform {}, {}; {}; {}", flank_name(g.tooth, g.side), where,
                             signed_um(g.mean_um, 1), thick, extreme, count);
  } else {
    g.words = fmt::format("{}, {}, {}", where, thick, trend);
    g.sentence = fmt::format("{}, {}: {}, {}, up to {} at L_y = {:.2f} mm, z = {:.2f} mm; {}", flank_name(g.tooth, g.side),
                             where, thick, trend, signed_um(g.extreme_um, 1), g.extreme_xi_mm, g.extreme_z_mm, count);
  }
}

} // namespace

std::vector<FailingRegion> find_failing_regions(const FlankResiduals& flank, const RegionOptions& o) {
  constexpr std::string_view what = "failing-region search";
  check_noise(what, o.noise_um);
  if (!(o.k > 0.0 && std::isfinite(o.k))) refuse(what, fmt::format("threshold factor k = {} (must be > 0)", o.k));
  const Prepared p = prepare(flank, what);
  const double sigma = o.noise_um, limit = o.k * sigma;
  const std::size_t n = p.size();

  std::vector<int> mark(n, 0); // +1 / −1 failing by sign, 0 passing
  bool any = false;
  for (std::size_t i = 0; i < n; ++i)
    if (std::abs(p.r[i]) > limit) {
      mark[i] = p.r[i] > 0 ? +1 : -1;
      any = true;
    }
  std::vector<FailingRegion> regions;
  if (!any) return regions;
  const auto nb = neighbours(p, flank);

  // Regions: the failing points connected through neighbours of the same sign.
  std::vector<bool> seen(n, false);
  for (std::size_t start = 0; start < n; ++start) {
    if (mark[start] == 0 || seen[start]) continue;
    std::vector<std::size_t> members{start}; // local indices
    seen[start] = true;
    for (std::size_t q = 0; q < members.size(); ++q)
      for (std::size_t k : nb[members[q]])
        if (!seen[k] && mark[k] == mark[start]) {
          seen[k] = true;
          members.push_back(k);
        }
    if (members.size() < o.min_points) continue;
    std::sort(members.begin(), members.end());
    Extent e;
    double mean_abs = 0.0;
    FailingRegion g = measure_region(flank, p, members, mark[start], e, mean_abs);
    fit_tendency(g, p, members, e, mean_abs, sigma);
    put_into_words(g, members.size());
    regions.push_back(std::move(g));
  }
  std::stable_sort(regions.begin(), regions.end(), [](const FailingRegion& a, const FailingRegion& b) {
    return std::abs(a.extreme_um) > std::abs(b.extreme_um);
  });
  return regions;
}

} // namespace geartopo::diagnosis
