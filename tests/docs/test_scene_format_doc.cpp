// Issue 17: docs/scene-format.md documents every effect a scene may list — type, parameter keys with their units,
// defaults and allowed ranges — as the library defines them. The table the document must hold is printed on failure.
#include "geartopo/effects/custom_effect.hpp"
#include "geartopo/effects/registry.hpp"

#include <gtest/gtest.h>
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

std::string effects_section_of_scene_format() {
  std::ifstream in(std::filesystem::path(GEARTOPO_SOURCE_DIR) / "docs" / "scene-format.md");
  std::stringstream s;
  s << in.rdbuf();
  const std::string text = s.str();
  const auto start = text.find("## `effects`");
  if (start == std::string::npos) return {};
  const auto end = text.find("\n## ", start + 1);
  return text.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

} // namespace

TEST(SceneFormatDoc, ListsEveryEffectParameterWithItsDefaultAndRange) {
  using namespace geartopo;
  const std::string section = effects_section_of_scene_format();
  std::string table = "| `type` | key | meaning | default | allowed | diagnose |\n|---|---|---|---|---|---|\n";
  std::vector<std::string> missing;
  for (const auto& type : effects::effect_types()) {
    const auto effect = effects::make_effect(type);
    ASSERT_TRUE(effect);
    for (const auto& p : effect->parameters()) {
      const std::string row = fmt::format("| `{}` | `{}` | {} | {:g} | [{:g}, {:g}] | {} |", type, p.key, p.meaning,
                                          p.default_value, p.lo, p.hi, p.fitted ? "fitted" : "set-up value, not fitted");
      table += row + "\n";
      if (section.find(row) == std::string::npos) missing.push_back(row);
    }
  }
  EXPECT_TRUE(missing.empty()) << "docs/scene-format.md, section \"## `effects`\", lacks " << missing.size()
                               << " row(s), e.g.\n" << (missing.empty() ? "" : missing.front()) << "\nThe table:\n" << table;
}

// Issue 40: every variable a custom law may use is defined in docs/scene-format.md, section "## `custom_effects`", as
// a row of its variables table.
TEST(SceneFormatDoc, DefinesEveryVariableOfACustomLaw) {
  std::ifstream in(std::filesystem::path(GEARTOPO_SOURCE_DIR) / "docs" / "scene-format.md");
  std::stringstream s;
  s << in.rdbuf();
  const std::string text = s.str();
  const auto start = text.find("## `custom_effects`");
  ASSERT_NE(start, std::string::npos) << "docs/scene-format.md has no custom_effects section";
  const std::string section = text.substr(start, text.find("\n## ", start + 1) - start);
  for (const auto& name : geartopo::effects::kContactVariableNames)
    EXPECT_NE(section.find(fmt::format("`{}`", name)), std::string::npos) << name << " is not defined in the section";
}
