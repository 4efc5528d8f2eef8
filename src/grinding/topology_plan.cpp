#include "geartopo/grinding/topology_plan.hpp"

#include "geartopo/core/parallel.hpp"
#include "geartopo/core/units.hpp"

namespace geartopo::grinding {

TopologyPlan::TopologyPlan(const GrindingSetup& setup, const SimulationOptions& options)
    : setup_(setup), options_(options) {
  options_.progress = nullptr;
  const SimulationPoints pts = simulation_points(setup, options);
  const IdealProcess ideal; // the targets do not depend on the process
  const FlankDeviation dev(setup.flanks(), setup.wheel(), setup.path(), ideal);
  const auto grid = [&](int tooth, geartopo::Flank flank, const std::vector<double>& xis, const std::vector<double>& zs) {
    std::vector<FlankDeviation::Target> out;
    out.reserve(xis.size() * zs.size());
    for (double xi : xis)
      for (double z : zs) out.push_back(dev.target(tooth, flank, xi, z));
    return out;
  };
  for (const int tooth : pts.teeth)
    for (const auto flank : {geartopo::Flank::Left, geartopo::Flank::Right}) {
      FlankPlan f{tooth, flank, grid(tooth, flank, pts.rows, pts.cols), {}, {}, {}};
      for (double xi : pts.profile_roll_lengths) f.profile.push_back(dev.target(tooth, flank, xi, pts.profile_z_mm));
      for (double z : pts.helix_z) f.helix.push_back(dev.target(tooth, flank, pts.helix_roll_length_mm, z));
      if (!pts.dense_rows.empty()) f.dense = grid(tooth, flank, pts.dense_rows, pts.dense_cols);
      flanks_.push_back(std::move(f));
    }
  // The depth's curvature along Z per target, from the ideal process (3 poses each, once per plan): with it every
  // simulate() asks 3 poses per point instead of 4 (FlankDeviation::at). Each flank writes its own targets, so the
  // result does not depend on the thread count.
  parallel_for(static_cast<int>(flanks_.size()), options.threads, [&](int i) {
    FlankPlan& f = flanks_[static_cast<size_t>(i)];
    for (auto* targets : {&f.grid, &f.profile, &f.helix, &f.dense})
      for (auto& t : *targets) t.depth_curvature_per_mm = dev.depth_curvature_per_mm(t);
  });
  rows_ = pts.rows;
  cols_ = pts.cols;
  prof_xi_ = pts.profile_roll_lengths;
  helix_z_ = pts.helix_z;
  dense_rows_ = pts.dense_rows;
  dense_cols_ = pts.dense_cols;
  prof_z_ = pts.profile_z_mm;
  helix_xi_ = pts.helix_roll_length_mm;
}

long long TopologyPlan::points() const {
  long long n = 0;
  for (const auto& f : flanks_)
    n += static_cast<long long>(f.grid.size() + f.profile.size() + f.helix.size() + f.dense.size());
  return n;
}

std::vector<LinearContact> TopologyPlan::linear_contacts() const {
  const IdealProcess ideal; // the contacts do not depend on the process
  const FlankDeviation dev(setup_.flanks(), setup_.wheel(), setup_.path(), ideal);
  std::vector<LinearContact> out;
  out.reserve(static_cast<size_t>(points()));
  for (const auto& f : flanks_)
    for (const auto* targets : {&f.grid, &f.profile, &f.helix, &f.dense})
      for (const auto& t : *targets) out.push_back(dev.linear_contact(t));
  return out;
}

std::vector<FlankTopology> TopologyPlan::simulate(const GrindingProcess& process, int threads) const {
  const auto& g = setup_.geometry();
  const FlankDeviation dev(setup_.flanks(), setup_.wheel(), setup_.path(), process);
  const Method method = options_.method;
  const auto deviation_um = [&](const FlankDeviation::Target& t) { return units::um_from_mm(dev.at(t, method).deviation_mm); };
  const auto grid = [&](const std::vector<FlankDeviation::Target>& targets, const std::vector<double>& xis,
                        const std::vector<double>& zs) {
    std::vector<GridPoint> out;
    out.reserve(targets.size());
    for (size_t r = 0; r < xis.size(); ++r)
      for (size_t c = 0; c < zs.size(); ++c)
        out.push_back({static_cast<int>(r + 1), static_cast<int>(c + 1), xis[r], g.diameter_at_roll_length(xis[r]), zs[c],
                       deviation_um(targets[r * zs.size() + c])});
    return out;
  };

  std::vector<FlankTopology> out(flanks_.size());
  parallel_for(static_cast<int>(out.size()), threads, [&](int i) {
    const FlankPlan& f = flanks_[static_cast<size_t>(i)];
    FlankTopology& ft = out[static_cast<size_t>(i)];
    ft.tooth = f.tooth;
    ft.flank = f.flank;
    ft.grid = grid(f.grid, rows_, cols_);
    ft.profile.reserve(f.profile.size());
    for (size_t k = 0; k < f.profile.size(); ++k)
      ft.profile.push_back({prof_xi_[k], g.diameter_at_roll_length(prof_xi_[k]), prof_z_, deviation_um(f.profile[k])});
    ft.helix.reserve(f.helix.size());
    const double helix_d = g.diameter_at_roll_length(helix_xi_);
    for (size_t k = 0; k < f.helix.size(); ++k) ft.helix.push_back({helix_xi_, helix_d, helix_z_[k], deviation_um(f.helix[k])});
    if (!f.dense.empty()) ft.dense = grid(f.dense, dense_rows_, dense_cols_);
  });
  require_all_reached(out);
  attach_design(out, setup_.design());
  return out;
}

} // namespace geartopo::grinding
