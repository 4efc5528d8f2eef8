#include "geartopo/pipeline/topology_sensitivities.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/parallel.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/jacobian.hpp"
#include "geartopo/machine/machine_data.hpp"

#include <algorithm>
#include <memory>

namespace geartopo::pipeline {

std::vector<UncertainEffectValue> uncertain_effect_values(const scene::Scene& s) {
  std::vector<UncertainEffectValue> out;
  for (size_t e = 0; e < s.effects.size() && e < s.effect_uncertainties.size(); ++e) {
    const auto params = effects::make_effect(s.effects[e].type)->parameters();
    for (size_t v = 0; v < s.effect_uncertainties[e].size() && v < s.effects[e].values.size() && v < params.size(); ++v)
      out.push_back({e, v, s.effect_uncertainties[e][v], params[v].lo, params[v].hi});
  }
  for (size_t c = 0; c < s.machine_changes.size() && c < s.machine_change_uncertainties.size(); ++c) {
    if (!(s.machine_change_uncertainties[c] > 0.0)) continue;
    const auto& ch = s.machine_changes[c];
    const double limit = scene::machine_change_limit(ch.law, machine::info(ch.component).quantity);
    out.push_back({c, 0, s.machine_change_uncertainties[c], -limit, limit, true});
  }
  return out;
}

Eigen::VectorXd flatten_deviations(const std::vector<grinding::FlankTopology>& topo) {
  std::vector<double> d;
  for (const auto& ft : topo) {
    for (const auto& p : ft.grid) d.push_back(p.deviation_um);
    for (const auto& p : ft.profile) d.push_back(p.deviation_um);
    for (const auto& p : ft.helix) d.push_back(p.deviation_um);
    for (const auto& p : ft.dense) d.push_back(p.deviation_um);
  }
  return Eigen::Map<Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size()));
}

void set_deviations(std::vector<grinding::FlankTopology>& topo, const Eigen::VectorXd& deviation_um) {
  Eigen::Index i = 0;
  for (auto& ft : topo) {
    for (auto& p : ft.grid) p.deviation_um = deviation_um(i++);
    for (auto& p : ft.profile) p.deviation_um = deviation_um(i++);
    for (auto& p : ft.helix) p.deviation_um = deviation_um(i++);
    for (auto& p : ft.dense) p.deviation_um = deviation_um(i++);
  }
}

namespace {

std::vector<machine::ErrorSource> drawn_map(const workbench::Workbench& wb, double z) {
  std::vector<machine::ErrorSource> all;
  all.reserve(machine::kComponentCount);
  for (int k = 0; k < machine::kComponentCount; ++k) all.push_back(machine::ErrorSource::zero(machine::component_at(k)));
  for (const auto& s : wb.scene.machine.sources) all[static_cast<size_t>(machine::index(s.id()))] = s;
  for (int k = 0; k < machine::kComponentCount; ++k) {
    auto& s = all[static_cast<size_t>(k)];
    s = s.drawn(z, wb.scene.machine.uncertainty.component_u[static_cast<size_t>(k)]);
  }
  return all;
}

/// The process the nominal scene grinds with: its machine on its chain and its effects.
struct NominalProcess {
  NominalProcess(const workbench::Workbench& wb, const machine::MachineModel& model)
      : machine(workbench::make_machine_process(*wb.scene.machine.chain, model, wb.scene.machine.datum_face_z_mm)) {
    if (!wb.effects.empty())
      with_effects = std::make_unique<effects::EffectsProcess>(*machine, wb.effects, wb.scene.machine.chain,
                                                               wb.scene.machine.datum_face_z_mm);
  }
  const grinding::GrindingProcess& process() const {
    return with_effects ? static_cast<const grinding::GrindingProcess&>(*with_effects) : *machine;
  }
  std::unique_ptr<const grinding::GrindingProcess> machine;
  std::unique_ptr<effects::EffectsProcess> with_effects;
};

/// J_twistw_e (6×43) and the drawn change of each component e1 − e0 at the machine's axes for the command q (the datum
/// face shift z₀ added): the CFXZAY's closed form on its own axes, any other chain's Jacobian at its axes θ(q).
void map_twists(const machine::KinematicChain& chain, const machine::MachineModel& nominal,
                const machine::MachineModel& unit, machine::AxisPose q, double z0, machine::MachineData& data,
                machine::Matrix6E& J_twistw_e, machine::ErrorVector& e0, machine::ErrorVector& e1) {
  q.z += z0;
  if (chain.is_setting_chain()) {
    machine::error_jacobians(q, data);
    J_twistw_e = data.J_twistw_e;
    nominal.errors_at(q, e0);
    unit.errors_at(q, e1);
    return;
  }
  const machine::AxisValues theta = chain.axes(q);
  machine::Matrix6E J_twistg_e;
  machine::error_jacobians(chain, theta, J_twistw_e, J_twistg_e);
  machine::errors_at(nominal, theta, e0);
  machine::errors_at(unit, theta, e1);
}

} // namespace

