// geartopo — left and right flanks (DIN ISO 21771 / ISO 1328-1, see docs/conventions.md).
// Seen from the datum face with the tooth tip up, the left flank is on the left. In the workpiece frame
// (z into the gear from the datum face) the right flank of a tooth faces +θ (towards the next tooth number),
// the left flank faces −θ.
#pragma once

#include <optional>
#include <string_view>

namespace geartopo {

enum class Flank { Left, Right };

/// +1 for the right flank (faces +θ), −1 for the left flank (faces −θ).
constexpr int side_sign(Flank f) { return f == Flank::Right ? +1 : -1; }

constexpr std::string_view to_string(Flank f) { return f == Flank::Right ? "right" : "left"; }

/// "left" / "right" → Flank; anything else → nullopt.
inline std::optional<Flank> parse_flank(std::string_view s) {
  if (s == "left") return Flank::Left;
  if (s == "right") return Flank::Right;
  return std::nullopt;
}

} // namespace geartopo
