#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_file.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/core/text_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <utility>

namespace geartopo::grinding {
namespace {

// A line as the reader sees it: without the '\r' of CRLF files and, on the first line, without the UTF-8 byte-order
// mark that Excel's "CSV UTF-8" writes (invisible in an editor, so columns are counted after it).
std::string clean_line(std::string s, int lineno) {
  if (!s.empty() && s.back() == '\r') s.pop_back();
  if (lineno == 1 && s.rfind(text::kUtf8Bom, 0) == 0) s.erase(0, text::kUtf8Bom.size());
  return s;
}

using text::Field;

using text::excerpt;

[[noreturn]] void fail(const std::string& src, int line, int col, const std::string& field, const std::string& msg) {
  throw InputError(src, line, col, field, msg);
}

double number(const Field& f, const std::string& src, int line, const char* name) {
  double v = 0.0;
  if (text::parse_number(f.text, v) != std::errc())
    fail(src, line, f.column, name, fmt::format("'{}' is not a number", excerpt(f.text)));
  if (!std::isfinite(v)) fail(src, line, f.column, name, fmt::format("'{}' is not finite", excerpt(f.text)));
  return v;
}

// A deviation beyond 1 mm is not a deviation of a ground flank (the grinding stock is a few tenths of a mm): it is a
// wrong unit or a broken file, and a value such as 1e300 µm would overflow every sum of squares downstream (issue 18).
double deviation(const Field& f, const std::string& src, int line) {
  const double v = number(f, src, line, "deviation_um");
  if (std::abs(v) > kMaxDeviationUm)
    fail(src, line, f.column, "deviation_um",
         fmt::format("{} µm is beyond ±{} µm, more than a ground flank can deviate (a wrong unit?)", excerpt(f.text),
                     kMaxDeviationUm));
  return v;
}

int whole(const Field& f, const std::string& src, int line, const char* name) {
  int v = 0;
  if (text::parse_number(f.text, v) != std::errc())
    fail(src, line, f.column, name, fmt::format("'{}' is not a whole number", excerpt(f.text)));
  return v;
}

// The header line must hold exactly these columns, in this order, and may end with design_um: the number of
// columns every row must have (7 or 8).
size_t check_header(const std::vector<Field>& f, const std::string& line, const char* const* names, const char* header,
                    const std::string& src, int lineno) {
  for (size_t i = 0; i < 7; ++i)
    if (i >= f.size() || f[i].text != names[i])
      fail(src, lineno, i < f.size() ? f[i].column : static_cast<int>(line.size()) + 1, "header",
           fmt::format("expected the columns {}[,{}] (column {} should be '{}')", header, kDesignColumn, i + 1, names[i]));
  if (f.size() > 7 && f[7].text != kDesignColumn)
    fail(src, lineno, f[7].column, "header",
         fmt::format("unexpected column '{}' (the only column after deviation_um is {})", excerpt(f[7].text), kDesignColumn));
  if (f.size() > 8) fail(src, lineno, f[8].column, "header", fmt::format("unexpected column '{}'", excerpt(f[8].text)));
  return f.size();
}

// A row's field count against the header's.
void check_row_size(const std::vector<Field>& f, size_t columns, const std::string& line, const std::string& src, int lineno) {
  if (f.size() != columns)
    fail(src, lineno, f.size() > columns ? f[columns].column : static_cast<int>(line.size()) + 1, "row",
         fmt::format("{} fields, expected {}", f.size(), columns));
}

// The design value of a row: the same bounds as a deviation.
double design(const Field& f, const std::string& src, int line) {
  const double v = number(f, src, line, kDesignColumn);
  if (std::abs(v) > kMaxDeviationUm)
    fail(src, line, f.column, kDesignColumn,
         fmt::format("{} µm is beyond ±{} µm, more than a drawing modifies a flank (a wrong unit?)", excerpt(f.text),
                     kMaxDeviationUm));
  return v;
}

} // namespace

std::vector<TopologyRow> topology_rows(const std::vector<FlankTopology>& topo, GridKind kind) {
  std::vector<TopologyRow> rows;
  for (const auto& ft : topo)
    for (const auto& p : kind == GridKind::Topology ? ft.grid : ft.dense)
      rows.push_back({ft.tooth, ft.flank, p.row, p.col, p.diameter_mm, p.z_mm, p.deviation_um, 0, p.design_um});
  return rows;
}

void write_topology_csv(std::ostream& out, const std::vector<FlankTopology>& topo, GridKind kind) {
  write_topology_rows(out, topology_rows(topo, kind));
}

void write_topology_rows(std::ostream& out, const std::vector<TopologyRow>& rows) {
  out << kTopologyHeader << "," << kDesignColumn << "\n";
  for (const auto& r : rows)
    out << fmt::format("{},{},{},{},{:.6f},{:.6f},{:.4f},{:.4f}\n", r.tooth, gears::to_string(r.flank), r.row, r.col,
                       r.diameter_mm, r.z_mm, r.deviation_um, r.design_um);
}

void write_traces_csv(std::ostream& out, const std::vector<FlankTopology>& topo) {
  out << kTracesHeader << "," << kDesignColumn << "\n";
  for (const auto& ft : topo) {
    for (const auto& p : ft.profile)
      out << fmt::format("{},{},profile,{:.6f},{:.6f},{:.6f},{:.4f},{:.4f}\n", ft.tooth, gears::to_string(ft.flank),
                         p.roll_length_mm, p.diameter_mm, p.z_mm, p.deviation_um, p.design_um);
    for (const auto& p : ft.helix)
      out << fmt::format("{},{},helix,{:.6f},{:.6f},{:.6f},{:.4f},{:.4f}\n", ft.tooth, gears::to_string(ft.flank),
                         p.roll_length_mm, p.diameter_mm, p.z_mm, p.deviation_um, p.design_um);
  }
}

void write_topology_csv(const std::filesystem::path& file, const std::vector<FlankTopology>& topo, GridKind kind) {
  output::write_atomically(file, [&](std::ostream& out) { write_topology_csv(out, topo, kind); });
}

void write_traces_csv(const std::filesystem::path& file, const std::vector<FlankTopology>& topo) {
  output::write_atomically(file, [&](std::ostream& out) { write_traces_csv(out, topo); });
}

std::vector<TopologyRow> read_topology_csv(std::istream& in, const std::string& src, int teeth) {
  static const char* names[] = {"tooth", "flank", "row", "col", "diameter_mm", "z_mm", "deviation_um"};
  std::vector<TopologyRow> rows;
  std::set<std::tuple<int, int, int, int>> seen;
  std::string line;
  int lineno = 0;
  bool header = false;
  size_t columns = 7;
  while (std::getline(in, line)) {
    ++lineno;
    line = clean_line(std::move(line), lineno);
    if (line.empty() || line[0] == '#') continue;
    const auto f = text::split_fields(line);
    if (!header) {
      columns = check_header(f, line, names, kTopologyHeader, src, lineno);
      header = true;
      continue;
    }
    check_row_size(f, columns, line, src, lineno);
    TopologyRow r;
    r.line = lineno;
    r.tooth = whole(f[0], src, lineno, "tooth");
    if (r.tooth < 1 || r.tooth > teeth) fail(src, lineno, f[0].column, "tooth", fmt::format("{} is not one of 1..{}", r.tooth, teeth));
    const auto flank = geartopo::parse_flank(f[1].text);
    if (!flank) fail(src, lineno, f[1].column, "flank", fmt::format("'{}' is neither left nor right", excerpt(f[1].text)));
    r.flank = *flank;
    r.row = whole(f[2], src, lineno, "row");
    if (r.row < 1) fail(src, lineno, f[2].column, "row", fmt::format("{} must be >= 1", r.row));
    r.col = whole(f[3], src, lineno, "col");
    if (r.col < 1) fail(src, lineno, f[3].column, "col", fmt::format("{} must be >= 1", r.col));
    r.diameter_mm = number(f[4], src, lineno, "diameter_mm");
    if (!(r.diameter_mm > 0.0)) fail(src, lineno, f[4].column, "diameter_mm", fmt::format("{} must be > 0", f[4].text));
    r.z_mm = number(f[5], src, lineno, "z_mm");
    r.deviation_um = deviation(f[6], src, lineno);
    if (columns == 8) r.design_um = design(f[7], src, lineno);
    if (!seen.insert({r.tooth, static_cast<int>(r.flank), r.row, r.col}).second)
      fail(src, lineno, f[0].column, "row", fmt::format("duplicate point: tooth {} {} row {} col {}", r.tooth,
                                                         gears::to_string(r.flank), r.row, r.col));
    rows.push_back(r);
  }
  if (!header) fail(src, std::max(lineno, 1), 1, "header", fmt::format("missing header {}", kTopologyHeader));
  if (rows.empty()) fail(src, lineno, 1, "rows", "no data rows");
  return rows;
}

std::vector<FlankTopology> read_traces_csv(std::istream& in, const std::string& src, int teeth) {
  static const char* names[] = {"tooth", "flank", "trace", "roll_length_mm", "diameter_mm", "z_mm", "deviation_um"};
  std::map<std::pair<int, int>, FlankTopology> flanks;
  std::string line;
  int lineno = 0;
  bool header = false;
  size_t columns = 7;
  while (std::getline(in, line)) {
    ++lineno;
    line = clean_line(std::move(line), lineno);
    if (line.empty() || line[0] == '#') continue;
    const auto f = text::split_fields(line);
    if (!header) {
      columns = check_header(f, line, names, kTracesHeader, src, lineno);
      header = true;
      continue;
    }
    check_row_size(f, columns, line, src, lineno);
    const int tooth = whole(f[0], src, lineno, "tooth");
    if (tooth < 1 || tooth > teeth) fail(src, lineno, f[0].column, "tooth", fmt::format("{} is not one of 1..{}", tooth, teeth));
    const auto flank = geartopo::parse_flank(f[1].text);
    if (!flank) fail(src, lineno, f[1].column, "flank", fmt::format("'{}' is neither left nor right", excerpt(f[1].text)));
    const bool profile = f[2].text == "profile";
    if (!profile && f[2].text != "helix") fail(src, lineno, f[2].column, "trace", fmt::format("'{}' is neither profile nor helix", excerpt(f[2].text)));
    TracePoint p{number(f[3], src, lineno, "roll_length_mm"), number(f[4], src, lineno, "diameter_mm"),
                 number(f[5], src, lineno, "z_mm"), deviation(f[6], src, lineno), lineno,
                 columns == 8 ? design(f[7], src, lineno) : 0.0};
    if (!(p.diameter_mm > 0.0)) fail(src, lineno, f[4].column, "diameter_mm", fmt::format("{} must be > 0", f[4].text));
    if (!(p.roll_length_mm >= 0.0)) fail(src, lineno, f[3].column, "roll_length_mm", fmt::format("{} must be >= 0", f[3].text));
    FlankTopology& ft = flanks[{tooth, static_cast<int>(*flank)}];
    ft.tooth = tooth;
    ft.flank = *flank;
    auto& trace = profile ? ft.profile : ft.helix;
    if (!trace.empty()) {
      const double prev = profile ? trace.back().roll_length_mm : trace.back().z_mm;
      const double cur = profile ? p.roll_length_mm : p.z_mm;
      if (!(cur > prev))
        fail(src, lineno, profile ? f[3].column : f[5].column, profile ? "roll_length_mm" : "z_mm",
             fmt::format("{} does not increase along the {} trace of tooth {} {} (previous {})", cur, f[2].text, tooth,
                         f[1].text, prev));
    }
    trace.push_back(p);
  }
  if (!header) fail(src, std::max(lineno, 1), 1, "header", fmt::format("missing header {}", kTracesHeader));
  if (flanks.empty()) fail(src, lineno, 1, "rows", "no data rows");
  std::vector<FlankTopology> out;
  for (auto& [key, ft] : flanks) out.push_back(std::move(ft));
  return out;
}

bool starts_like_traces_csv(std::istream& in) {
  std::string line;
  bool traces = false;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    line = clean_line(std::move(line), lineno);
    if (line.empty() || line[0] == '#') continue;
    // The header alone or followed by ",design_um" (compared in pieces: GCC 12 at -O2 warns falsely about a
    // concatenated temporary, -Warray-bounds, GCC bug 105329).
    const std::string_view header = kTracesHeader;
    const std::string_view rest = std::string_view(line).substr(std::min(line.size(), header.size()));
    traces = std::string_view(line).starts_with(header) &&
             (rest.empty() || (rest.size() == 1 + std::string_view(kDesignColumn).size() && rest[0] == ',' &&
                               rest.substr(1) == kDesignColumn));
    break;
  }
  in.clear();
  in.seekg(0);
  return traces;
}

int design_column_line(std::istream& in) {
  std::string line;
  int header_line = 0;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    line = clean_line(std::move(line), lineno);
    if (line.empty() || line[0] == '#') continue;
    const auto f = text::split_fields(line); // the fields as check_header sees them
    if (f.size() == 8 && f[7].text == kDesignColumn) header_line = lineno;
    break;
  }
  in.clear();
  in.seekg(0);
  return header_line;
}

std::vector<FlankTopology> read_traces_csv(const std::filesystem::path& file, int teeth) {
  auto in = input::open_input_file(file, input::kMaxMeasurementBytes, "traces file");
  return read_traces_csv(in, file.string(), teeth);
}

std::vector<TopologyRow> read_topology_csv(const std::filesystem::path& file, int teeth) {
  auto in = input::open_input_file(file, input::kMaxMeasurementBytes, "topology file");
  return read_topology_csv(in, file.string(), teeth);
}

} // namespace geartopo::grinding
