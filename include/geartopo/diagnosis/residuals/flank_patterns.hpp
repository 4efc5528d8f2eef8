// geartopo diagnosis — the named patterns of one flank's residual (offset, slopes, twist, crownings, waviness) with
// standard errors: least squares on the Legendre basis plus significant waves (docs/residual-patterns.md, section 1).
// Units: µm (patterns, σ, standard errors), mm (ξ, z, wavelengths), rad.
#pragma once

#include "geartopo/diagnosis/residuals/flank_residuals.hpp"
#include "geartopo/diagnosis/residuals/waviness.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace geartopo::diagnosis {

/// The six polynomial patterns, in the order of the Legendre basis 1, u, w, u·w, P2(u), P2(w).
enum class NamedPattern { Offset, ProfileSlope, HelixSlope, Twist, ProfileCrowning, HelixCrowning };
inline constexpr std::array<NamedPattern, 6> kNamedPatterns{NamedPattern::Offset,          NamedPattern::ProfileSlope,
                                                            NamedPattern::HelixSlope,      NamedPattern::Twist,
                                                            NamedPattern::ProfileCrowning, NamedPattern::HelixCrowning};
/// "offset", "profile slope", "helix slope", "twist", "profile crowning", "helix crowning".
std::string_view to_string(NamedPattern p);


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

} // namespace geartopo::diagnosis
