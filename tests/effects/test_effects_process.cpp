// EffectsProcess: its first-order error twist (used by the linear method and by diagnosis's fits) is the
// linearisation of its exact pose, for every library effect on top of the default machine.
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

using namespace geartopo;

namespace {

const workbench::Workbench& default_scene() {
  static const workbench::Workbench wb(std::filesystem::path(GEARTOPO_SOURCE_DIR) / "scenes/skmc1200w-mn14-z35.yaml");
  return wb;
}

// The largest |linear − exact| and the largest |exact| over path points spread over the whole grinding order.
std::pair<double, double> linear_vs_exact(const grinding::GrindingProcess& p, const grinding::GrindingSetup& s) {
  double worst = 0.0, size = 0.0;
  const auto& strokes = s.path().strokes();
  for (size_t k = 0; k < strokes.size(); k += 7)
    for (double f : {0.0, 0.5, 1.0}) {
      const auto& st = strokes[k];
      const auto pp = s.path().point(st.space, st.z_begin_mm + f * (st.z_end_mm - st.z_begin_mm));
      const machine::Vector6d exact = machine::pose_error_twist(p.actual_wMg(pp) * machine::ideal_wMg(pp.q).inverse());
      worst = std::max(worst, (p.error_twist_w(pp) - exact).cwiseAbs().maxCoeff());
      size = std::max(size, exact.cwiseAbs().maxCoeff());
    }
  return {worst, size};
}

class EveryEffect : public ::testing::TestWithParam<std::string> {};

// Each parameter at its typical magnitude: the twists agree to 1 % of their size (second order in µm and µrad
// errors is far below that), and the effect does change the twist.
TEST_P(EveryEffect, FirstOrderTwistIsTheLinearisationOfTheExactPose) {
  const auto& wb = default_scene();
  auto e = effects::make_effect(GetParam());
  std::vector<double> v = e->values();
  for (size_t k = 0; k < v.size(); ++k)
    if (e->parameters()[k].fitted) v[k] = e->parameters()[k].typical;
  e->set_values(v);
  e->bind(wb.setup);
  const effects::EffectsProcess with(wb.machine_process, {e.get()});
  const auto [worst, size] = linear_vs_exact(with, wb.setup);
  const double size0 = linear_vs_exact(wb.machine_process, wb.setup).second;
  EXPECT_LT(worst, 0.01 * size + 1e-9) << "size " << size;
  // these change the wheel's radius, not its pose
  if (GetParam() != "wheel_wear" && GetParam() != "wheel_profile" && GetParam() != "wheel_flank_profile" &&
      GetParam() != "wheel_profile_wear" && GetParam() != "wheel_flank_waviness") {
    EXPECT_NE(size, size0) << "the effect does not move the wheel";
  }
}

// An effect that says its table pose is the same at every path point (diagnosis then forms it once per evaluation)
// keeps its word: the hook itself, at path points over the whole grinding order (every stroke, its start, middle and
// end), gives the same pose bit for bit, with every fitted parameter away from zero. Eccentricity (a clamping error)
// is the library effect that says so; the others claim nothing and are not checked.
TEST(TablePose, DeclaredConstantIsTheSameAtEveryPathPoint) {
  const auto& wb = default_scene();
  std::vector<std::string> claiming;
  for (const auto& type : effects::effect_types()) {
    auto e = effects::make_effect(type);
    std::vector<double> v = e->values();
    for (size_t k = 0; k < v.size(); ++k)
      if (e->parameters()[k].fitted) v[k] = (k % 2 ? -3.0 : 2.0) * e->parameters()[k].typical;
    e->set_values(v);
    e->bind(wb.setup);
    if (!e->table_in_gear_is_constant()) continue;
    claiming.push_back(type);
    const auto& strokes = wb.setup.path().strokes();
    const auto& first = strokes.front();
    const machine::Pose reference = e->table_in_gear(wb.setup.path().point(first.space, first.z_begin_mm));
    for (const auto& st : strokes)
      for (double f : {0.0, 0.5, 1.0}) {
        const auto pp = wb.setup.path().point(st.space, st.z_begin_mm + f * (st.z_end_mm - st.z_begin_mm));
        EXPECT_EQ(e->table_in_gear(pp).matrix(), reference.matrix()) << type << ", space " << st.space << ", " << f;
      }
  }
  // Every library effect claims it: eccentricity mounts the gear once, the others keep the default identity table
  // (which lets diagnosis::EffectContribution skip the pose per point); each claim is checked above.
  EXPECT_EQ(claiming, effects::effect_types());
}

INSTANTIATE_TEST_SUITE_P(Library, EveryEffect, ::testing::ValuesIn(effects::effect_types()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

} // namespace
