// geartopo — a value and its standard uncertainty as text for a reader, rounded per GUM (JCGM 100:2008) §7.2.6: the
// uncertainty to two significant digits, the value to the same decimal place ("24.4 ± 5.4", "0 ± 110"). For screens
// and reports only: files that are read back (JSON, YAML) keep full precision. Unit-free: the caller's unit.
// [M] §7.2.6 is quoted from a secondary source ("quote u_c(y) to at most two significant digits … output estimates
// should be rounded to be consistent with their uncertainties"); the GUM itself was not read for this work.
#pragma once

#include <string>

namespace geartopo::text {

/// "value ± u" rounded per GUM §7.2.6 (to nearest): u = 1.09e2 → "0 ± 110" for value −0.2223; 0.05696 ± 0.00384 →
/// "0.0570 ± 0.0038"; explicit_plus prints a sign before a positive value ("+2.00 ± 0.06"). Without a positive finite u
/// (a parameter held fixed, an undefined σ) the value is given to 4 significant digits and u as it is ("3.142 ± 0").
std::string with_uncertainty(double value, double u, bool explicit_plus = false);

} // namespace geartopo::text
