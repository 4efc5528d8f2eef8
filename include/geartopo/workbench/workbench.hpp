// geartopo — everything a scene describes, built once: the scene, the grinding set-up (gear, wheel, path), the
// machine model, the grinding process it drives and the scene's effects on top. The one place that assembles them
// (the program's commands, the tests and the benchmarks all use it) and so the one place that checks that the
// set-up fits the machine (axis strokes), locating what does not in the scene file. Not copyable: the processes
// refer to the model.
#pragma once

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/effects/effect.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/machine_process.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/machine/machine_model.hpp"
#include "geartopo/scene/scene.hpp"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace geartopo::workbench {

struct Workbench {
  /// Builds and checks everything; throws InputError located at the scene field that does not fit the machine.
  /// `keep_going` (may be empty) is called between the steps and from the custom effects' check before every grid row
  /// of a flank (a fine grid on every tooth takes seconds): a Ctrl-C check that may throw to stop, as
  /// grinding::SimulationOptions::keep_going.
  explicit Workbench(scene::Scene s, const std::function<void()>& keep_going = {});
  /// load_scene(file), then everything above; throws InputError.
  explicit Workbench(const std::filesystem::path& scene_file);
  Workbench(const Workbench&) = delete;
  Workbench& operator=(const Workbench&) = delete;

  /// What was chosen for the user and must be said (e.g. a wheel diameter when the scene gives none and the default
  /// 350 mm does not fit the gear). Commands print them; the report lists them.
  std::vector<std::string> notes;
  scene::Scene scene;
  grinding::GrindingSetup setup;
  machine::MachineModel machine;
  /// Owns machine_process (make_machine_process of the scene's chain).
  std::unique_ptr<const grinding::GrindingProcess> machine_process_owner;
  /// Geometric errors only, on the scene's chain: a MachineProcess on the CFXZAY, a ChainProcess on any other.
  const grinding::GrindingProcess& machine_process;
  /// The scene's effects, bound to setup, then its machine_changes (one effects::ComponentChanges) when it has any.
  std::vector<std::unique_ptr<effects::Effect>> effects;
  std::unique_ptr<effects::EffectsProcess> effects_process; ///< null when the scene has no effects
  /// The NC program's motions that grind the drawing's helix modifications (compensation/design_motion.hpp, the
  /// scene's process.lead_crowning), and the machine running them; null when the design has no helix part.
  std::unique_ptr<compensation::CorrectionTable> design_motion;
  std::unique_ptr<compensation::CompensatedProcess> design_process;

  /// What the machine does: geometric errors plus the scene's effects, running the design motions.
  const grinding::GrindingProcess& process() const {
    if (design_process) return *design_process;
    return effects_process ? static_cast<const grinding::GrindingProcess&>(*effects_process) : machine_process;
  }
  /// The process without the design motions: geometric errors plus the scene's effects (what design_process wraps).
  const grinding::GrindingProcess& machine_and_effects() const {
    return effects_process ? static_cast<const grinding::GrindingProcess&>(*effects_process) : machine_process;
  }
  /// What diagnose explains a measurement with: process() without the user's own effects (scene.custom_effects), which
  /// diagnose fits afresh as candidates (DiagnoseOptions::own_effects). process() when the scene declares none.
  const grinding::GrindingProcess& diagnosis_model() const { return diagnosis_model_ ? *diagnosis_model_ : process(); }
  /// The types of the scene's library effects, in scene order ("thermal_drift", …), then its machine changes by name
  /// and law ("E_AOA linear_in_time", diagnosis::Candidate::name's form): what diagnosis must not propose again. The
  /// user's own effects are not among them: diagnose tries them.
  std::vector<std::string> effect_types() const;

private:
  /// diagnosis_model()'s parts when the scene has custom effects: the library effects and changes alone, that process,
  /// and the same running the design motions (null when not needed).
  std::vector<std::unique_ptr<effects::Effect>> known_effects_;
  std::unique_ptr<effects::EffectsProcess> known_effects_process_;
  std::unique_ptr<compensation::CompensatedProcess> known_design_process_;
  const grinding::GrindingProcess* diagnosis_model_ = nullptr;
  void build_diagnosis_model();
  /// Every custom effect finite at the scene's measurement grid on every tooth and flank, at its values; else the
  /// InputError at its deviation_um naming the point and the variables.
  void check_custom_effects_finite(const std::function<void()>& keep_going) const;
};

/// A process built on top of the scene's machine (a Monte Carlo sample's drawn machine, the nominal one of a
/// sensitivity) running the scene's design motions, as Workbench::process() does; `inner` itself without them.
/// Holds references: `wb` and `inner` must outlive it.
class WithDesignMotion {
public:
  WithDesignMotion(const Workbench& wb, const grinding::GrindingProcess& inner)
      : inner_(inner),
        design_(wb.design_motion ? std::make_unique<compensation::CompensatedProcess>(inner, *wb.design_motion) : nullptr) {}
  const grinding::GrindingProcess& process() const {
    return design_ ? static_cast<const grinding::GrindingProcess&>(*design_) : inner_;
  }

private:
  const grinding::GrindingProcess& inner_;
  std::unique_ptr<compensation::CompensatedProcess> design_;
};

/// The simulation the scene's `measurement` section asks for (`geartopo simulate` without flags, geartopo.simulate):
/// its teeth, grid, trace points and dense grid; the exact method on all hardware threads.
grinding::SimulationOptions scene_simulation(const scene::MeasurementGrid& grid);

/// The grinding process of a machine with `model`'s geometric errors on `chain`, the gear's datum face at chain
/// z = datum_face_z_mm — the one place that chooses it: MachineProcess on the CFXZAY (is_setting_chain: its own
/// evaluator, the fast path), a grinding::ChainProcess on any other chain. `model` must outlive it.
std::unique_ptr<const grinding::GrindingProcess> make_machine_process(const machine::KinematicChain& chain,
                                                                      const machine::MachineModel& model,
                                                                      double datum_face_z_mm);

/// Wheel diameters tried, largest first, when the scene gives none and the default does not fit the gear (mm).
inline constexpr double kWheelDiametersToTryMm[] = {350, 300, 250, 200, 160, 125, 100, 80, 63, 50};

/// Instances of effects with their values, bound to a set-up.
std::vector<std::unique_ptr<effects::Effect>> make_effects(const std::vector<scene::EffectSpec>& specs,
                                                           const grinding::GrindingSetup& setup);
/// The same followed by the changed error components (effects::ComponentChanges) when there are any: what a scene's
/// `effects` and `machine_changes` do to the grinding process together; the changes act through `chain`'s error
/// Jacobian (null: the CFXZAY), the gear's datum face at its z = datum_face_z_mm.
std::vector<std::unique_ptr<effects::Effect>> make_effects(const std::vector<scene::EffectSpec>& specs,
                                                           const std::vector<machine::ComponentChange>& changes,
                                                           const grinding::GrindingSetup& setup,
                                                           const machine::KinematicChain* chain = nullptr,
                                                           double datum_face_z_mm = 0.0);

} // namespace geartopo::workbench
