// geartopo evaluation — where a model of a ground gear fails against measurements (`geartopo compare`): named
// residual patterns per flank (offset, slopes, twist, crownings, waviness), their tooth-to-tooth trends, failing
// regions named in gear terms, and summary statistics. See docs/residual-patterns.md for the definitions and rules.
//
// Units: roll length ξ (profile direction, root → tip) and axial position z (from the datum face, into the gear) in
// mm; residuals (measured − model), pattern heights, standard errors and the noise level σ in µm along the flank
// normal, plus material positive; wavelengths in mm; angles and phases in rad.
//
// Evaluation ranges: every flank carries its L_α = [ξ0, ξ1] and L_β = [z0, z1]. Points outside them (by more than
// kRangeSlackMm) are left out of every evaluation here and counted; normalised coordinates are
// u = 2(ξ − ξ0)/(ξ1 − ξ0) − 1 and w = 2(z − z0)/(z1 − z0) − 1, both in [−1, 1].
//
// Every function throws std::invalid_argument with a message naming the reason for invalid input: non-finite values,
// no points, empty or non-finite ranges, tooth < 1, σ ≤ 0, or too few points to determine what is asked.
#pragma once

#include "geartopo/core/flank.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::evaluation {

using geartopo::to_string; // Flank (core/flank.hpp)

// ---------------------------------------------------------------------------------------------------------------------
// Input

/// One residual value on a flank.
struct ResidualPoint {
  double xi_mm = 0.0;       ///< roll length ξ (mm), increasing towards the tip
  double z_mm = 0.0;        ///< axial position (mm from the datum face)
  double residual_um = 0.0; ///< measured − model (µm, along the flank normal, plus material positive)
};

/// The residual of one measured flank. Points may be scattered; they often form the 7 × 9 grid.
struct FlankResiduals {
  int tooth = 1; ///< 1..z
  Flank side = Flank::Right;
  std::vector<ResidualPoint> points;
  double xi_start_mm = 0.0; ///< L_α start ξ0 (root end)
  double xi_end_mm = 0.0;   ///< L_α end ξ1 (tip end), ξ1 > ξ0
  double z_start_mm = 0.0;  ///< L_β start z0 (datum-face end)
  double z_end_mm = 0.0;    ///< L_β end z1 (far-face end), z1 > z0
};

/// A fitted value with its standard error (same unit), computed from the caller's σ and the design matrix.
struct Estimate {
  double value = 0.0;
  double standard_error = 0.0;
};

// ---------------------------------------------------------------------------------------------------------------------
// 1. Named patterns of one flank

/// The six polynomial patterns, in the order of the Legendre basis 1, u, w, u·w, P2(u), P2(w).
enum class NamedPattern { Offset, ProfileSlope, HelixSlope, Twist, ProfileCrowning, HelixCrowning };
inline constexpr std::array<NamedPattern, 6> kNamedPatterns{NamedPattern::Offset,          NamedPattern::ProfileSlope,
                                                            NamedPattern::HelixSlope,      NamedPattern::Twist,
                                                            NamedPattern::ProfileCrowning, NamedPattern::HelixCrowning};
/// "offset", "profile slope", "helix slope", "twist", "profile crowning", "helix crowning".
std::string_view to_string(NamedPattern p);

/// Direction of a waviness: Profile = a function of ξ only (along the profile), Helix = a function of z only.
enum class WaveDirection { Profile, Helix };
std::string_view to_string(WaveDirection d); ///< "along the profile (ξ)", "along the face width (z)"

/// A significant sinusoid along one direction x (ξ or z): A·cos(2π (x − x_start)/λ − φ), x_start = ξ0 or z0.
/// Amplitude and phase come from the final joint fit (Legendre terms + significant waves) at the found λ; their
/// standard errors hold λ fixed.
struct Waviness {
  WaveDirection direction = WaveDirection::Helix;
  Estimate amplitude_um;        ///< A ≥ 0 (µm): half the peak-to-valley height of the wave
  double wavelength_mm = 0.0;   ///< λ (mm)
  Estimate phase_rad;           ///< φ ∈ [0, 2π)
  double first_crest_mm = 0.0;  ///< x_start + φ λ/(2π): position (ξ or z, mm) of the first crest inside the range
  double chi2 = 0.0;            ///< ΔRSS/σ²: residual sum of squares removed by the wave, in units of σ²
  double variance_drop = 0.0;   ///< ΔRSS / RSS before the wave (fraction of what the other terms leave)
};

