#include "design_table.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/core/text_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <utility>

namespace geartopo::scene {
namespace {

constexpr const char* kHeader = "flank,diameter_mm,z_mm,design_um";
constexpr double kMaxDesignUm = 1000.0; // as a deviation (grinding::kMaxDeviationUm): a drawing modifies by µm

} // namespace

gears::DesignTable read_design_table(const std::filesystem::path& file) {
  const std::string src = file.string();
  const std::string text = input::read_input_file(file, input::kMaxErrorTableBytes, "design table");
  const auto fail = [&](int line, int column, const std::string& field, const std::string& message) {
    throw InputError(src, line, column, field, message);
  };
  // Per flank: (diameter, z) → (value, line); the grid's knots are the distinct diameters and z given.
  std::map<int, std::map<std::pair<double, double>, std::pair<double, int>>> points;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::string_view view(line);
    if (lineno == 1) text::strip_bom(view);
    if (view.empty() || view.front() == '#') continue;
    const auto f = text::split_fields(view);
    if (!header) {
      if (view != kHeader) fail(lineno, 1, "header", fmt::format("expected the columns {}", kHeader));
      header = true;
      continue;
    }
    if (f.size() != 4)
      fail(lineno, f.size() > 4 ? f[4].column : static_cast<int>(view.size()) + 1, "row",
           fmt::format("{} fields, expected 4", f.size()));
    const auto flank = geartopo::parse_flank(f[0].text);
    if (!flank) fail(lineno, f[0].column, "flank", fmt::format("'{}' is neither left nor right", text::excerpt(f[0].text)));
    double v[3] = {0, 0, 0};
    const char* names[] = {"diameter_mm", "z_mm", "design_um"};
    for (int k = 0; k < 3; ++k) {
      const auto& field = f[static_cast<size_t>(k + 1)];
      if (text::parse_number(field.text, v[k]) != std::errc())
        fail(lineno, field.column, names[k], fmt::format("'{}' is not a number", text::excerpt(field.text)));
      if (!std::isfinite(v[k])) fail(lineno, field.column, names[k], fmt::format("'{}' is not finite", text::excerpt(field.text)));
    }
    if (!(v[0] > 0.0)) fail(lineno, f[1].column, "diameter_mm", fmt::format("{} must be > 0", text::excerpt(f[1].text)));
    if (std::abs(v[2]) > kMaxDesignUm)
      fail(lineno, f[3].column, "design_um",
           fmt::format("{} µm is beyond ±{} µm, more than a drawing modifies a flank (a wrong unit?)",
                       text::excerpt(f[3].text), kMaxDesignUm));
    if (!points[static_cast<int>(*flank)].emplace(std::pair{v[0], v[1]}, std::pair{v[2], lineno}).second)
      fail(lineno, f[0].column, "row", fmt::format("duplicate point: {} flank, d = {} mm, z = {} mm", f[0].text, v[0], v[1]));
  }
  if (!header) fail(std::max(lineno, 1), 1, "header", fmt::format("missing header {}", kHeader));
  if (points.empty()) fail(lineno, 1, "rows", "no data rows");

  gears::DesignTable table;
  table.file = src;
  for (const auto& [side, values] : points) {
    auto& grid = side == static_cast<int>(geartopo::Flank::Left) ? table.left : table.right;
    std::set<double> ds, zs;
    for (const auto& [key, value] : values) ds.insert(key.first), zs.insert(key.second);
    const char* name = side == static_cast<int>(geartopo::Flank::Left) ? "left" : "right";
    if (ds.size() < 2 || zs.size() < 2)
      fail(0, 0, "rows", fmt::format("the {} flank's points span {} diameter(s) and {} z value(s): a grid needs at least "
                                     "2 × 2",
                                     name, ds.size(), zs.size()));
    grid.diameter_mm.assign(ds.begin(), ds.end());
    grid.z_mm.assign(zs.begin(), zs.end());
    for (double d : grid.diameter_mm)
      for (double z : grid.z_mm) {
        const auto it = values.find({d, z});
        if (it == values.end())
          fail(0, 0, "rows", fmt::format("the {} flank's grid has no point at d = {} mm, z = {} mm: every diameter needs "
                                         "every z",
                                         name, d, z));
        grid.value_um.push_back(it->second.first);
      }
  }
  return table;
}

} // namespace geartopo::scene
