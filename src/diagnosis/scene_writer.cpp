#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_file.hpp"
#include <fstream>

#include "geartopo/effects/registry.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "custom_entry_writer.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sstream>
#include <stdexcept>

namespace geartopo::diagnosis {

namespace {

/// The `draws` block of an effect (docs/scene-format.md, "Effects drawn from a posterior"): the keys of the values the
/// sets move (a value held at the item's own in every set is left out: the reader puts it back) and one flow list per
/// set, 6 significant digits.
std::string draws_yaml(const effects::Effect& e, const std::vector<double>& values, const Eigen::MatrixXd& sets) {
  const auto& params = e.parameters();
  std::vector<size_t> column;
  std::vector<std::string> keys;
  for (size_t k = 0; k < params.size() && k < values.size() && static_cast<Eigen::Index>(k) < sets.cols(); ++k)
    if (params[k].fitted && !params[k].whole && (sets.col(static_cast<Eigen::Index>(k)).array() != values[k]).any())
      column.push_back(k), keys.push_back(params[k].key);
  if (column.empty()) return {}; // every set is the item itself: the effect is exact
  std::string out = fmt::format("    # {} equally likely value sets of the fit's posterior: its single values are not "
                                "determined (docs/diagnosis.md)\n", sets.rows());
  out += fmt::format("    draws:\n      keys: [{}]\n      sets:\n", fmt::join(keys, ", "));
  for (Eigen::Index i = 0; i < sets.rows(); ++i) {
    std::vector<std::string> row;
    for (const size_t k : column) row.push_back(fmt::format("{:.6g}", sets(i, static_cast<Eigen::Index>(k))));
    out += fmt::format("        - [{}]\n", fmt::join(row, ", "));
  }
  return out;
}

bool has_sets(const std::vector<Eigen::MatrixXd>& draws, size_t effect) {
  return effect < draws.size() && draws[effect].rows() > 0;
}

} // namespace

std::string effects_yaml_items(const std::vector<scene::EffectSpec>& effects, const std::vector<std::string>& comments,
                               const std::vector<std::vector<double>>& uncertainties, const Eigen::MatrixXd& correlation,
                               const std::vector<Eigen::MatrixXd>& draws) {
  // Every value's effect and key, in order: the correlation's rows and columns.
  std::vector<std::pair<size_t, std::string>> slots;
  for (size_t i = 0; i < effects.size(); ++i)
    for (const auto& p : effects::make_effect(effects[i].type)->parameters()) slots.emplace_back(i, p.key);
  const auto n = static_cast<Eigen::Index>(slots.size());
  const bool correlated = correlation.rows() == n && correlation.cols() == n && n > 0;
  std::string out;
  Eigen::Index at = 0;
  for (size_t i = 0; i < effects.size(); ++i) {
    const auto e = effects::make_effect(effects[i].type);
    const auto& params = e->parameters();
    if (i < comments.size() && !comments[i].empty()) out += "  # " + comments[i] + "\n";
    out += "  - type: " + effects[i].type + "\n";
    for (size_t k = 0; k < params.size(); ++k) out += fmt::format("    {}: {:.6g}\n", params[k].key, effects[i].values[k]);
    if (has_sets(draws, i)) { // the sets are its whole distribution: no uncertainty, no correlation of its own
      out += draws_yaml(*e, effects[i].values, draws[i]);
      at += static_cast<Eigen::Index>(params.size());
      continue;
    }
    std::vector<std::string> us;
    for (size_t k = 0; i < uncertainties.size() && k < uncertainties[i].size() && k < params.size(); ++k)
      if (uncertainties[i][k] > 0.0) us.push_back(fmt::format("{}: {:.6g}", params[k].key, uncertainties[i][k]));
    if (!us.empty()) out += fmt::format("    uncertainty: {{{}}}\n", fmt::join(us, ", "));
    std::vector<std::string> pairs;
    for (Eigen::Index a = at; correlated && a < at + static_cast<Eigen::Index>(params.size()); ++a)
      for (Eigen::Index b = a + 1; b < n; ++b) {
        if (correlation(a, b) == 0.0) continue;
        const auto& [eb, key_b] = slots[static_cast<size_t>(b)];
        if (has_sets(draws, eb)) continue;
        pairs.push_back(fmt::format("[{}, {}, {:.6g}]", slots[static_cast<size_t>(a)].second,
                                    eb == i ? key_b : effects[eb].type + "." + key_b, correlation(a, b)));
      }
    if (!pairs.empty()) out += fmt::format("    correlation: [{}]\n", fmt::join(pairs, ", "));
    at += static_cast<Eigen::Index>(params.size());
  }
  return out;
}

namespace {

/// `text` with `items` appended to its top-level list `key` (created at the end if absent).
std::string with_list_items(const std::string& text, const std::string& key, const std::string& items) {
  // Find a top-level "<key>:" line; its block ends at the next top-level key (a line starting with a letter).
  std::istringstream in(text);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  size_t start = lines.size();
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].rfind(key + ":", 0) == 0) start = i;
  std::string out;
  if (start == lines.size()) {
    out = text;
    if (!out.empty() && out.back() != '\n') out += "\n";
    return out + "\n" + key + ":\n" + items;
  }
  size_t end = start + 1;
  while (end < lines.size() && (lines[end].empty() || lines[end][0] == ' ' || lines[end][0] == '#' || lines[end][0] == '-'))
    ++end;
  // Keep trailing blank or comment lines of the block after the insertion.
  size_t insert = end;
  while (insert > start + 1 && (lines[insert - 1].empty() || lines[insert - 1][0] == '#')) --insert;
  for (size_t i = 0; i < insert; ++i) out += lines[i] + "\n";
  if (lines[start].find('[') != std::string::npos || lines[start].find('{') != std::string::npos) {
    // Flow style: only an empty list can be rewritten as a block without losing anything.
    if (lines[start].find("[]") == std::string::npos)
      throw std::runtime_error("the scene's " + key + " list is in flow style ([...]): write it as a block list to add to it");
    out.erase(out.size() - lines[start].size() - 1);
    out += key + ":\n";
  }
  out += items;
  for (size_t i = insert; i < lines.size(); ++i) out += lines[i] + "\n";
  return out;
}

} // namespace