/// The periodogram scan along one direction. `wave` is set only when the strongest candidate passes both rules
/// (docs/residual-patterns.md): chi2 > chi2_threshold = 2 ln(M/α) and variance_drop ≥ the minimum fraction.
struct WavinessScan {
  WaveDirection direction = WaveDirection::Helix;
  bool scanned = false;            ///< false: fewer than 5 distinct positions or λ_min ≥ range length
  double min_wavelength_mm = 0.0;  ///< λ_min = 2 × largest spacing between neighbouring distinct positions, ≥ L/max_waves
  double max_wavelength_mm = 0.0;  ///< λ_max = range length
  std::size_t independent_wavelengths = 0; ///< M = max(1, 2⌈L (1/λ_min − 1/λ_max)⌉) (calibrated, see the doc)
  double chi2_threshold = 0.0;     ///< 2 ln(M/α)
  double best_wavelength_mm = 0.0; ///< strongest candidate, significant or not (0 if not scanned)
  double best_chi2 = 0.0;          ///< its ΔRSS/σ²
  double best_variance_drop = 0.0; ///< its ΔRSS / RSS before
  std::optional<Waviness> wave;    ///< the reported waviness, only when significant
};

struct PatternOptions {
  double noise_um = 0.0;                    ///< σ (µm) of one residual value, > 0 (given by the caller)
  double waviness_false_alarm = 1e-3;       ///< α: probability of reporting a waviness in pure noise, per direction
  double waviness_min_variance_drop = 0.10; ///< the wave must remove at least this fraction of the remaining RSS
  double waviness_oversampling = 10.0;      ///< frequency step of the scan = 1/(oversampling × range length), ≥ 1
  /// Shortest wavelength scanned ≥ range length / this (besides twice the largest gap between sampled positions):
  /// bounds the scan for scattered points (a point cloud has tiny gaps; the scan would grow with n²).
  double waviness_max_waves = 64.0;
};

/// Named patterns of one flank (least squares on the Legendre basis; docs/residual-patterns.md has the formulas).
struct FlankPatterns {
  int tooth = 1;
  Flank side = Flank::Right;
  double noise_um = 0.0;                ///< σ used for the standard errors and the waviness test
  std::size_t points_used = 0;          ///< points inside the evaluation ranges
  std::size_t points_outside_range = 0; ///< points left out
  /// Legendre coefficients (µm) of 1, u, w, u·w, (3u² − 1)/2, (3w² − 1)/2, in that order.
  std::array<Estimate, 6> legendre_um{};
  Estimate offset_um;           ///< a0: mean of the fitted surface over L_α × L_β (thickness/pitch offset)
  Estimate profile_slope_um;    ///< 2 a1: rise across L_α at mid face width (like f_Hα; > 0: more material at the tip)
  Estimate helix_slope_um;      ///< 2 a2: rise across L_β at mid profile (like f_Hβ; > 0: more material at the far face)
  Estimate twist_um;            ///< 4 a3: helix slope at the tip end of L_α minus helix slope at the root end
  Estimate profile_crowning_um; ///< −1.5 a4: middle of the profile above its ends (like C_α; > 0: barrel)
  Estimate helix_crowning_um;   ///< −1.5 a5: middle of the face width above its ends (like C_β; > 0: barrel)
  WavinessScan waviness_profile; ///< along ξ
  WavinessScan waviness_helix;   ///< along z
  double rms_residual_um = 0.0;    ///< RMS of the residual values used
  double rms_unexplained_um = 0.0; ///< RMS after removing the patterns and the reported waves
  double chi2_per_dof = 0.0;       ///< RSS/(σ² (N − parameters)); ≈ 1 when patterns + noise of σ explain all (0 if N = p)
};

/// Value of one named pattern.
Estimate pattern_value(const FlankPatterns& f, NamedPattern p);

/// Fits the named patterns and scans for waviness along z, then along ξ (with a significant z wave in the model),
/// then refits everything jointly. Needs ≥ 3 distinct ξ and ≥ 3 distinct z among ≥ 6 points in range (the six
/// polynomial terms must be determined); throws std::invalid_argument otherwise.
FlankPatterns fit_flank_patterns(const FlankResiduals& flank, const PatternOptions& options);

