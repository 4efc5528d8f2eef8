#include "custom_entry_writer.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <regex>
#include <sstream>
#include <stdexcept>

namespace geartopo::diagnosis {
namespace {

std::size_t indent_of(const std::string& l) {
  const auto i = l.find_first_not_of(' ');
  return i == std::string::npos ? l.size() : i;
}
bool blank_or_comment(const std::string& l) {
  const auto i = l.find_first_not_of(" \t");
  return i == std::string::npos || l[i] == '#';
}
std::string unquoted(std::string v) {
  if (const auto hash = v.find(" #"); hash != std::string::npos) v.resize(hash);
  while (!v.empty() && (v.back() == ' ' || v.back() == '\t' || v.back() == '\r')) v.pop_back();
  if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front()) v = v.substr(1, v.size() - 2);
  return v;
}

/// The lines of one item: [begin, end) and the column its keys start at.
struct Item {
  std::size_t begin = 0, end = 0, key_column = 0, name_line = 0;
};

Item find_item(const std::vector<std::string>& lines, const std::string& name) {
  std::size_t start = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (lines[i].rfind("custom_effects:", 0) == 0) start = i;
  if (start == lines.size()) throw std::runtime_error("the scene has no custom_effects list to write '" + name + "' into");
  std::size_t block_end = start + 1;
  while (block_end < lines.size() && (blank_or_comment(lines[block_end]) || lines[block_end][0] == ' ' || lines[block_end][0] == '-'))
    ++block_end;
  const std::regex name_re(R"(^(\s*-\s+|\s*)name:\s*(.*)$)");
  for (std::size_t i = start + 1; i < block_end; ++i) {
    std::smatch m;
    if (!std::regex_match(lines[i], m, name_re) || unquoted(m[2].str()) != name) continue;
    Item it;
    it.name_line = i;
    it.key_column = static_cast<std::size_t>(m.length(1));
    it.begin = i;
    const auto is_dash = [&](std::size_t k) { return lines[k].compare(indent_of(lines[k]), 2, "- ") == 0; };
    while (it.begin > start + 1 && !is_dash(it.begin)) --it.begin;
    // The item runs to the next line at or left of its dash (the next item or the list's end).
    const std::size_t dash = indent_of(lines[it.begin]);
    it.end = it.begin + 1;
    while (it.end < block_end && (blank_or_comment(lines[it.end]) || indent_of(lines[it.end]) > dash)) ++it.end;
    return it;
  }
  throw std::runtime_error("the scene's custom_effects has no entry named '" + name + "' to write its fitted values into");
}

const std::regex kNumber(R"([-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)");

/// Replaces the number after "value:" in line `l` from column `from`; false when there is none.
bool replace_value(std::string& l, std::size_t from, double v) {
  const auto at = l.find("value:", from);
  if (at == std::string::npos) return false;
  std::smatch m;
  const std::string rest = l.substr(at + 6);
  if (!std::regex_search(rest, m, kNumber) || m.position(0) != static_cast<long>(rest.find_first_not_of(' '))) return false;
  l = l.substr(0, at + 6) + rest.substr(0, static_cast<std::size_t>(m.position(0))) + fmt::format("{:.6g}", v) +
      rest.substr(static_cast<std::size_t>(m.position(0) + m.length(0)));
  return true;
}

void write_parameter(std::vector<std::string>& lines, const Item& item, const std::string& name, const std::string& key,
                     double value) {
  const std::regex key_re("^\\s*" + key + ":(.*)$");
  for (std::size_t i = item.begin; i < item.end; ++i) {
    std::smatch m;
    if (!std::regex_match(lines[i], m, key_re) || indent_of(lines[i]) <= item.key_column) continue;
    if (m[1].str().find('{') != std::string::npos) {
      if (replace_value(lines[i], static_cast<std::size_t>(m.position(1)), value)) return;
    } else {
      for (std::size_t j = i + 1; j < item.end && (blank_or_comment(lines[j]) || indent_of(lines[j]) > indent_of(lines[i])); ++j)
        if (replace_value(lines[j], 0, value)) return;
    }
  }
  throw std::runtime_error(fmt::format("custom effect '{}': the value of parameter '{}' was not found in a form geartopo "
                                       "can rewrite ({{value: …, min: …}} on one line, or value: on a line of its own)",
                                       name, key));
}

} // namespace

std::string with_custom_entry_values(const std::string& text, const std::string& name, const std::vector<std::string>& keys,
                                     const std::vector<double>& values, const std::vector<double>& uncertainties,
                                     const std::vector<std::string>& pairs, const std::string& comment) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  Item item = find_item(lines, name);
  for (std::size_t k = 0; k < keys.size() && k < values.size(); ++k) write_parameter(lines, item, name, keys[k], values[k]);
  // The entry's own uncertainty and correlation, replaced: the old keys' lines (and their continuation) go.
  for (std::size_t i = item.begin; i < item.end;) {
    const bool own = indent_of(lines[i]) == item.key_column && i != item.name_line &&
                     (lines[i].compare(item.key_column, 12, "uncertainty:") == 0 ||
                      lines[i].compare(item.key_column, 12, "correlation:") == 0);
    if (!own) {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < item.end && !blank_or_comment(lines[j]) && indent_of(lines[j]) > item.key_column) ++j;
    lines.erase(lines.begin() + static_cast<long>(i), lines.begin() + static_cast<long>(j));
    item.end -= j - i;
  }
  const std::string pad(item.key_column, ' ');
  std::vector<std::string> added;
  std::vector<std::string> us;
  for (std::size_t k = 0; k < keys.size() && k < uncertainties.size(); ++k)
    if (uncertainties[k] > 0.0) us.push_back(fmt::format("{}: {:.6g}", keys[k], uncertainties[k]));
  if (!comment.empty()) added.push_back(pad + "# " + comment);
  if (!us.empty()) added.push_back(pad + fmt::format("uncertainty: {{{}}}", fmt::join(us, ", ")));
  if (!pairs.empty()) added.push_back(pad + fmt::format("correlation: [{}]", fmt::join(pairs, ", ")));
  lines.insert(lines.begin() + static_cast<long>(item.name_line + 1), added.begin(), added.end());
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

} // namespace geartopo::diagnosis
