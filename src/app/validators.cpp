#include "app/validators.hpp"

#include "geartopo/core/text_field.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>

namespace geartopo::app {

CLI::Validator finite_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0.0;
        const char* end = text.data() + text.size();
        const auto [p, ec] = std::from_chars(text.data(), end, v);
        if (ec != std::errc() || p != end) return fmt::format("'{}' is not a number", text);
        if (!std::isfinite(v)) return fmt::format("'{}' is not a finite number", text);
        if (v < lo || v > hi) return fmt::format("{} is outside [{}, {}]", text, lo, hi);
        return {};
      },
      fmt::format("FINITE in [{}, {}]", lo, hi));
}

CLI::Validator probe_sigma_um() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        const char* end = text.data() + text.size();
        const auto [p, ec] = std::from_chars(text.data(), end, v);
        if (ec != std::errc() && ec != std::errc::result_out_of_range) return fmt::format("'{}' is not a number", text::excerpt(text));
        if (p != end) return fmt::format("'{}' is not a number", text::excerpt(text));
        if (ec == std::errc::result_out_of_range || !std::isfinite(v) || v < kMinProbeSigmaUm || v > kMaxProbeSigmaUm)
          return fmt::format("{} µm is not a probe noise σ: {:g} … {:g} µm (below {:g} µm no probe measures, and the "
                             "fit's Σr²/σ² would overflow)",
                             text::excerpt(text), kMinProbeSigmaUm, kMaxProbeSigmaUm, kMinProbeSigmaUm);
        return {};
      },
      fmt::format("σ in [{:g}, {:g}] µm", kMinProbeSigmaUm, kMaxProbeSigmaUm));
}

CLI::Validator non_empty_path() {
  return CLI::Validator([](std::string& text) -> std::string { return text.empty() ? "an empty path" : ""; }, "PATH");
}

CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
          return fmt::format("'{}' is not a whole number of 0 … 2⁶⁴ − 1", text::excerpt(text));
        // CLI11 would wrap 2⁶⁴ to 0 (and anything larger to something else): a seed must be what was written.
        std::uint64_t v = 0;
        if (text::parse_number(text, v) != std::errc())
          return fmt::format("'{}' is beyond 2⁶⁴ − 1 = {}, the largest seed", text::excerpt(text),
                             std::numeric_limits<std::uint64_t>::max());
        return {};
      },
      "UINT64");
}

} // namespace geartopo::app
