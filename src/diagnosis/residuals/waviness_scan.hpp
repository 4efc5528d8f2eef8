// geartopo diagnosis, private — the periodogram scan for one sinusoid along ξ or z (waviness.hpp,
// docs/residual-patterns.md "Waviness"), used by the flank pattern fit. Units: mm (positions, wavelengths), µm.
#pragma once

#include "geartopo/diagnosis/residuals/flank_patterns.hpp"

#include <Eigen/Dense>

#include <vector>

namespace geartopo::diagnosis::residuals {

/// The design matrix A (n × p) with the cos and sin columns of a wave of wavelength λ (mm) along x (relative to x0)
/// appended: n × (p + 2).
Eigen::MatrixXd with_wave(const Eigen::MatrixXd& A, const std::vector<double>& x, double x0, double lambda);

/// Scans wavelengths along x (ξ or z, mm; range [x0, x1]) for the single sinusoid that removes the most RSS from the
/// base model (design matrix `base`, n × p, kept in the fit) of the residuals y (µm, n); σ in µm. The wave is set only
/// when it passes both detection rules; its amplitude and phase are left for the caller's joint fit.
WavinessScan scan_waviness(WaveDirection dir, const Eigen::MatrixXd& base, const Eigen::VectorXd& y,
                           const std::vector<double>& x, double x0, double x1, double sigma, const PatternOptions& o);

} // namespace geartopo::diagnosis::residuals
