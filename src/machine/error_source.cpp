// geartopo — constant / polynomial / table error sources. Units: converted to mm and rad on construction.
#include "geartopo/machine/error_source.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace geartopo::machine {

namespace {

double value_scale_or_throw(ComponentId id, std::string_view unit) {
  const ComponentInfo& c = info(id);
  if (auto s = value_unit_scale(c.quantity, unit)) return *s;
  if (is_known_unit(unit))
    throw std::invalid_argument(fmt::format("{}: unit '{}' is not a {} unit (use {})", c.name, unit,
                                            c.quantity == Quantity::Length ? "length" : "angle",
                                            file_unit(c.quantity)));
  throw std::invalid_argument(fmt::format("{}: unknown unit '{}'", c.name, unit));
}

} // namespace

ErrorSource ErrorSource::zero(ComponentId id) { return ErrorSource(id, Kind::Constant); }

ErrorSource ErrorSource::constant(ComponentId id, double value, std::string_view unit) {
  const double scale = value_scale_or_throw(id, unit);
  if (!std::isfinite(value))
    throw std::invalid_argument(fmt::format("{}: constant value is not finite", info(id).name));
  ErrorSource s(id, Kind::Constant);
  s.constant_ = value * scale;
  return s;
}

ErrorSource ErrorSource::polynomial(ComponentId id, std::vector<double> coefficients, std::string_view value_unit,
                                    std::string_view position_unit) {
  const ComponentInfo& c = info(id);
  const double vs = value_scale_or_throw(id, value_unit);
  const auto ps = position_unit_scale(c.axis, position_unit);
  if (!ps)
    throw std::invalid_argument(fmt::format("{}: '{}' is not a position unit of axis {} (use {})", c.name,
                                            position_unit, axis_name(c.axis), is_rotary(c.axis) ? "deg" : "mm"));
  while (coefficients.size() > 1 && coefficients.back() == 0.0) coefficients.pop_back();
  if (coefficients.empty()) coefficients.push_back(0.0);
  for (double k : coefficients)
    if (!std::isfinite(k)) throw std::invalid_argument(fmt::format("{}: polynomial coefficient is not finite", c.name));
  if (coefficients.size() > 1 && !c.position_dependent)
    throw std::invalid_argument(fmt::format("{} is position independent: give it as a constant", c.name));
  if (coefficients.size() > 1 && c.axis == Axis::C)
    throw std::invalid_argument(
        fmt::format("{}: a polynomial in γ is not periodic over the C turn; give a periodic table", c.name));
  ErrorSource s(id, Kind::Polynomial);
  // value = Σ k_i (p_file)^i · vs with p_file = p_internal / ps  →  internal coefficient k_i·vs/ps^i.
  double pscale = 1.0;
  for (double k : coefficients) {
    s.coefficients_.push_back(k * vs / pscale);
    pscale *= *ps;
  }
  return s;
}

ErrorSource ErrorSource::table(ComponentId id, CubicSpline spline, TableOrigin origin) {
  ErrorSource s(id, Kind::Table);
  s.spline_ = std::move(spline);
  s.origin_ = std::move(origin);
  return s;
}

ErrorSource ErrorSource::table(ComponentId id, CubicSpline spline, TableOrigin origin, CubicSpline uncertainty) {
  if (uncertainty.knots() != spline.knots() || uncertainty.periodic() != spline.periodic())
    throw std::invalid_argument(fmt::format("{}: the uncertainty column needs the value column's knots and ends", info(id).name));
  ErrorSource s = table(id, std::move(spline), std::move(origin));
  s.uncertainty_ = std::move(uncertainty);
  s.has_uncertainty_ = true;
  return s;
}

double ErrorSource::value(double position) const noexcept {
  switch (kind_) {
  case Kind::Constant: return constant_ + offset_;
  case Kind::Polynomial: {
    double v = 0.0;
    for (auto it = coefficients_.rbegin(); it != coefficients_.rend(); ++it) v = v * position + *it; // Horner
    return v + offset_;
  }
  case Kind::Table: {
    const double v = spline_.value(position) + offset_;
    return draw_ == 0.0 ? v : v + draw_ * uncertainty(position);
  }
  }
  return 0.0;
}

double ErrorSource::uncertainty(double position) const noexcept {
  return has_uncertainty_ ? clamped_uncertainty(uncertainty_.value(position)) : 0.0;
}

ErrorSource ErrorSource::shifted(double offset) const {
  if (!std::isfinite(offset)) throw std::invalid_argument(fmt::format("{}: offset {} is not finite", info(id_).name, offset));
  ErrorSource s = *this;
  s.offset_ += offset;
  return s;
}

ErrorSource ErrorSource::drawn(double z, double default_u) const {
  if (!has_uncertainty_) return shifted(default_u * z); // the scene's constant u: as before u columns existed
  if (!std::isfinite(z)) throw std::invalid_argument(fmt::format("{}: draw {} is not finite", info(id_).name, z));
  ErrorSource s = *this;
  s.draw_ += z;
  return s;
}

double ErrorSource::rate(double position) const noexcept {
  switch (kind_) {
  case Kind::Constant: return 0.0;
  case Kind::Polynomial: {
    double v = 0.0;
    for (std::size_t i = coefficients_.size(); i-- > 1;) v = v * position + static_cast<double>(i) * coefficients_[i];
    return v;
  }
  case Kind::Table: {
    const double d = spline_.derivative(position);
    if (draw_ == 0.0) return d;
    // d/dp of draw·max(u(p), 0): the column's slope where u(p) > 0, zero where it is held at 0.
    return uncertainty_.value(position) > 0.0 ? d + draw_ * uncertainty_.derivative(position) : d;
  }
  }
  return 0.0;
}

std::string ErrorSource::describe() const {
  switch (kind_) {
  case Kind::Constant: return "constant";
  case Kind::Polynomial: return fmt::format("polynomial of degree {}", coefficients_.size() - 1);
  case Kind::Table:
    if (has_uncertainty_)
      return fmt::format("table {} column {} '{}' (standard uncertainty: column {} '{}')", origin_.file, origin_.column,
                         origin_.field, origin_.uncertainty_column, origin_.uncertainty_field);
    return fmt::format("table {} column {} '{}'", origin_.file, origin_.column, origin_.field);
  }
  return {};
}

} // namespace geartopo::machine
