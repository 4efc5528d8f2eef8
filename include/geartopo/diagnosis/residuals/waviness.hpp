// geartopo diagnosis — waviness of a flank's residual: one sinusoid along the profile (ξ) or along the face width (z),
// found by a periodogram scan and reported only when significant (docs/residual-patterns.md, "Waviness").
// Units: positions and wavelengths mm, amplitudes µm, phases rad.
#pragma once

#include "geartopo/diagnosis/residuals/flank_residuals.hpp"

#include <cstddef>
#include <optional>
#include <string_view>

namespace geartopo::diagnosis {

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
  bool scanned = false;            ///< false: fewer than 5 distinct positions or λ_min ≥ range length, or (traces)
                                   ///< no dense line along this direction
  bool no_dense_line = false;      ///< traces measured, but none along this direction: not scanned
  double min_wavelength_mm = 0.0;  ///< λ_min = 2 × largest spacing between neighbouring distinct positions, ≥ L/max_waves
  double max_wavelength_mm = 0.0;  ///< λ_max = range length
  std::size_t independent_wavelengths = 0; ///< M = max(1, 2⌈L (1/λ_min − 1/λ_max)⌉) (calibrated, see the doc)
  double chi2_threshold = 0.0;     ///< 2 ln(M/α)
  double best_wavelength_mm = 0.0; ///< strongest candidate, significant or not (0 if not scanned)
  double best_chi2 = 0.0;          ///< its ΔRSS/σ²
  double best_variance_drop = 0.0; ///< its ΔRSS / RSS before
  std::optional<Waviness> wave;    ///< the reported waviness, only when significant
};

} // namespace geartopo::diagnosis
