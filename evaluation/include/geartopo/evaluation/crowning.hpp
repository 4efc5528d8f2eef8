// geartopo evaluation — crowning C_α / C_β of one trace (the Klingelnberg/ISO/TR 10064-1 style quantity printed beside
// F, f_f and f_H; definition and its source status in docs/iso1328.md, "Crowning").
//
// Units: positions mm, deviations µm (along the flank normal, plus material positive).
#pragma once

#include "geartopo/evaluation/trace.hpp"

namespace geartopo::evaluation {

/// Crowning of a trace over its evaluation range: the least-squares parabola d(s) = a + b·s + c·s² of the points
/// inside the range (s the position), and C = the height of that parabola at the middle of the range above the chord
/// through its values at the two range ends: C = −c·(L/2)² for a range of length L. C > 0: the flank is fuller in the
/// middle (barrelled, crowned); C < 0: hollow. Independent of any offset or linear slope of the trace.
/// Throws std::invalid_argument like evaluate_trace (bad trace, range not covered, fewer than 3 points inside).
double crowning_um(const Trace& trace);

} // namespace geartopo::evaluation
