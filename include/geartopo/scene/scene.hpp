// geartopo — a scene: one gear on one machine, with wheel, process and measurement grid (docs/scene-format.md).
// Units in the file are named in every key (_mm, _deg, _um); inside, lengths are mm and angles rad.
#pragma once

#include "geartopo/core/input_error.hpp"

#include "geartopo/gears/gear_spec.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/wheel_path.hpp"
#include "geartopo/machine/component_change.hpp"
#include "geartopo/machine/error_source.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/machine_model.hpp"

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace geartopo::scene {

/// Where and how densely flanks are evaluated (and, by a CMM, measured).
struct MeasurementGrid {
  int rows = 7, cols = 9;                    ///< topological grid: alignment curves × profile curves
  int profile_points = 100, helix_points = 150; ///< dense traces
  int dense_rows = 0, dense_cols = 0;        ///< optional dense grid (0: none)
  std::vector<int> teeth;                    ///< empty: all teeth
  std::string measured_file;                 ///< optional measurement (topology CSV), resolved against the scene file
  /// What measured_file's deviations are measured from when it has no design_um column: "design" (the drawing) or
  /// "involute"; empty: not said (measurement::MeasuredAgainst).
  std::string measured_against;
};

/// A physical effect the scene models: its type and its parameter values in file units, in the order of the
/// effect's parameters() (defaults filled in).
struct EffectSpec {
  std::string type;
  std::vector<double> values;
};

/// How well the machine is known and how well it repeats (docs/scene-format.md, "machine.uncertainty"): the standard
/// uncertainty (k = 1) of each error component, the axes' repeatability per stroke (one standard deviation) and the
/// command resolution (the step a correction is rounded to; 0: not rounded). Internal units: mm and rad.
struct MachineUncertainty {
  /// Indexed by ComponentId; mm (δ, offsets) or rad. A component whose table has a `u_` column is drawn with that
  /// column instead (machine::ErrorSource::drawn); its entry here keeps its kind's value, unused by the draws.
  std::array<double, machine::kComponentCount> component_u{};
  /// One standard deviation s per stroke, X, Y, Z (mm), A, C (rad); the file gives ISO 230-2's R↑ = 4 s.
  machine::Vector5d repeatability = machine::Vector5d::Zero();
  machine::Vector5d resolution = machine::Vector5d::Zero();     ///< X, Y, Z (mm), A, C (rad)

  /// The documented defaults: map uncertainties of ISO 230-2 practice (linear axes 1 µm / 3 µrad, A and C 2 µm /
  /// 5 µrad, squareness 5 µrad, axis-line location 2 µm / 5 µrad), the seed paper's machine repeatability (R↑ = 3 µm,
  /// 1 mdeg, so s = R↑/4) and a controller's command resolution of 1 µm / 1 mdeg.
  static MachineUncertainty defaults();
};

/// The machine: its kinematic chain, strokes, where the gear sits, and its geometric error components (all others
/// zero).
struct MachineSection {
  std::string name;
  /// `machine.chain` / `machine.chain_file` (default the CFXZAY) with `strokes` applied; kept by make_chain for the
  /// program's life.
  const machine::KinematicChain* chain = &machine::cfxzay();
  /// The chain's strokes by pose slot (x_mm … the linear axes in letter order, a_deg the swivel).
  machine::Strokes strokes = machine::Strokes::skmc_1200w();
  double datum_face_z_mm = 0.0; ///< machine Z of the gear's datum face; default: face width centred in the Z stroke
  std::vector<machine::ErrorSource> sources;   ///< from tables, constants and polynomials
  std::vector<std::string> table_files;        ///< resolved paths, for reports
  MachineUncertainty uncertainty = MachineUncertainty::defaults();
  machine::MachineModel model() const { return machine::MachineModel(strokes, sources); }
};

/// The report's header block (all optional free text; docs/scene-format.md `report`). Empty = not given.
struct ReportHeader {
  std::string part;              ///< part name / number
  std::string drawing;           ///< drawing number
  std::string operator_name;     ///< who ran or measured it
  std::string measuring_machine; ///< gear measuring machine
  std::optional<double> probe_diameter_mm; ///< probe ball diameter, mm
  std::optional<int> tolerance_class;      ///< class whose tolerance boxes the trace charts show (else the achieved one)
};

/// The largest |size| a machine_changes entry may give (file units of its key): 1000 µm or 10000 µrad, a tenth of that
/// per minute for a rate — far beyond any real machine, so a value beyond it is a typing error.
double machine_change_limit(machine::ChangeLaw law, machine::Quantity q);

struct Scene {
  std::string source;      ///< file the scene was read from (as given), for messages
  std::string name;        ///< free text
  std::string description; ///< free text
  gears::GearSpec gear;
  /// Gear keys whose values the scene declares assumed (not from a drawing), in file order.
  std::vector<std::string> assumed;
  /// Gear keys that were absent and took their conventional value (tip/root diameter).
  std::vector<std::string> defaulted;
  MachineSection machine;
  grinding::WheelSpec wheel;
  grinding::ProcessSpec process;
  MeasurementGrid grid;
  std::vector<EffectSpec> effects;
  /// The names of the user's own effects (`custom_effects`, docs/scene-format.md), in file order: each is an entry of
  /// `effects` too (after the library's), its law registered under its name (effects/custom_effect.hpp). Simulate,
  /// synth, compensate and the Monte Carlo use their values like any effect's; diagnose fits them afresh as candidates
  /// beside the library's (their values are not part of the model it explains the measurement with).
  std::vector<std::string> custom_effects;
  /// Error components changed since the map in `machine` was measured, with their laws in time (scene key
  /// `machine_changes`, docs/scene-format.md): what diagnosis finds beyond the library. Empty: none.
  std::vector<machine::ComponentChange> machine_changes;
  /// Standard uncertainty of each change's size (file units of its key), parallel to machine_changes; 0: exact. From
  /// the item's `uncertainty: {<key>: u}`; the Monte Carlo prediction draws the size within it.
  std::vector<double> machine_change_uncertainties;
  ReportHeader report;
  /// Standard uncertainty of each effect value (file units), parallel to `effects` and their values, e.g. from the fit
  /// that identified them (diagnosis); empty or missing entries: exact. The Monte Carlo prediction draws the values
  /// within them (pipeline/monte_carlo.hpp). From each effect's `uncertainty` map (docs/scene-format.md); empty when
  /// no effect gives one.
  std::vector<std::vector<double>> effect_uncertainties;
  /// Correlation of those values (N × N, unit-free; N the number of values of all effects, in scene order): a fit's
  /// amplitude and time constant trade against each other, and drawing them independently would make drifts the data
  /// exclude. Empty: independent. From the effects' `correlation` lists of [key_a, key_b, r] (docs/scene-format.md);
  /// pairs not given are uncorrelated.
  Eigen::MatrixXd effect_correlation;
  /// Equally likely value sets of each effect (sets × the effect's values in parameter order, file units), e.g. the
  /// posterior a diagnosis drew when the single values are not determined (docs/scene-format.md, "Effects drawn from
  /// a posterior"); parallel to `effects`, 0 rows: none. Every effect with sets has the same number of them, and set j
  /// of each belongs together (one joint draw): a prediction picks one j per sample. An effect with sets has no
  /// standard uncertainty and no correlation. Empty when no effect has sets.
  std::vector<Eigen::MatrixXd> effect_draws;

  /// Where each field's value stands in the scene file (dotted path → position): errors found after reading, when
  /// the scene is built into a set-up (workbench), are located with it.
  std::map<std::string, SourcePosition> positions;
  /// Throws InputError "file:line:column: field: message" at `field`, or at its longest recorded prefix.
  [[noreturn]] void fail_at(const std::string& field, const std::string& message) const;
};

/// Reads and validates a scene file, including the gear's domain rules (undercut, pointed tip, …).
/// Throws InputError.
Scene load_scene(const std::filesystem::path& file);

/// Same from text; `source` names it in messages.
Scene parse_scene(const std::string& text, const std::string& source);

} // namespace geartopo::scene