std::string scene_with_effects(const std::string& text, const std::vector<scene::EffectSpec>& effects,
                               const std::vector<std::string>& comments,
                               const std::vector<std::vector<double>>& uncertainties, const Eigen::MatrixXd& correlation,
                               const std::vector<Eigen::MatrixXd>& draws) {
  // The user's own effects go back into their entries; the library's are appended, with the correlation among their
  // values and value sets (the correlation between a library effect's value and a custom effect's is not written, nor
  // value sets for a custom effect: docs/scene-format.md).
  std::vector<Eigen::Index> first(effects.size() + 1, 0);
  for (size_t i = 0; i < effects.size(); ++i) first[i + 1] = first[i] + static_cast<Eigen::Index>(effects[i].values.size());
  const bool correlated = correlation.rows() == first.back() && correlation.cols() == first.back() && first.back() > 0;
  std::string out = text;
  std::vector<scene::EffectSpec> library;
  std::vector<std::string> library_comments;
  std::vector<std::vector<double>> library_u;
  std::vector<Eigen::Index> library_slots;
  std::vector<Eigen::MatrixXd> library_draws;
  for (size_t i = 0; i < effects.size(); ++i) {
    const auto& u = i < uncertainties.size() ? uncertainties[i] : std::vector<double>{};
    const std::string comment = i < comments.size() ? comments[i] : "";
    if (!effects::is_custom_effect(effects[i].type)) {
      library.push_back(effects[i]);
      library_comments.push_back(comment);
      library_u.push_back(u);
      library_draws.push_back(i < draws.size() ? draws[i] : Eigen::MatrixXd());
      for (Eigen::Index k = first[i]; k < first[i + 1]; ++k) library_slots.push_back(k);
      continue;
    }
    std::vector<std::string> keys, pairs;
    for (const auto& p : effects::make_effect(effects[i].type)->parameters()) keys.push_back(p.key);
    for (Eigen::Index a = 0; correlated && a < first[i + 1] - first[i]; ++a)
      for (Eigen::Index b = a + 1; b < first[i + 1] - first[i]; ++b)
        if (const double r = correlation(first[i] + a, first[i] + b); r != 0.0)
          pairs.push_back(fmt::format("[{}, {}, {:.6g}]", keys[static_cast<size_t>(a)], keys[static_cast<size_t>(b)], r));
    out = with_custom_entry_values(out, effects[i].type, keys, effects[i].values, u, pairs, comment);
  }
  if (library.empty()) return out;
  Eigen::MatrixXd library_correlation;
  if (correlated) {
    const auto n = static_cast<Eigen::Index>(library_slots.size());
    library_correlation.resize(n, n);
    for (Eigen::Index a = 0; a < n; ++a)
      for (Eigen::Index b = 0; b < n; ++b) library_correlation(a, b) = correlation(library_slots[a], library_slots[b]);
  }
  return with_list_items(out, "effects", effects_yaml_items(library, library_comments, library_u, library_correlation, library_draws));
}

std::string machine_changes_yaml_items(const std::vector<machine::ComponentChange>& changes,
                                       const std::vector<double>& uncertainties, const std::vector<std::string>& comments,
                                       const machine::KinematicChain* chain) {
  std::string out;
  for (size_t i = 0; i < changes.size(); ++i) {
    const auto& c = changes[i];
    const auto q = machine::info(c.component).quantity;
    const double scale = machine::file_per_internal(c.law, q);
    if (i < comments.size() && !comments[i].empty()) out += "  # " + comments[i] + "\n";
    out += fmt::format("  - {{component: {}, law: {}, {}: {:.6g}", machine::info(chain, c.component).name,
                       c.law_name(), machine::size_key(c.law, q), c.size * scale);
    if (c.law == machine::ChangeLaw::SteadyState) out += fmt::format(", time_constant_s: {:.6g}", c.time_constant_s);
    if (c.law == machine::ChangeLaw::PerRevolution) out += fmt::format(", phase_deg: {:.6g}", c.phase_rad * 180.0 / 3.141592653589793);
    // The fit's 1σ: a prediction from the completed scene draws the size within it (docs/monte-carlo.md).
    if (i < uncertainties.size() && uncertainties[i] > 0.0)
      out += fmt::format(", uncertainty: {{{}: {:.6g}}}", machine::size_key(c.law, q), uncertainties[i] * scale);
    out += "}\n";
  }
  return out;
}

