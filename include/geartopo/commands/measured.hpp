// geartopo — the commands on a measurement, once for every front end (`geartopo compare / diagnose / plan` and the
// Python module's compare, diagnose, plan): each checks what it is given (limits.hpp, naming the front end's argument),
// makes the library calls and returns the results with the content of the command's JSON file. The front ends only
// read their arguments, print and write. Units: µm.
#pragma once

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::commands {

/// A scene as the commands need it: the workbench it built, its name as messages and files say it, its YAML text and
/// the folder its relative paths start from (the completed scene is written from the text).
struct SceneInput {
  const workbench::Workbench& wb;
  std::string name;
  std::string text;
  std::filesystem::path dir;
};

/// The measurement: its points and its name as messages and files say it.
struct MeasuredInput {
  const std::vector<measurement::MeasuredPoint>& points;
  std::string name;
  measurement::ReadCounts read; ///< what the reader skipped (compare reports it)
};

/// How each front end names the arguments it was given (for the messages of limits.hpp).
struct ArgumentNames {
  std::string noise = "noise_um", candidates = "candidates";
};

struct CompareResult {
  diagnosis::Comparison comparison;
  nlohmann::json json; ///< compare.json
};
/// measured − model at every point, where the model fails, the residual's patterns (noise σ: 0 estimated).
/// `keep_going`: a Ctrl-C check (diagnosis::compare's), may be empty.
CompareResult compare(const SceneInput& scene, const MeasuredInput& measured, double noise_um,
                      const ArgumentNames& names = {}, const std::function<void()>& keep_going = {});

struct DiagnoseRequest {
  double noise_um = 0.0;                ///< 0: estimated
  std::vector<std::string> candidates;  ///< library effects to try (empty: every one not in the scene)
  bool scene_uncertainty = false;       ///< generalised least squares with the scene's declared uncertainties
  diagnosis::DiagnoseOptions::PlanLayout layout = diagnosis::DiagnoseOptions::PlanLayout::Grid;
  std::function<void(long long done, long long total)> on_candidate_fitted; ///< progress, may be empty
  std::function<void()> keep_going; ///< a Ctrl-C check (DiagnoseOptions::keep_going), may be empty
};

struct DiagnoseResult {
  diagnosis::Diagnosis diagnosis;
  nlohmann::json json;                        ///< diagnosis.json
  std::optional<std::string> scene_with_effect; ///< the completed scene's text for `save_dir`; none when withheld
};
/// Which effect is missing, and the scene with it added (its relative paths rebased to `save_dir`, where the caller
/// will save it).
DiagnoseResult diagnose(const SceneInput& scene, const MeasuredInput& measured, const DiagnoseRequest& request,
                        const std::filesystem::path& save_dir, const ArgumentNames& names = {});

struct PlanResult {
  diagnosis::Diagnosis diagnosis;
  nlohmann::json json; ///< plan.json
};
/// What to measure next when explanations are within the ΔBIC threshold of each other.
PlanResult plan(const SceneInput& scene, const MeasuredInput& measured, const DiagnoseRequest& request,
                const ArgumentNames& names = {});

} // namespace geartopo::commands