TopologySensitivities topology_sensitivities(const workbench::Workbench& wb, const grinding::TopologyPlan& plan,
                                             const compensation::CorrectionTable& table, int threads) {
  const machine::MachineModel nominal_model(wb.machine.strokes(), drawn_map(wb, 0.0));
  const machine::MachineModel unit_model(wb.machine.strokes(), drawn_map(wb, 1.0)); // every component + its u
  const NominalProcess nominal(wb, nominal_model);
  const workbench::WithDesignMotion designed(wb, nominal.process());
  const compensation::CompensatedProcess ground(designed.process(), table);

  TopologySensitivities s;
  s.nominal_um = flatten_deviations(plan.simulate(ground, threads));
  const std::vector<grinding::LinearContact> contacts = plan.linear_contacts();
  const auto n = static_cast<Eigen::Index>(contacts.size());
  s.map_um.resize(n, machine::kComponentCount);
  s.stroke_um.resize(n, 5);
  s.space.resize(contacts.size());
  const double z0 = wb.scene.machine.datum_face_z_mm;
  // Per point: the row w = [n; P × n] of the linear deviation n·(δp + δθ × P) (6), times the twist per draw.
  constexpr int kBlock = 256; // points per task: the result does not depend on the blocking
  const int blocks = static_cast<int>((n + kBlock - 1) / kBlock);
  parallel_for(blocks, threads, [&](int b) {
    machine::MachineData data;
    machine::Matrix6E J_twistw_e;
    machine::ErrorVector e0, e1;
    for (Eigen::Index i = Eigen::Index(b) * kBlock; i < std::min<Eigen::Index>(n, Eigen::Index(b + 1) * kBlock); ++i) {
      const auto& c = contacts[static_cast<size_t>(i)];
      const grinding::PathPoint pp = ground.corrected(c.pp); // the command the machine receives (with the correction)
      Eigen::Matrix<double, 1, 6> w;
      w << c.n.transpose(), c.p.cross(c.n).transpose();
      // Map: twist in the machine's table frame per component J_twistw_e (6×43), scaled by the draw's change of
      // each component at the machine's axes (u, or u(p) of a table's column), then moved to the datum as
      // MachineProcess::error_twist_w and ChainProcess::error_twist_w do.
      map_twists(*wb.scene.machine.chain, nominal_model, unit_model, pp.q, z0, data, J_twistw_e, e0, e1);
      machine::Matrix6E twist = J_twistw_e * (e1 - e0).asDiagonal();
      for (int k = 0; k < machine::kComponentCount; ++k)
        twist.col(k).head<3>() += Eigen::Vector3d(0.0, 0.0, -z0).cross(Eigen::Vector3d(twist.col(k).tail<3>()));
      s.map_um.row(i) = units::um_from_mm(1.0) * (w * twist);
      // Stroke offset: as a correction of the table's axes (the chain's own; the setting's on the CFXZAY: J_twistw_q)
      // at the commanded pose (CompensatedProcess::error_twist_w).
      s.stroke_um.row(i) = units::um_from_mm(1.0) * (w * table.axes().J_twistw(c.pp.q));
      s.space[static_cast<size_t>(i)] = c.pp.space;
    }
  });

  return s;
}

} // namespace geartopo::pipeline
