// geartopo evaluation — left and right flanks (DIN ISO 21771; docs/conventions.md, docs/iso1328.md).
// Seen from the datum face with the tooth tip up, the left flank is on the left. Teeth are numbered 1..z in the
// positive angular sense θ about +z; the right flank of a tooth faces +θ, the left flank −θ.
// No units here.
#pragma once

#include <string_view>

namespace geartopo::evaluation {

enum class Side { Left, Right };

/// σ = +1 for the right flank (faces +θ), −1 for the left flank (faces −θ).
constexpr int side_sign(Side s) { return s == Side::Right ? +1 : -1; }

constexpr std::string_view to_string(Side s) { return s == Side::Right ? "right" : "left"; }

} // namespace geartopo::evaluation
