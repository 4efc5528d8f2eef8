// geartopo — a twist of the chain's workpiece frame referred to the gear's datum frame (docs/machine-model.md §9).
// The chain's workpiece frame w has its origin on the C table's face; the gear's frame (the datum face, where the
// path's z = 0 lies) is z₀ = datum_face_z_mm above it along z. A twist (v over ω, 6-vector, mm and rad) whose point of
// reference is w's origin moves to the datum by Tz(−z₀): v' = v + p × ω with p = (0, 0, −z₀), ω unchanged.
// Units: mm, rad.
#pragma once

#include "geartopo/machine/twist.hpp"

namespace geartopo::machine {

/// ξ with its point of reference moved from the chain's workpiece frame to the gear's datum face z₀ above it.
Vector6d twist_at_datum(const Vector6d& xi_w, double datum_face_z_mm);

/// Every column of J (6 × n: twists, e.g. J_twistw_e or J_twistw_θ) moved the same way.
template <typename Derived>
void twists_at_datum(Eigen::MatrixBase<Derived>& J, double datum_face_z_mm) {
  for (Eigen::Index k = 0; k < J.cols(); ++k) J.col(k) = twist_at_datum(J.col(k), datum_face_z_mm);
}

} // namespace geartopo::machine
