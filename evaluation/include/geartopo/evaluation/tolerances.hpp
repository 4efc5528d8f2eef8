// geartopo evaluation — ISO 1328-1:2013 flank tolerance classes: tolerance formulas (clause 5.3), rounding, range of
// validity (clause 1) and the class of a measured value. Sources and confidence labels: docs/iso1328.md.
//
// Units: d, m_n, b in mm; helix angle in rad; tolerances and values in µm.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace geartopo::evaluation {

/// The toleranced quantities.
enum class Quantity {
  SinglePitch,     ///< f_p   (tolerance f_pT)
  CumulativePitch, ///< F_p   (F_pT)
  ProfileSlope,    ///< f_Hα  (f_HαT), compared by absolute value
  ProfileForm,     ///< f_fα  (f_fαT)
  ProfileTotal,    ///< F_α   (F_αT)
  HelixSlope,      ///< f_Hβ  (f_HβT), compared by absolute value
  HelixForm,       ///< f_fβ  (f_fβT)
  HelixTotal,      ///< F_β   (F_βT)
  Runout,          ///< F_r   (F_rT = 0.9 F_pT, from one source only)
};

/// "f_p", "F_p", "f_Hα", … (UTF-8).
std::string_view symbol(Quantity q);

/// The gear data the tolerances depend on.
struct GearParameters {
  int teeth = 0;                     ///< z
  double reference_diameter_mm = 0;  ///< d
  double normal_module_mm = 0;       ///< m_n
  double face_width_mm = 0;          ///< b
  double helix_angle_rad = 0;        ///< β (signed; |β| is checked)
};

/// Why ISO 1328-1:2013 tolerances may not be applied to this gear (5 ≤ z ≤ 1000, 5 ≤ d ≤ 15000 mm,
/// 0.5 ≤ m_n ≤ 70 mm, 4 ≤ b ≤ 1200 mm, |β| ≤ 45°; not to be extrapolated), or nullopt if they may.
/// Every violated limit is named, separated by "; ".
std::optional<std::string> validity_refusal(const GearParameters& p);

/// Classes run 1..11; this value stands for "worse than class 11".
inline constexpr int kWorseThanClass11 = 12;
inline constexpr int kFinestClass = 1;
inline constexpr int kCoarsestClass = 11;

/// "5" for 1..11, "worse than 11" for kWorseThanClass11.
std::string class_label(int flank_class);
/// The same, and "–" when there is no class (ISO 1328-1 does not apply, or nothing was evaluated).
std::string class_label(const std::optional<int>& flank_class);

/// Rounding of clause 5.2.3 (as gathered, [C]): above 10 µm to whole µm; 5–10 µm to 0.5 µm; below 5 µm to 0.1 µm.
/// Ties round half up. Because decimal ties (4.95, 7.25, 10.5) are not exact in binary, a value within 1e-9 of a
/// rounding step below a tie counts as the tie. Throws std::invalid_argument for negative or non-finite values.
double round_tolerance_um(double unrounded_um);

/// Unrounded class-5 tolerance (the formulas of clause 5.3). F_αT, F_βT = √(slope² + form²) of unrounded values;
/// F_rT = 0.9 · F_pT.
double class5_tolerance_um(Quantity q, const GearParameters& p);

/// Unrounded tolerance of class A: class5 × (√2)^(A − 5).
double unrounded_tolerance_um(Quantity q, const GearParameters& p, int flank_class);

/// Rounded tolerance of class A (the value the class is judged by).
double tolerance_um(Quantity q, const GearParameters& p, int flank_class);

/// All rounded tolerances of one class.
struct ToleranceSet {
  int flank_class = 0;
  double f_pT_um = 0, F_pT_um = 0, f_HalphaT_um = 0, f_falphaT_um = 0, F_alphaT_um = 0, f_HbetaT_um = 0,
         f_fbetaT_um = 0, F_betaT_um = 0, F_rT_um = 0;
  double of(Quantity q) const;
};
ToleranceSet tolerances(const GearParameters& p, int flank_class);

/// Class of a measured value: the smallest A in 1..11 whose rounded tolerance ≥ |value|, else kWorseThanClass11.
int tolerance_class(Quantity q, double value_um, const GearParameters& p);

// All functions taking GearParameters throw std::domain_error carrying validity_refusal() when the gear is outside
// the range of validity, and std::invalid_argument for a class outside 1..11 or a non-finite value.

} // namespace geartopo::evaluation
