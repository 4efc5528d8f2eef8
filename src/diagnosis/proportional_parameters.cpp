// geartopo diagnosis — a user's law's proportional parameters (proportional_parameters.hpp). Units: µm.
#include "proportional_parameters.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>

namespace geartopo::diagnosis {
namespace {

constexpr double kRelative = 1e-9; // of the fields' size: what rounding leaves of an exact proportionality

/// The first parameter of S that fails a check at the setting `others` (S at 0 there), or none when all pass.
std::optional<std::size_t> first_failing(const std::vector<std::size_t>& S, std::vector<double> others,
                                         const std::vector<effects::ParameterSpec>& specs,
                                         const std::function<Eigen::VectorXd(const std::vector<double>&)>& field) {
  for (std::size_t k : S) others[k] = 0.0;
  const Eigen::VectorXd zero = field(others);
  std::vector<Eigen::VectorXd> single; // d(a e_k)
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(zero.size());
  std::vector<double> all = others;
  double size = 0.0;
  for (std::size_t k : S) {
    const double a = specs[k].typical;
    std::vector<double> v1 = others, v2 = others;
    v1[k] = a, v2[k] = 2.0 * a, all[k] = a;
    const Eigen::VectorXd f1 = field(v1), f2 = field(v2);
    if (!f1.allFinite() || !f2.allFinite() || f1.norm() == 0.0) return k;
    if ((f2 - 2.0 * f1).norm() > kRelative * (f1.norm() + f2.norm())) return k;
    size += f1.norm();
    sum += f1;
  }
  if (!zero.allFinite() || zero.norm() > kRelative * size) return S.empty() ? std::nullopt : std::optional(S.front());
  if (S.size() > 1 && (field(all) - sum).norm() > kRelative * size) return S.back();
  return std::nullopt;
}

} // namespace

std::vector<std::size_t> proportional_parameters(const effects::Effect& effect, const EffectContribution& at, int threads) {
  const auto& specs = effect.parameters();
  std::vector<std::size_t> S;
  for (std::size_t k = 0; k < specs.size(); ++k)
    if (specs[k].fitted && !specs[k].whole && specs[k].lo <= 0.0 && specs[k].hi >= 0.0 && specs[k].typical > 0.0)
      S.push_back(k);
  if (S.empty()) return S;
  const std::unique_ptr<effects::Effect> copy = effect.clone();
  const auto field = [&](const std::vector<double>& v) {
    copy->set_values(v);
    const effects::Effect* one[] = {copy.get()};
    return Eigen::VectorXd(at.deviation_um(one, threads));
  };
  const std::vector<double> neutral = effect.values();
  std::vector<double> moved = neutral;
  for (std::size_t k = 0; k < specs.size(); ++k)
    if (specs[k].fitted) moved[k] = neutral[k] + 0.37 * (specs[k].hi - neutral[k]);
  for (bool changed = true; changed && !S.empty();) {
    changed = false;
    for (const auto& setting : {neutral, moved})
      if (const auto bad = first_failing(S, setting, specs, field)) {
        S.erase(std::find(S.begin(), S.end(), *bad));
        changed = true;
        break;
      }
  }
  return S;
}

} // namespace geartopo::diagnosis
