#include "app/parsers.hpp"

#include "geartopo/grinding/topology.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>

namespace geartopo::app {

namespace {

bool parse_int(const std::string& s, int& v) {
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

} // namespace

std::vector<int> parse_teeth(const std::string& text, int teeth) {
  // "" used to mean all teeth: an empty list is far more likely a script's empty variable than a wish for all.
  if (text.empty()) throw CLI::ValidationError("--teeth", "an empty list (use e.g. 1,18 or all)");
  if (text == "all") return {};
  std::vector<int> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    int v = 0;
    if (!parse_int(item, v) || v < 1 || v > teeth)
      throw CLI::ValidationError("--teeth", fmt::format("'{}' is not a tooth number of 1..{} (use e.g. 1,18 or all)", item, teeth));
    if (std::find(out.begin(), out.end(), v) != out.end())
      throw CLI::ValidationError("--teeth", fmt::format("tooth {} is listed twice", v));
    out.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::pair<int, int> parse_grid_size(const std::string& text) {
  const auto x = text.find('x');
  int r = 0, c = 0;
  if (x == std::string::npos || !parse_int(text.substr(0, x), r) || !parse_int(text.substr(x + 1), c) || r < 2 || c < 2 ||
      static_cast<long long>(r) * c > grinding::kMaxPointsPerFlank)
    throw CLI::ValidationError("--dense", fmt::format("'{}' is not ROWSxCOLS with 2 ≤ each and at most {} points per flank",
                                                      text, grinding::kMaxPointsPerFlank));
  return {r, c};
}

void add_iso_options(CLI::App* cmd, workbench::IsoOptions& o) {
  // Through the words (evaluation's parse_… functions): CLI11 cannot bind these enums directly, their to_string
  // overloads (string_view) confuse its default-value printing.
  cmd->add_option_function<std::string>(
         "--iso-direction", [&o](const std::string& w) { o.direction = *evaluation::parse_iso_direction(w); },
         "ISO 1328-1 profile/helix deviations transverse (default: the standard's, normal / cos β_b) or normal")
      ->check(CLI::IsMember({"transverse", "normal"}))
      ->option_text("transverse|normal");
  cmd->add_option_function<std::string>(
         "--helix-slope-sign", [&o](const std::string& w) { o.helix_slope_sign = *evaluation::parse_helix_slope_sign(w); },
         "Sign of f_Hβ: helix-angle (default; > 0 when the helix angle is larger than designed) or "
         "rise-towards-plus-z (> 0 when material rises away from the datum face)")
      ->check(CLI::IsMember({"helix-angle", "rise-towards-plus-z"}))
      ->option_text("helix-angle|rise-towards-plus-z");
}

} // namespace geartopo::app
