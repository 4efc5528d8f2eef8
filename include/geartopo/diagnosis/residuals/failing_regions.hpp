// geartopo diagnosis — where the model fails: connected groups of points with |residual| > k σ of one sign, named in
// gear terms (root/tip third, near the datum face, …) with their tendency (docs/residual-patterns.md, section 3).
// Units: µm (residuals, σ), mm (ξ, z).
#pragma once

#include "geartopo/diagnosis/residuals/flank_residuals.hpp"

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::diagnosis {

enum class ProfileZone { RootThird, Middle, TipThird, RootHalf, TipHalf, Whole };
enum class AxialZone { DatumFaceEnd, Middle, FarFaceEnd, DatumFaceHalf, FarFaceHalf, Whole };
enum class ProfileGrowth { None, TowardsTip, TowardsRoot };
enum class AxialGrowth { None, TowardsDatumFace, TowardsFarFace };
/// "root third", "middle of the profile", "tip third", "root half", "tip half", "whole profile".
std::string_view to_string(ProfileZone z);
/// "near the datum face", "mid face width", "near the far face", "half towards the datum face",
/// "half towards the far face", "whole face width".
std::string_view to_string(AxialZone z);

struct RegionOptions {
  double noise_um = 0.0;     ///< σ (µm), > 0
  double k = 3.0;            ///< a point fails when |residual| > k σ; k > 0
  std::size_t min_points = 1; ///< regions with fewer points are dropped
};

/// A connected group of failing points of one sign on one flank.
struct FailingRegion {
  int tooth = 1;
  Flank side = Flank::Right;
  std::vector<std::size_t> point_indices; ///< into FlankResiduals::points, ascending
  int sign = +1;                          ///< +1 plus material (thicker), −1 minus material (thinner)
  double extreme_um = 0.0;                ///< signed residual of largest |residual|
  std::size_t extreme_index = 0;          ///< its point index
  double extreme_xi_mm = 0.0, extreme_z_mm = 0.0;
  double mean_um = 0.0;                   ///< mean residual of the region
  double xi_min_mm = 0.0, xi_max_mm = 0.0, z_min_mm = 0.0, z_max_mm = 0.0; ///< extent of its points
  ProfileZone profile_zone = ProfileZone::Whole;
  AxialZone axial_zone = AxialZone::Whole;
  ProfileGrowth profile_growth = ProfileGrowth::None;
  AxialGrowth axial_growth = AxialGrowth::None;
  bool peaked = false;                     ///< no growth, but a local bump/hollow well above noise
  double change_along_profile_um = 0.0;    ///< fitted change of |residual| over the region's ξ extent (+: towards tip)
  double change_along_face_um = 0.0;       ///< fitted change of |residual| over its z extent (+: towards far face)
  std::string words;    ///< e.g. "tip third, near the datum face, thicker, growing towards the datum face"
  std::string sentence; ///< e.g. "tooth 18, right flank, tip third, near the datum face: thicker (plus material), …"
};

/// Marks points with |residual| > k σ, groups them (same sign; 8-neighbours on a grid, else proximity) and names each
/// region. Sorted by |extreme| descending. Empty when nothing fails.
std::vector<FailingRegion> find_failing_regions(const FlankResiduals& flank, const RegionOptions& options);

} // namespace geartopo::diagnosis