std::string scene_with_machine_changes(const std::string& text, const std::vector<machine::ComponentChange>& changes,
                                       const std::vector<double>& uncertainties, const std::vector<std::string>& comments,
                                       const machine::KinematicChain* chain) {
  return with_list_items(text, "machine_changes", machine_changes_yaml_items(changes, uncertainties, comments, chain));
}

} // namespace geartopo::diagnosis

namespace geartopo::diagnosis {
namespace {

std::string rebase(const std::string& item, const std::filesystem::path& from, const std::filesystem::path& to) {
  std::filesystem::path p(item);
  if (p.is_absolute() || item.empty()) return item;
  const auto abs = std::filesystem::weakly_canonical(std::filesystem::absolute(from / p));
  return std::filesystem::relative(abs, std::filesystem::weakly_canonical(std::filesystem::absolute(to))).generic_string();
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

} // namespace

std::string rebase_scene_paths(const std::string& text, const std::filesystem::path& from, const std::filesystem::path& to) {
  std::istringstream in(text);
  std::string out;
  bool in_tables_block = false;
  for (std::string line; std::getline(in, line);) {
    const std::string t = trim(line);
    const auto indent = line.substr(0, line.find_first_not_of(' '));
    if (t.rfind("tables:", 0) == 0) {
      in_tables_block = false;
      const auto open = line.find('['), close = line.rfind(']');
      if (open != std::string::npos && close != std::string::npos && close > open) {
        std::string items = line.substr(open + 1, close - open - 1), rebuilt;
        std::istringstream list(items);
        for (std::string item; std::getline(list, item, ',');)
          rebuilt += (rebuilt.empty() ? "" : ", ") + rebase(trim(item), from, to);
        line = line.substr(0, open + 1) + rebuilt + line.substr(close);
      } else {
        in_tables_block = true; // block list follows
      }
    } else if (in_tables_block && t.rfind("- ", 0) == 0) {
      line = indent + "- " + rebase(trim(t.substr(2)), from, to);
    } else if (in_tables_block && !t.empty() && t[0] != '#') {
      in_tables_block = false;
    }
    if (t.rfind("measured:", 0) == 0) {
      const auto colon = line.find(':');
      std::string value = trim(line.substr(colon + 1));
      const auto hash = value.find(" #");
      const std::string comment = hash == std::string::npos ? "" : value.substr(hash);
      if (hash != std::string::npos) value = trim(value.substr(0, hash));
      line = line.substr(0, colon + 1) + " " + rebase(value, from, to) + (comment.empty() ? "" : " " + comment);
    }
    out += line + "\n";
  }
  return out;
}

void write_scene_with_effects(const std::filesystem::path& scene_file, const std::vector<scene::EffectSpec>& effects,
                              const std::vector<std::string>& comments, const std::filesystem::path& out_file,
                              const std::vector<std::vector<double>>& uncertainties, const Eigen::MatrixXd& correlation,
                              const std::vector<machine::ComponentChange>& changes,
                              const std::vector<double>& change_uncertainties,
                              const std::vector<std::string>& change_comments,
                              const std::vector<Eigen::MatrixXd>& draws, const machine::KinematicChain* chain) {
  output::write_text_atomically(out_file, scene_text_with_effects(input::read_input_file(scene_file, input::kMaxSceneBytes,
                                                                                         "scene file"),
                                                                  scene_file.parent_path(), out_file.parent_path(),
                                                                  effects, comments, uncertainties, correlation, changes,
                                                                  change_uncertainties, change_comments, draws, chain));
}

std::string scene_text_with_effects(const std::string& scene_text, const std::filesystem::path& from_dir,
                                    const std::filesystem::path& to_dir, const std::vector<scene::EffectSpec>& effects,
                                    const std::vector<std::string>& comments,
                                    const std::vector<std::vector<double>>& uncertainties,
                                    const Eigen::MatrixXd& correlation,
                                    const std::vector<machine::ComponentChange>& changes,
                                    const std::vector<double>& change_uncertainties,
                                    const std::vector<std::string>& change_comments,
                                    const std::vector<Eigen::MatrixXd>& draws, const machine::KinematicChain* chain) {
  std::string completed = scene_text;
  if (!effects.empty()) completed = scene_with_effects(completed, effects, comments, uncertainties, correlation, draws);
  if (!changes.empty())
    completed = scene_with_machine_changes(completed, changes, change_uncertainties, change_comments, chain);
  return rebase_scene_paths(completed, from_dir, to_dir);
}

} // namespace geartopo::diagnosis
