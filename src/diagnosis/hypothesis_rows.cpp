#include "geartopo/diagnosis/hypothesis_rows.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace geartopo::diagnosis {

std::vector<HypothesisRow> hypothesis_rows(const Diagnosis& d) {
  std::vector<HypothesisRow> rows;
  std::vector<std::string> placed; // every member of an earlier row's class
  for (const auto& h : d.hypotheses) {
    if (std::find(placed.begin(), placed.end(), h.name()) != placed.end()) continue;
    rows.push_back({&h, h.equivalent});
    placed.insert(placed.end(), h.equivalent.begin(), h.equivalent.end());
  }
  return rows;
}

std::string members_text(const HypothesisRow& row, std::size_t shown) {
  const auto& m = row.members;
  if (m.empty()) return {};
  const std::string listed =
      m.size() <= shown ? fmt::format("{}", fmt::join(m, ", "))
                        : fmt::format("{} and {} more (all in diagnosis.json, \"equivalent\")",
                                      fmt::join(m.begin(), m.begin() + static_cast<long>(shown), ", "), m.size() - shown);
  return fmt::format("one class with {} (the data cannot tell them apart)", listed);
}

} // namespace geartopo::diagnosis