/// One line per pattern, e.g. "tooth 3, right flank: offset +1.20 ± 0.06 µm (thicker), profile slope …".
std::string describe_patterns(const FlankPatterns& f);

// ---------------------------------------------------------------------------------------------------------------------
// 2. Tooth-to-tooth trends of one side

enum class TrendKind {
  Constant,          ///< no change beyond the standard errors
  Difference,        ///< two teeth only, significantly different
  Linear,            ///< linear in tooth number
  OncePerRevolution, ///< c + A cos(θ_j − φ), θ_j = 2π (j − 1)/z
  Irregular          ///< varies beyond the standard errors, but neither trend is significant
};
std::string_view to_string(TrendKind k);

/// How one named pattern changes with tooth number. Fields that do not apply to the number of teeth stay 0/false.
struct PatternTrend {
  NamedPattern pattern = NamedPattern::Offset;
  TrendKind kind = TrendKind::Constant;
  std::size_t teeth = 0;
  Estimate mean_um;              ///< inverse-variance weighted mean
  double chi2_constant = 0.0;    ///< Σ ((y_j − mean)/s_j)² of the constant model
  int tooth_a = 0, tooth_b = 0;  ///< two teeth: lower and higher tooth number
  Estimate difference_um;        ///< two teeth: y_b − y_a
  Estimate slope_um_per_tooth;   ///< ≥ 3 teeth: weighted linear fit against tooth number
  bool linear_significant = false;
  bool sinusoid_fitted = false;  ///< ≥ 3 teeth whose angles determine c, a, b
  Estimate amplitude_um;         ///< A ≥ 0
  Estimate phase_rad;            ///< φ ∈ [0, 2π): the tooth angle where the pattern is largest
  double max_at_tooth = 0.0;     ///< 1 + φ z/(2π) (fractional tooth number)
  bool sinusoid_significant = false;
  bool scatter_beyond_model = false; ///< residual χ² of the chosen model still exceeds its 1 − p quantile
  std::string sentence;
};

struct TrendOptions {
  double significance_sigmas = 3.0; ///< k: tests at the two-sided normal tail p = erfc(k/√2) (0.27 % for k = 3)
};

struct SideTrends {
  Flank side = Flank::Right;
  int teeth_in_gear = 0;
  std::vector<int> teeth;             ///< ascending
  std::array<PatternTrend, 6> trends; ///< indexed like kNamedPatterns
};

/// Trends of the six named patterns over the given flanks (all of one side, distinct teeth in 1..teeth_in_gear, at
/// least 2). Throws std::invalid_argument otherwise, or for teeth_in_gear < 2 or non-finite/zero standard errors.
SideTrends fit_tooth_trends(std::span<const FlankPatterns> flanks, int teeth_in_gear, const TrendOptions& options = {});

// ---------------------------------------------------------------------------------------------------------------------
// 3. Failing regions

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

// ---------------------------------------------------------------------------------------------------------------------
// 4. Summary statistics

struct ResidualStats {
  std::size_t points = 0;
  double rms_um = 0.0;     ///< √(Σ r²/N) over all pooled points
  double max_abs_um = 0.0; ///< max |r|
  double extreme_um = 0.0; ///< the signed r with max |r|
  int extreme_tooth = 0;
  Flank extreme_side = Flank::Right;
  double extreme_xi_mm = 0.0, extreme_z_mm = 0.0;
};
struct FlankStats {
  int tooth = 1;
  Flank side = Flank::Right;
  std::size_t points_outside_range = 0;
  ResidualStats stats;
};
struct ToothStats {
  int tooth = 1;
  ResidualStats stats; ///< both flanks pooled
};
struct SideStats {
  Flank side = Flank::Right;
  std::size_t flanks = 0;
  ResidualStats stats;
};
struct ResidualSummary {
  std::vector<FlankStats> flanks; ///< by tooth, left before right
  std::vector<ToothStats> teeth;  ///< ascending tooth
  std::vector<SideStats> sides;   ///< left, right (present sides only)
  ResidualStats overall;
};

/// RMS and max |residual| per flank, tooth, side and overall (points inside the evaluation ranges). Throws
/// std::invalid_argument for no flanks, a repeated (tooth, side) or an invalid flank.
ResidualSummary summarize_residuals(std::span<const FlankResiduals> flanks);

} // namespace geartopo::evaluation
