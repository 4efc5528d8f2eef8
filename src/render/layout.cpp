#include "detail/layout.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace geartopo::render::detail {

int font_px(ImageSize size, int requested) {
  if (requested > 0) return requested;
  const double diagonal = std::sqrt(static_cast<double>(size.width) * size.height);
  return std::clamp(static_cast<int>(std::lround(diagonal * 0.0184)), 10, 40);
}

double nice_step(double span, int target) {
  const double raw = span / std::max(target, 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / magnitude;
  const double m = r < 1.5 ? 1.0 : r < 3.0 ? 2.0 : r < 7.0 ? 5.0 : 10.0;
  return m * magnitude;
}

Range nice_range(double lo, double hi, double pad) {
  if (hi < lo) std::swap(lo, hi);
  double span = hi - lo;
  if (span <= 1e-12 * std::max(1.0, std::abs(lo))) {
    const double half = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= half;
    hi += half;
    span = hi - lo;
  }
  lo -= pad * span;
  hi += pad * span;
  const double step = nice_step(hi - lo, 12); // round the ends finely: the ticks use a coarser step
  return {std::floor(lo / step + 1e-9) * step, std::ceil(hi / step - 1e-9) * step};
}

std::vector<double> nice_ticks(Range range, int target) {
  std::vector<double> ticks;
  const double span = range.max - range.min;
  if (!(span > 0.0)) return ticks;
  const double step = nice_step(span, target);
  const double eps = 1e-9 * span;
  for (double k = std::ceil((range.min - eps) / step); k * step <= range.max + eps; k += 1.0) {
    const double t = k * step;
    ticks.push_back(std::abs(t) < eps ? 0.0 : t);
  }
  return ticks;
}

std::string format_value(double v, int decimals) {
  std::string s = fmt::format("{:.{}f}", v, std::max(decimals, 0));
  if (s.find_first_not_of("-0.") == std::string::npos && s.front() == '-') s.erase(0, 1);
  return s;
}

int decimals_for_step(double step) {
  if (!(step > 0.0) || step >= 1.0) return 0;
  return std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 6);
}

std::string axis_label(const std::string& title, const std::string& unit) {
  if (unit.empty()) return title;
  if (title.empty()) return "[" + unit + "]";
  return title + " [" + unit + "]";
}

const std::string& font_file(bool bold) {
  static const auto find = [](const char* name) {
    for (const char* dir : {"/usr/share/fonts/truetype/dejavu/", "/usr/share/fonts/dejavu/", "/usr/share/fonts/TTF/"}) {
      const std::filesystem::path p = std::filesystem::path(dir) / name;
      std::error_code ec;
      if (std::filesystem::exists(p, ec)) return p.string();
    }
    return std::string();
  };
  static const std::string regular = find("DejaVuSans.ttf");
  static const std::string bold_face = find("DejaVuSans-Bold.ttf");
  return bold && !bold_face.empty() ? bold_face : regular;
}

double text_width_estimate(const std::string& text, int px) {
  std::size_t chars = 0;
  for (unsigned char c : text)
    if ((c & 0xC0) != 0x80) ++chars; // count UTF-8 code points
  return 0.64 * px * static_cast<double>(chars);
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

} // namespace geartopo::render::detail
