#include "geartopo/surfaces/point_cloud.hpp"
#include "geartopo/files/input_file.hpp"

#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/text_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <stdexcept>
#include <string_view>

namespace geartopo::surfaces {
namespace {

using text::Field;

std::string_view trim(std::string_view s) {
  constexpr std::string_view blanks = " \t";
  const size_t a = s.find_first_not_of(blanks);
  if (a == std::string_view::npos) return {};
  return s.substr(a, s.find_last_not_of(blanks) - a + 1);
}

[[noreturn]] void fail(const std::string& src, std::int64_t line, int col, std::string_view field,
                       const std::string& msg) {
  throw InputError(src, static_cast<int>(std::min<std::int64_t>(line, std::numeric_limits<int>::max())), col,
                   std::string(field), msg);
}

// Concatenation by appending: GCC 12 warns falsely (-Wrestrict) on `"literal" + std::string&&`.
template <class... Parts>
std::string cat(const Parts&... parts) {
  std::string s;
  (s.append(std::string_view(parts)), ...);
  return s;
}

// Quotes a field in a message: whole, or its first 40 characters when longer (a corrupt file can hold a 64 KiB field).
std::string quoted(std::string_view s) {
  if (s.size() <= 40) return cat("'", s, "'");
  return cat("'", text::utf8_prefix(s, 40), "…' (", std::to_string(s.size()), " characters)");
}

// A coordinate as a message shows it: fixed decimals, or 6 significant digits when absurd (1e300 mm was printed as
// 63 of its 301 digits).
constexpr double kMaxCoordinateMm = 1e5;

std::string fixed(double v, int decimals) {
  char buf[64];
  if (std::abs(v) >= 1e9) std::snprintf(buf, sizeof buf, "%.6g", v);
  else std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

double number(const Field& f, const std::string& src, std::int64_t line, std::string_view name) {
  double v = 0.0;
  const std::errc ec = text::parse_number(f.text, v);
  if (f.text.empty()) fail(src, line, f.column, name, "empty field, expected a number");
  if (ec == std::errc::result_out_of_range) fail(src, line, f.column, name, quoted(f.text) + " is out of range");
  if (ec != std::errc()) fail(src, line, f.column, name, quoted(f.text) + " is not a number");
  if (!std::isfinite(v)) fail(src, line, f.column, name, quoted(f.text) + " is not finite");
  // A coordinate beyond 100 m is no gear's (a wrong unit, or a corrupt file): refused here, naming the file, rather
  // than reaching a fit as an infinite residual.
  if (std::abs(v) > kMaxCoordinateMm)
    fail(src, line, f.column, name, quoted(f.text) + " mm is beyond ±100000 mm, further than any gear reaches (a wrong unit?)");
  return v;
}

std::int64_t whole(const Field& f, const std::string& src, std::int64_t line, std::string_view name) {
  std::int64_t v = 0;
  if (text::parse_number(f.text, v) != std::errc() || v < 0)
    fail(src, line, f.column, name, quoted(f.text) + " is not a whole number >= 0");
  return v;
}

/// A pair of points that are duplicates: `later` repeats `earlier` (indices into the point list, earlier < later).
struct Duplicate {
  std::int64_t later = -1, earlier = -1;
  bool found() const { return later >= 0; }
  /// Keeps the pair whose later point comes first in the file (then the earliest partner): the first line at which
  /// a streaming reader would have seen a repeat.
  void offer(std::int64_t a, std::int64_t b) {
    const Duplicate d{std::max(a, b), std::min(a, b)};
    if (!found() || d.later < later || (d.later == later && d.earlier < earlier)) *this = d;
  }
};

// Near-duplicate search by sorting points into cells much larger than the tolerance: a point's near-duplicates lie in
// its own cell or, when it sits within the tolerance of a cell wall, in the neighbour across that wall. Sorting keeps
// memory access sequential (a hash table of a million cells was cache-miss bound, ~4× slower).
Duplicate first_duplicate_point(const std::vector<CloudPoint>& points) {
  constexpr double t = kDuplicatePointTolerance_mm;
  constexpr double kCell = 1e-6; // mm
  struct Entry {
    std::array<std::int64_t, 3> cell;
    std::int64_t index;
    bool operator<(const Entry& o) const { return cell < o.cell || (cell == o.cell && index < o.index); }
  };
  const auto cell = [](double x) { // clamped: a far-out coordinate must not overflow the cast
    return static_cast<std::int64_t>(std::clamp(std::floor(x / kCell), -4e18, 4e18));
  };
  std::vector<Entry> e(points.size());
  for (size_t n = 0; n < points.size(); ++n) {
    const Eigen::Vector3d& p = points[n].position_mm;
    e[n] = {{cell(p.x()), cell(p.y()), cell(p.z())}, static_cast<std::int64_t>(n)};
  }
  std::sort(e.begin(), e.end());
  const auto close = [&](std::int64_t a, std::int64_t b) {
    return (points[static_cast<size_t>(a)].position_mm - points[static_cast<size_t>(b)].position_mm).norm() <= t;
  };
  Duplicate dup;
  // Within each cell (groups are almost always of one point). A group is sorted by index: the first b with a close
  // earlier a is the group's best, and its first such a the earliest partner (so a run of identical points is O(n)).
  for (size_t g = 0; g < e.size();) {
    size_t h = g + 1;
    while (h < e.size() && e[h].cell == e[g].cell) ++h;
    bool found = false;
    for (size_t b = g + 1; b < h && !found; ++b)
      for (size_t a = g; a < b && !found; ++a)
        if (close(e[a].index, e[b].index)) {
          dup.offer(e[a].index, e[b].index);
          found = true;
        }
    g = h;
  }
  // Across cell walls, for the few points within t of one.
  for (const Entry& me : e) {
    const Eigen::Vector3d& p = points[static_cast<size_t>(me.index)].position_mm;
    std::array<std::array<std::int64_t, 2>, 3> range;
    for (int k = 0; k < 3; ++k) range[k] = {cell(p[k] - t), cell(p[k] + t)};
    if (range[0][0] == range[0][1] && range[1][0] == range[1][1] && range[2][0] == range[2][1]) continue;
    for (std::int64_t i = range[0][0]; i <= range[0][1]; ++i)
      for (std::int64_t j = range[1][0]; j <= range[1][1]; ++j)
        for (std::int64_t k = range[2][0]; k <= range[2][1]; ++k) {
          const std::array<std::int64_t, 3> c{i, j, k};
          if (c == me.cell) continue;
          for (auto it = std::lower_bound(e.begin(), e.end(), Entry{c, -1}); it != e.end() && it->cell == c; ++it)
            if (close(me.index, it->index)) dup.offer(me.index, it->index);
        }
  }
  return dup;
}

/// First repeated id, as for points.
Duplicate first_duplicate_id(const std::vector<CloudPoint>& points) {
  std::vector<std::pair<std::int64_t, std::int64_t>> e(points.size()); // (id, index)
  for (size_t n = 0; n < points.size(); ++n) e[n] = {points[n].id, static_cast<std::int64_t>(n)};
  std::sort(e.begin(), e.end());
  Duplicate dup;
  size_t run = 0; // first entry of the current run of equal ids: the earliest line with that id
  for (size_t n = 1; n < e.size(); ++n) {
    if (e[n].first != e[run].first) {
      run = n;
      continue;
    }
    dup.offer(e[run].second, e[n].second);
  }
  return dup;
}

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

} // namespace

std::vector<CloudPoint> read_point_cloud(std::istream& in, const std::string& src) {
  static constexpr std::array<std::string_view, 4> kNames{"x_mm", "y_mm", "z_mm", "id"};
  std::vector<CloudPoint> points;
  std::vector<int> id_columns; // column of each row's id, for messages (only with an id column)
  std::vector<Field> f;
  std::string buffer;
  std::int64_t lineno = 0, header_line = 0;
  size_t columns = 0; // 0 until the header is read, then 3 or 4

  while (std::getline(in, buffer)) {
    ++lineno;
    std::string_view line = buffer;
    int offset = 0; // characters dropped from the start (the BOM), for column numbers
    if (lineno == 1 && text::strip_bom(line)) offset = static_cast<int>(text::kUtf8Bom.size());
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    text::split_fields(line, f);
    for (auto& field : f) field.column += offset;

    if (columns == 0) { // the header
      for (size_t i = 0; i < 3; ++i) {
        if (i >= f.size())
          fail(src, lineno, static_cast<int>(line.size()) + 1 + offset, "header",
               cat("missing column ", quoted(kNames[i]), ", expected ", kPointCloudHeader, " (optionally ,id)"));
        if (f[i].text != kNames[i])
          fail(src, lineno, f[i].column, "header",
               cat("expected ", quoted(kNames[i]), ", found ", quoted(f[i].text), " (header ", kPointCloudHeader,
                   ", optionally ,id)"));
      }
      if (f.size() >= 4 && f[3].text != kNames[3])
        fail(src, lineno, f[3].column, "header",
             cat("unexpected column ", quoted(f[3].text), ", only 'id' may follow z_mm"));
      if (f.size() > 4)
        fail(src, lineno, f[4].column, "header", cat("unexpected column ", quoted(f[4].text), " after id"));
      columns = f.size();
      header_line = lineno;
      continue;
    }

    if (f.size() != columns) {
      const int col = f.size() > columns ? f[columns].column : static_cast<int>(line.size()) + 1 + offset;
      fail(src, lineno, col, "row",
           cat(std::to_string(f.size()), " fields, expected ", std::to_string(columns), " (", kPointCloudHeader,
               columns == 4 ? ",id)" : ")"));
    }
    CloudPoint p;
    p.line = lineno;
    for (size_t k = 0; k < 3; ++k)
      p.position_mm[static_cast<Eigen::Index>(k)] = number(f[k], src, lineno, kNames[k]);
    if (columns == 4) {
      p.id = whole(f[3], src, lineno, "id");
      id_columns.push_back(f[3].column);
    }
    points.push_back(p);
  }
  if (in.bad()) fail(src, lineno + 1, 1, "file", "read error");
  if (columns == 0) fail(src, lineno + 1, 1, "header", std::string("missing header ") + kPointCloudHeader);
  if (points.empty()) fail(src, header_line, 1, "header", "no points follow the header");

  // Repeats, after the syntax: the first line that repeats an earlier point or id.
  if (columns == 4) {
    if (const Duplicate d = first_duplicate_id(points); d.found()) {
      const CloudPoint& p = points[static_cast<size_t>(d.later)];
      fail(src, p.line, id_columns[static_cast<size_t>(d.later)], "id",
           cat(std::to_string(p.id), " repeats the id on line ",
               std::to_string(points[static_cast<size_t>(d.earlier)].line)));
    }
  }
  if (const Duplicate d = first_duplicate_point(points); d.found()) {
    const CloudPoint& p = points[static_cast<size_t>(d.later)];
    fail(src, p.line, 1, "point",
         cat("(", shortest(p.position_mm.x()), ", ", shortest(p.position_mm.y()), ", ", shortest(p.position_mm.z()),
             ") duplicates the point on line ", std::to_string(points[static_cast<size_t>(d.earlier)].line),
             " (closer than 1e-9 mm)"));
  }
  return points;
}

bool starts_like_point_cloud(std::istream& in) {
  std::string buffer;
  for (std::int64_t lineno = 1; std::getline(in, buffer); ++lineno) {
    std::string_view line = buffer;
    if (lineno == 1) text::strip_bom(line);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    return trim(content.substr(0, content.find(','))) == "x_mm";
  }
  return false;
}

std::vector<CloudPoint> read_point_cloud(const std::filesystem::path& file) {
  auto in = input::open_input_file(file, input::kMaxMeasurementBytes, "point cloud");
  return read_point_cloud(in, file.string());
}

std::vector<FlankSample> assign_to_flanks(const std::vector<CloudPoint>& points, const gears::InvoluteHelicoid& flanks,
                                          double max_offset_mm, const std::string& src,
                                          const FlankRangeTolerance& tolerance) {
  if (!(std::isfinite(max_offset_mm) && max_offset_mm > 0.0))
    throw std::invalid_argument("assign_to_flanks: max_offset_mm must be finite and > 0");
  if (!(tolerance.diameter_mm >= 0.0 && tolerance.z_mm >= 0.0))
    throw std::invalid_argument("assign_to_flanks: range tolerances must be >= 0");
  const gears::GearGeometry& g = flanks.geometry();
  const double d_lo = g.root_form_diameter_mm() - tolerance.diameter_mm;
  const double d_hi = g.tip_diameter_mm() + tolerance.diameter_mm;
  const double z_lo = -tolerance.z_mm;
  const double z_hi = g.spec().face_width_mm + tolerance.z_mm;

  std::vector<FlankSample> out;
  out.reserve(points.size());
  for (const CloudPoint& p : points) {
    const Eigen::Vector3d& w = p.position_mm;
    const auto where = [&] {
      return cat("(", fixed(w.x(), 4), ", ", fixed(w.y(), 4), ", ", fixed(w.z(), 4), ")");
    };
    if (!w.allFinite()) fail(src, p.line, 1, "point", "coordinates are not finite");
    const auto loc = flanks.locate(w);
    if (!loc)
      fail(src, p.line, 1, "point",
           cat(where(), " does not project onto a flank (inside the base cylinder, or the projection did not",
               " converge)"));
    const std::string on = cat(" (foot on tooth ", std::to_string(loc->tooth), " ", gears::to_string(loc->flank),
                               " flank at d = ", fixed(loc->diameter_mm, 3), " mm, z = ", fixed(loc->z_mm, 3), " mm)");
    if (std::abs(loc->normal_distance_mm) > max_offset_mm)
      fail(src, p.line, 1, "point",
           cat(where(), " is off the flank: normal distance ", fixed(loc->normal_distance_mm, 4), " mm exceeds ",
               fixed(max_offset_mm, 4), " mm", on));
    if (!(loc->diameter_mm >= d_lo && loc->diameter_mm <= d_hi))
      fail(src, p.line, 1, "point",
           cat(where(), " projects outside d_Ff..d_a = ", fixed(g.root_form_diameter_mm(), 3), "..",
               fixed(g.tip_diameter_mm(), 3), " mm", on));
    if (!(loc->z_mm >= z_lo && loc->z_mm <= z_hi))
      fail(src, p.line, 1, "point",
           cat(where(), " projects outside the face width 0..", fixed(g.spec().face_width_mm, 3), " mm", on));
    FlankSample s;
    s.tooth = loc->tooth;
    s.flank = loc->flank;
    s.roll_length_mm = loc->roll_length_mm;
    s.diameter_mm = loc->diameter_mm;
    s.z_mm = loc->z_mm;
    s.normal_distance_mm = loc->normal_distance_mm;
    s.line = p.line;
    s.id = p.id;
    out.push_back(s);
  }
  return out;
}

} // namespace geartopo::surfaces
