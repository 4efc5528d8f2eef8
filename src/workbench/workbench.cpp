#include "geartopo/workbench/workbench.hpp"

#include "geartopo/effects/component_changes.hpp"
#include "geartopo/compensation/design_motion.hpp"

#include "geartopo/core/field_error.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/effects/custom_effect.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/wheel_setting.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <utility>

namespace geartopo::workbench {
namespace {

bool outside(double v, const machine::Interval& iv) { return v < iv.min - 1e-9 || v > iv.max + 1e-9; }

/// The wheel's position against the X, Y and A strokes. Checked before the form wheel is synthesised: it is cheap,
/// and a gear far too big for the machine would otherwise fail inside the synthesis with a message naming no field.
void check_wheel_position(const scene::Scene& s) {
  const gears::GearGeometry geometry(s.gear);
  const auto set = grinding::make_wheel_setting(geometry, s.wheel.outer_diameter_mm, s.wheel.axial_position_mm);
  const auto& st = s.machine.strokes;
  if (outside(set.centre_distance_mm, st.x_mm))
    s.fail_at("wheel.outer_diameter_mm", fmt::format("puts X at the centre distance {:.3f} mm, outside the X stroke "
                                                     "[{}, {}] mm",
                                                     set.centre_distance_mm, st.x_mm.min, st.x_mm.max));
  if (outside(set.axial_position_mm, st.y_mm))
    s.fail_at("wheel.axial_position_mm",
              fmt::format("{} mm is outside the Y stroke [{}, {}] mm", set.axial_position_mm, st.y_mm.min, st.y_mm.max));
  const double a_deg = units::deg_from_rad(set.tilt_rad);
  if (outside(a_deg, st.a_deg))
    s.fail_at("gear.helix_angle_deg",
              fmt::format("needs A = {:.3f}°, outside the A stroke [{}, {}]°", a_deg, st.a_deg.min, st.a_deg.max));
}

/// The grinding set-up (form wheel, path), its errors located at the scene field they concern.
grinding::GrindingSetup located_setup(const scene::Scene& s) {
  try {
    // The CFXZAY's axes are the setting's: its strokes are checked here, any other chain's on the path (check_chain).
    if (s.machine.chain->is_setting_chain()) check_wheel_position(s);
    return grinding::GrindingSetup(s.gear, s.wheel, s.process);
  } catch (const InputError&) {
    throw;
  } catch (const FieldError& e) {
    s.fail_at(e.field(), e.what());
  } catch (const std::runtime_error& e) {
    s.fail_at("wheel", e.what());
  }
}

/// A wheel too large for a small gear (m_n 1, β 30° with 350 mm) cannot be synthesised: its envelope folds or its tip
/// stays above the root form circle. When the scene gives no diameter, the largest of kWheelDiametersToTryMm that
/// works is taken and said in `notes`; when the scene gives one that does not work, the error says which would.
grinding::GrindingSetup setup_with_a_wheel_that_fits(scene::Scene& s, std::vector<std::string>& notes) {
  try {
    return located_setup(s);
  } catch (const InputError& first) {
    if (std::string_view(first.what()).find("form wheel:") == std::string_view::npos) throw;
    const bool given = s.positions.count("wheel.outer_diameter_mm") != 0;
    const double asked = s.wheel.outer_diameter_mm;
    for (const double d : kWheelDiametersToTryMm) {
      if (d >= asked) continue;
      scene::Scene trial = s;
      trial.wheel.outer_diameter_mm = d;
      try {
        auto setup = located_setup(trial);
        if (given)
          s.fail_at("wheel.outer_diameter_mm",
                    fmt::format("{} mm does not fit this gear ({}); a {} mm wheel does (the largest of {} mm that does)",
                                asked, std::string_view(first.what()).substr(std::string_view(first.what()).find("form wheel:")),
                                d, fmt::join(kWheelDiametersToTryMm, ", ")));
        s.wheel.outer_diameter_mm = d;
        notes.push_back(fmt::format("wheel.outer_diameter_mm is not given and the default {} mm does not fit this gear: "
                                    "using {} mm, the largest of {} mm that does",
                                    asked, d, fmt::join(kWheelDiametersToTryMm, ", ")));
        return setup;
      } catch (const InputError& e) {
        if (given && std::string_view(e.what()).find("does not fit this gear") != std::string_view::npos) throw;
      }
    }
    throw;
  }
}

/// Every stroke's Z travel (datum face at machine Z = datum_face_z_mm) against the Z stroke.
void check_strokes(const scene::Scene& s, const grinding::GrindingSetup& setup) {
  const auto& z_stroke = s.machine.strokes.z_mm;
  for (const auto& stroke : setup.path().strokes()) {
    const double lo = std::min(stroke.z_begin_mm, stroke.z_end_mm) + s.machine.datum_face_z_mm;
    const double hi = std::max(stroke.z_begin_mm, stroke.z_end_mm) + s.machine.datum_face_z_mm;
    if (outside(lo, z_stroke) || outside(hi, z_stroke))
      s.fail_at("machine.datum_face_z_mm",
                fmt::format("the strokes run from Z = {:.3f} to {:.3f} mm, outside the Z stroke [{}, {}] mm", lo, hi,
                            z_stroke.min, z_stroke.max));
  }
}

/// A chain other than the CFXZAY: every path point reachable within its strokes and not singular, else the point and
/// the axis named at the scene's chain.
void check_chain(const scene::Scene& s, const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process) {
  const auto* chain = dynamic_cast<const grinding::ChainProcess*>(&process);
  if (chain == nullptr) return;
  try {
    chain->check_path(setup.path());
  } catch (const std::runtime_error& e) {
    s.fail_at(s.positions.count("machine.chain_file") != 0 ? "machine.chain_file" : "machine.chain", e.what());
  }
}

/// The design motions within the strokes: on the CFXZAY the count of samples outside; on any other chain the first
/// sample outside named with the axis and its stroke, as check_chain names a path point.
void check_design_motion(const scene::Scene& s, const compensation::CorrectionTable& motion) {
  const int count = motion.rows_outside_strokes();
  if (count == 0) return;
  std::string first;
  if (!motion.axes().is_setting()) {
    const auto& chain = *motion.axes().chain;
    for (const auto& r : motion.rows()) {
      const auto v = chain.outside_stroke(machine::AxisValues{r.machine_axes.vector() + r.correction});
      if (!v) continue;
      first = fmt::format(", first at space {}, Z = {:.3f} mm: {}", r.space, r.z_stroke_mm, v->message);
      break;
    }
  }
  s.fail_at("gear.modifications",
            fmt::format("the motions that grind the helix modifications leave the {} strokes at {} of {} path "
                        "samples{}",
                        motion.axes().is_setting() ? std::string("machine's")
                                                   : fmt::format("{} chain's", motion.axes().chain->name()),
                        count, motion.rows().size(), first));
}

} // namespace

std::unique_ptr<const grinding::GrindingProcess> make_machine_process(const machine::KinematicChain& chain,
                                                                      const machine::MachineModel& model,
                                                                      double datum_face_z_mm) {
  if (chain.is_setting_chain()) return std::make_unique<const grinding::MachineProcess>(model, datum_face_z_mm);
  return std::make_unique<const grinding::ChainProcess>(chain, model, datum_face_z_mm);
}

Workbench::Workbench(scene::Scene s, const std::function<void()>& keep_going)
    : scene(std::move(s)), setup(setup_with_a_wheel_that_fits(scene, notes)), machine(scene.machine.model()),
      machine_process_owner(make_machine_process(*scene.machine.chain, machine, scene.machine.datum_face_z_mm)),
      machine_process(*machine_process_owner), effects(make_effects(scene.effects, scene.machine_changes, setup, scene.machine.chain,
                                                              scene.machine.datum_face_z_mm)) {
  if (keep_going) keep_going();
  if (scene.machine.chain->is_setting_chain()) check_strokes(scene, setup);
  check_chain(scene, setup, machine_process);
  if (!effects.empty())
    effects_process = std::make_unique<effects::EffectsProcess>(machine_process, effects, scene.machine.chain,
                                                                scene.machine.datum_face_z_mm);
  if (setup.design().modifications().has_helix()) {
    design_motion = std::make_unique<compensation::CorrectionTable>(compensation::design_motions(
        setup, scene.process.lead_crowning, {machine, scene.machine.datum_face_z_mm, scene.machine.chain}));
    check_design_motion(scene, *design_motion);
    design_process = std::make_unique<compensation::CompensatedProcess>(machine_and_effects(), *design_motion);
  }
  if (!scene.custom_effects.empty()) {
    check_custom_effects_finite(keep_going);
    build_diagnosis_model();
  }
}

void Workbench::build_diagnosis_model() {
  std::vector<scene::EffectSpec> known;
  for (const auto& e : scene.effects)
    if (std::find(scene.custom_effects.begin(), scene.custom_effects.end(), e.type) == scene.custom_effects.end())
      known.push_back(e);
  known_effects_ = make_effects(known, scene.machine_changes, setup, scene.machine.chain, scene.machine.datum_face_z_mm);
  const grinding::GrindingProcess* base = &machine_process;
  if (!known_effects_.empty()) {
    known_effects_process_ = std::make_unique<effects::EffectsProcess>(machine_process, known_effects_,
                                                                       scene.machine.chain, scene.machine.datum_face_z_mm);
    base = known_effects_process_.get();
  }
  diagnosis_model_ = base;
  if (design_motion) {
    known_design_process_ = std::make_unique<compensation::CompensatedProcess>(*base, *design_motion);
    diagnosis_model_ = known_design_process_.get();
  }
}

void Workbench::check_custom_effects_finite(const std::function<void()>& keep_going) const {
  // The scene's grid on every tooth it measures (all when it names none), both flanks, at the generating contact:
  // the first point in this fixed order whose value is not finite is named, whatever the thread count later.
  const grinding::IdealProcess ideal;
  const grinding::FlankDeviation generating(setup.flanks(), setup.wheel(), setup.path(), ideal);
  std::vector<int> teeth = scene.grid.teeth;
  if (teeth.empty())
    for (int t = 1; t <= setup.geometry().teeth(); ++t) teeth.push_back(t);
  const auto& r = setup.ranges();
  for (std::size_t i = 0; i < scene.effects.size(); ++i) {
    const auto named = std::find(scene.custom_effects.begin(), scene.custom_effects.end(), scene.effects[i].type);
    if (named == scene.custom_effects.end()) continue;
    const std::string field = fmt::format("custom_effects[{}].deviation_um", named - scene.custom_effects.begin());
    std::vector<double> v;
    std::vector<grinding::PathPoint> pp;
    for (int tooth : teeth)
      for (const auto flank : {Flank::Left, Flank::Right})
        for (int a = 0; a < scene.grid.rows; ++a) {
          if (keep_going) keep_going(); // a 300 × 300 grid on 35 teeth takes seconds
          for (int b = 0; b < scene.grid.cols; ++b) {
            const double xi = r.xi_eval_start_mm + (r.xi_eval_end_mm - r.xi_eval_start_mm) * b / (scene.grid.cols - 1);
            const double z = r.z_eval_start_mm + (r.z_eval_end_mm - r.z_eval_start_mm) * a / (scene.grid.rows - 1);
            const auto c = generating.linear_contact(tooth, flank, xi, z);
            v.push_back(c.v), pp.push_back(c.pp);
          }
        }
    // All points in one batch: a law given as a Python function is called once.
    std::vector<double> out(v.size());
    try {
      effects[i]->wheel_radius_errors_mm(v, pp, out);
    } catch (const effects::NonFiniteDeviation& e) {
      scene.fail_at(field, e.what());
    }
  }
}

Workbench::Workbench(const std::filesystem::path& scene_file) : Workbench(scene::load_scene(scene_file)) {}

std::vector<std::string> Workbench::effect_types() const {
  std::vector<std::string> out;
  for (const auto& e : scene.effects)
    if (std::find(scene.custom_effects.begin(), scene.custom_effects.end(), e.type) == scene.custom_effects.end())
      out.push_back(e.type);
  for (const auto& c : scene.machine_changes)
    out.push_back(fmt::format("{} {}", scene.machine.chain->info(c.component).name, c.law_name()));
  return out;
}

grinding::SimulationOptions scene_simulation(const scene::MeasurementGrid& grid) {
  grinding::SimulationOptions so;
  so.teeth = grid.teeth;
  so.rows = grid.rows;
  so.cols = grid.cols;
  so.profile_points = grid.profile_points;
  so.helix_points = grid.helix_points;
  so.dense_rows = grid.dense_rows;
  so.dense_cols = grid.dense_cols;
  return so;
}

std::vector<std::unique_ptr<effects::Effect>> make_effects(const std::vector<scene::EffectSpec>& specs,
                                                           const grinding::GrindingSetup& setup) {
  std::vector<std::unique_ptr<effects::Effect>> out;
  for (const auto& s : specs) out.push_back(effects::make_effect(s.type, s.values, setup));
  return out;
}

std::vector<std::unique_ptr<effects::Effect>> make_effects(const std::vector<scene::EffectSpec>& specs,
                                                           const std::vector<machine::ComponentChange>& changes,
                                                           const grinding::GrindingSetup& setup,
                                                           const machine::KinematicChain* chain, double datum_face_z_mm) {
  auto out = make_effects(specs, setup);
  if (!changes.empty()) {
    out.push_back(std::make_unique<effects::ComponentChanges>(changes, chain, datum_face_z_mm));
    out.back()->bind(setup);
  }
  return out;
}

} // namespace geartopo::workbench
