#include "app/options.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "geartopo/grinding/topology.hpp"

#include <charconv>
#include <map>

namespace geartopo::app {

namespace {
bool parse_int(const std::string& s, int& v) {
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}
} // namespace

std::vector<int> parse_teeth(const std::string& text, int teeth) {
  if (text.empty() || text == "all") return {};
  std::vector<int> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    int v = 0;
    if (!parse_int(item, v) || v < 1 || v > teeth)
      throw CLI::ValidationError("--teeth", fmt::format("'{}' is not a tooth number of 1..{} (use e.g. 1,18 or all)", item, teeth));
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

void add_klingelnberg_options(CLI::App* cmd, diagnosis::KlingelnbergOptions& o) {
  using diagnosis::DeviationDirection;
  using diagnosis::ProfileSpacing;
  using diagnosis::SignConvention;
  cmd->add_option("--mka-spacing", o.spacing,
                  "Klingelnberg export: profile points evenly in roll-length (default) or diameter")
      ->transform(CLI::CheckedTransformer(std::map<std::string, ProfileSpacing>{{"roll-length", ProfileSpacing::RollLength},
                                                                                {"diameter", ProfileSpacing::Diameter}}))
      ->option_text("roll-length|diameter");
  cmd->add_option("--mka-direction", o.direction,
                  "Klingelnberg export: deviations transverse (default; × cos β_b to the normal) or normal")
      ->transform(CLI::CheckedTransformer(std::map<std::string, DeviationDirection>{
          {"transverse", DeviationDirection::Transverse}, {"normal", DeviationDirection::Normal}}))
      ->option_text("transverse|normal");
  cmd->add_option("--mka-signs", o.signs,
                  "Klingelnberg export: raw probe sign (default; profile left and helix × −1) or din (plus material)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, SignConvention>{{"raw", SignConvention::Raw},
                                                                                {"din", SignConvention::Din}}))
      ->option_text("raw|din");
}

} // namespace geartopo::app
