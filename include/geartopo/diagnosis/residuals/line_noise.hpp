// geartopo diagnosis — the probe noise σ of a measurement estimated from its measured lines' own point-to-point scatter
// (docs/residual-patterns.md, "Noise"), and where profile and helix lines of a flank disagree where they cross.
// Units: mm (ξ, z), µm (residuals, σ).
#pragma once

#include "geartopo/diagnosis/residuals/flank_residuals.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace geartopo::diagnosis {

/// A measured line is the points of one flank that share z (a profile line) or ξ (a helix line) within 1 µm, in order
/// of the other coordinate. A dense line has at least this many distinct positions: enough that the signal changes
/// smoothly from point to point, so its second differences are noise (a grid's 7 or 9 points per line are not).
inline constexpr std::size_t kDenseLinePoints = 20;

struct LineNoise {
  double sigma_um = 0.0;       ///< robust σ: 1.4826 × MAD of the normalised, curvature-corrected second differences
  std::size_t lines = 0;       ///< dense lines used
  std::size_t differences = 0; ///< second differences pooled
};

/// σ from the dense lines of the flanks (their ranges are not used): along each line, sorted by position x, the
/// second difference e_i = r_i − (w r_{i−1} + (1 − w) r_{i+1}), w = (x_{i+1} − x_i)/(x_{i+1} − x_{i−1}), annihilates
/// a straight line at any spacing and has variance σ² (1 + w² + (1 − w)²) for independent noise: divided by that
/// root. A curvature f'' adds −f'' h_a h_b / 2 (h_a, h_b the two spacings): one f'' per line, the median of the ratios,
/// is removed. The pooled differences' MAD × 1.4826 is σ for Gaussian noise and ignores the few differences a step or a
/// spike spoils. lines = 0 (σ 0) when no flank has a dense line.
LineNoise line_noise_um(std::span<const FlankResiduals> flanks);

/// The dense lines of a flank: profile lines (sharing z) and helix lines (sharing ξ).
struct DenseLineCount {
  std::size_t profile = 0, helix = 0;
};
DenseLineCount dense_line_count(const FlankResiduals& flank);

/// Where a profile line (z = z_p) and a helix line (ξ = ξ_h) of one flank cross inside both, each line's value
/// interpolated linearly there: profile − helix (µm). Both measure the same point of the flank.
struct LineCrossing {
  double xi_mm = 0.0, z_mm = 0.0;
  double profile_um = 0.0, helix_um = 0.0;
};

/// The crossings of a flank's dense profile and helix lines (dense: kDenseLinePoints).
std::vector<LineCrossing> line_crossings(const FlankResiduals& flank);

} // namespace geartopo::diagnosis
