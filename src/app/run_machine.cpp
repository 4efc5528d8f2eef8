#include "app/machine_command.hpp"

#include "app/commands.hpp"
#include "app/messages.hpp"

#include "geartopo/core/units.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/jacobian.hpp"
#include "geartopo/machine/machine_data.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iostream>

namespace geartopo::app {
namespace {

nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

// (mm; rad) → (µm; µrad)
nlohmann::json twist_json(const machine::Vector6d& t) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) out.push_back(i < 3 ? units::um_from_mm(t(i)) : units::urad_from_rad(t(i)));
  return out;
}

std::string matrix_text(const Eigen::MatrixXd& m, int width = 12, int prec = 6) {
  std::string s;
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    s += "   ";
    for (Eigen::Index c = 0; c < m.cols(); ++c) s += fmt::format(" {:>{}.{}f}", m(r, c), width, prec);
    s += "\n";
  }
  return s;
}

} // namespace

int run_machine(const MachineOptions& opt) {
  const Workbench wb(opt.scene);
  const auto& p = opt.pose;
  const machine::AxisPose q{p[0], p[1], p[2], p[3] * units::kRadPerDeg, p[4] * units::kRadPerDeg};
  if (!wb.machine.within_strokes(q))
    say("geartopo: warning: the pose lies outside the machine's strokes; tables are extrapolated");
  machine::MachineData data;
  const machine::Pose ideal = machine::ideal_wMg(q);
  const machine::Pose actual = machine::actual_wMg(wb.machine, data, q);
  const auto exact = machine::exact_pose_error(wb.machine, data, q);
  const auto linear = machine::twist_linear(wb.machine, data, q);
  const machine::Matrix65 J = machine::J_twistg_q(q);
  if (opt.json) {
    nlohmann::json j;
    j["pose"] = {{"X_mm", p[0]}, {"Y_mm", p[1]}, {"Z_mm", p[2]}, {"A_deg", p[3]}, {"C_deg", p[4]}};
    j["ideal"] = matrix_json(ideal.matrix());
    j["actual_exact"] = matrix_json(actual.matrix());
    j["twist_exact"] = twist_json(exact.w);
    j["twist_linear"] = twist_json(linear.w);
    j["twist_exact_wheel"] = twist_json(exact.g);
    j["twist_linear_wheel"] = twist_json(linear.g);
    j["twist_units"] = "translation µm (x, y, z) then rotation µrad (x, y, z); twist_* in the workpiece frame, "
                       "twist_*_wheel in the wheel frame";
    j["jacobian"] = matrix_json(J);
    j["jacobian_units"] = "wheel-frame twist (mm; rad) per unit command; columns X, Y, Z per mm, A, C per rad";
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("Axes X {} mm, Y {} mm, Z {} mm, A {}°, C {}°\n", p[0], p[1], p[2], p[3], p[4]);
  std::cout << "ideal wheel pose wMg (Eq. 11, mm):\n" << matrix_text(ideal.matrix());
  std::cout << "actual wheel pose wMg, exact chain (mm):\n" << matrix_text(actual.matrix());
  const auto row = [](const char* name, const machine::Vector6d& t) {
    return fmt::format("  {:<22} δp = ({:9.3f} {:9.3f} {:9.3f}) µm   δθ = ({:9.3f} {:9.3f} {:9.3f}) µrad\n", name,
                       units::um_from_mm(t(0)), units::um_from_mm(t(1)), units::um_from_mm(t(2)), units::urad_from_rad(t(3)), units::urad_from_rad(t(4)), units::urad_from_rad(t(5)));
  };
  std::cout << "pose error twist, workpiece frame:\n" << row("exact", exact.w) << row("first order", linear.w);
  std::cout << "pose error twist, wheel frame:\n" << row("exact", exact.g) << row("first order", linear.g);
  std::cout << "Jacobian J_M (wheel-frame twist per X, Y, Z [per mm], A, C [per rad]):\n" << matrix_text(J, 11, 5);
  return 0;
}

} // namespace geartopo::app
