#include "geartopo/diagnosis/effect_contribution.hpp"

#include "geartopo/machine/first_order.hpp"

#include "geartopo/core/parallel.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/datum_shift.hpp"
#include "geartopo/machine/jacobian.hpp"

#include <algorithm>

namespace geartopo::diagnosis {
namespace {

// Points per parallel task: one task per point would drown the work in scheduling.
constexpr int kChunk = 1024;

// keep_going (may be empty) is called before each chunk; an exception from it stops parallel_for.
template <class Fn>
void for_chunks(std::size_t n, int threads, Fn&& per_point, const std::function<void()>& keep_going = {}) {
  const int count = static_cast<int>((n + kChunk - 1) / kChunk);
  geartopo::parallel_for(count, threads, [&](int c) {
    if (keep_going) keep_going();
    const std::size_t end = std::min(n, static_cast<std::size_t>(c + 1) * kChunk);
    for (std::size_t i = static_cast<std::size_t>(c) * kChunk; i < end; ++i) per_point(i);
  });
}

} // namespace

machine::Matrix65 EffectContribution::J_twistw_axes(const machine::AxisPose& q) const {
  if (chain_ == nullptr) return machine::J_twistw_q(q);
  // The chain's axes at z + z₀, their twist moved back to the datum (as effects::EffectsProcess does).
  machine::AxisPose at = q;
  at.z += datum_face_z_mm_;
  machine::Matrix65 J = machine::J_twistw_theta(*chain_, chain_->axes(at));
  machine::twists_at_datum(J, datum_face_z_mm_);
  return J;
}

EffectContribution::EffectContribution(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts,
                                       int threads, const machine::KinematicChain* chain, double datum_face_z_mm,
                                       const std::function<void()>& keep_going)
    : points_(pts.size()), offset_um_(mean_allowance_offset_um(setup.geometry())),
      chain_(chain != nullptr && !chain->is_setting_chain() ? chain : nullptr), datum_face_z_mm_(datum_face_z_mm) {
  const grinding::IdealProcess ideal; // the contact does not depend on the process
  const grinding::FlankDeviation dev(setup.flanks(), setup.wheel(), setup.path(), ideal);
  for_chunks(pts.size(), threads, [&](std::size_t i) {
    const auto& p = pts[i];
    const grinding::LinearContact c = dev.linear_contact(p.tooth, p.flank, p.roll_length_mm, p.z_mm);
    PointState& s = points_[i];
    s.pp = c.pp;
    s.w << c.n, c.p.cross(c.n);
    s.a_q = J_twistw_axes(c.pp.q).transpose() * s.w; // 5×6 · 6
    s.v = c.v;
    s.normal_per_radial = c.normal_per_radial;
  }, keep_going);
}

// effects::EffectsProcess over the ideal machine, first order (effects_process.cpp): the twist is
// J_twistw_q(q)·(commanded − q) (on another chain J_twistw_theta·δθ) + Σ pose_error_twist(table_in_gear), the wheel's radius error Σ δR_e(v); and
// grinding::linear_deviation_mm makes n·(δp + δθ × P) − δR·normal_per_radial of them. With n·(δθ × P) = δθ·(P × n)
// that is a_qᵀ δq + wᵀ ξ_table − δR·normal_per_radial (mm).
Eigen::VectorXd EffectContribution::deviation_um(std::span<const effects::Effect* const> effects, int threads) const {
  // A table pose that does not depend on the path point (eccentricity's clamping) is the same twist at every point:
  // formed once here, added per point in the same order as before, so the sums are the same bits.
  struct Table {
    bool constant = false;
    bool identity = true;      ///< an identity pose adds exactly zero, and is skipped
    machine::Vector6d twist{}; ///< 6: pose_error_twist of the constant pose
  };
  std::vector<Table> tables(effects.size());
  for (std::size_t k = 0; k < effects.size(); ++k) {
    if (!effects[k]->table_in_gear_is_constant()) continue;
    const machine::Pose wMc = effects[k]->table_in_gear(points_.empty() ? grinding::PathPoint{} : points_.front().pp);
    tables[k].constant = true;
    tables[k].identity = wMc.matrix().isIdentity(0.0);
    if (!tables[k].identity) tables[k].twist = machine::pose_error_twist(wMc);
  }
  // An effect that evaluates in batches (a Python law: one call per batch) at every point first, chunk by chunk — the
  // chunks are fixed by kChunk, not by the thread count, so each call sees the same points at any thread count.
  std::vector<std::vector<double>> batched(effects.size());
  for (std::size_t k = 0; k < effects.size(); ++k)
    if (effects[k]->evaluates_in_batches()) batched[k] = batched_radius_mm(*effects[k], threads);
  Eigen::VectorXd out(static_cast<Eigen::Index>(points_.size()));
  for_chunks(points_.size(), threads, [&](std::size_t i) {
    const PointState& s = points_[i];
    machine::Vector5d offset = machine::Vector5d::Zero();
    machine::Vector6d table = machine::Vector6d::Zero();
    double radius_mm = 0.0;
    for (std::size_t k = 0; k < effects.size(); ++k) {
      const effects::Effect& e = *effects[k];
      offset += e.command_offset(s.pp);
      if (tables[k].constant) {
        if (!tables[k].identity) table += tables[k].twist;
      } else {
        const machine::Pose wMc = e.table_in_gear(s.pp);
        if (!wMc.matrix().isIdentity(0.0)) table += machine::pose_error_twist(wMc); // identity: exactly zero
      }
      radius_mm += batched[k].empty() ? e.wheel_radius_error_mm(s.v, s.pp) : batched[k][i];
    }
    // The commanded axes minus the nominal ones, as EffectsProcess forms them (the same rounding); on another chain
    // its own axes' offsets, each effect's by the role of the axis (effects::chain_offsets).
    const machine::Vector5d dq =
        chain_ == nullptr ? machine::Vector5d((s.pp.q.vector() + offset) - s.pp.q.vector())
                          : effects::chain_offsets(*chain_, offset);
    const double deviation_mm = s.a_q.dot(dq) + s.w.dot(table) - radius_mm * s.normal_per_radial;
    out(static_cast<Eigen::Index>(i)) = units::um_from_mm(deviation_mm);
  });
  return out;
}

std::vector<double> EffectContribution::batched_radius_mm(const effects::Effect& e, int threads) const {
  std::vector<double> out(points_.size());
  const int count = static_cast<int>((points_.size() + kChunk - 1) / kChunk);
  geartopo::parallel_for(count, threads, [&](int c) {
    const std::size_t begin = static_cast<std::size_t>(c) * kChunk, end = std::min(points_.size(), begin + kChunk);
    std::vector<double> v;
    std::vector<grinding::PathPoint> pp;
    for (std::size_t i = begin; i < end; ++i) v.push_back(points_[i].v), pp.push_back(points_[i].pp);
    e.wheel_radius_errors_mm(v, pp, std::span<double>(out).subspan(begin, end - begin));
  });
  return out;
}

EffectContribution EffectContribution::rows(std::span<const std::size_t> indices) const {
  EffectContribution out;
  out.offset_um_ = offset_um_;
  out.chain_ = chain_;
  out.datum_face_z_mm_ = datum_face_z_mm_;
  out.points_.reserve(indices.size());
  for (const std::size_t i : indices) out.points_.push_back(points_.at(i));
  return out;
}

Eigen::MatrixXd EffectContribution::component_sensitivity_um(int threads, const std::function<void()>& keep_going) const {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(points_.size()), machine::kComponentCount); // n × 43
  for_chunks(points_.size(), threads, [&](std::size_t i) {
    // At the machine's axes, z + z₀ (the error map's positions, the C table and the X slide z₀ below the datum), the
    // twist moved back to the datum by Tz(−z₀): what MachineProcess / ChainProcess::error_twist_w do with the map.
    machine::AxisPose q = points_[i].pp.q;
    q.z += datum_face_z_mm_;
    machine::Matrix6E J_twistw_e;
    if (chain_ != nullptr) {
      machine::Matrix6E J_twistg_e;
      machine::error_jacobians(*chain_, chain_->axes(q), J_twistw_e, J_twistg_e);
    } else {
      machine::MachineData data;
      machine::error_jacobians(q, data);
      J_twistw_e = data.J_twistw_e;
    }
    machine::twists_at_datum(J_twistw_e, datum_face_z_mm_);
    out.row(static_cast<Eigen::Index>(i)) = units::um_from_mm(1.0) * (points_[i].w.transpose() * J_twistw_e);
  }, keep_going);
  return out;
}

Eigen::VectorXd EffectContribution::evaluate_um(const std::vector<std::unique_ptr<effects::Effect>>& effects,
                                                int threads) const {
  std::vector<const effects::Effect*> list;
  for (const auto& e : effects) list.push_back(e.get());
  Eigen::VectorXd out = deviation_um(list, threads);
  out.array() += offset_um_;
  return out;
}

} // namespace geartopo::diagnosis
