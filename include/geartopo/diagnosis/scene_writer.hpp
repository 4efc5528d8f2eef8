// geartopo — writes a scene file with effects added, keeping the original text (comments, order) untouched and
// appending the new items to its `effects:` list (or a new `effects:` section at the end).
#pragma once

#include "geartopo/machine/component_change.hpp"

#include "geartopo/scene/scene.hpp"

#include <Eigen/Dense>

#include <filesystem>
#include <string>
#include <vector>

namespace geartopo::diagnosis {

/// The YAML items ("  - type: …") for effects, values in file units with their keys, and a comment line each. With
/// `uncertainties` (parallel to the effects' values, file units; 0: exact) each item gets an `uncertainty` map of its
/// uncertain values, and with `correlation` (N × N over all the effects' values in order) a `correlation` list of
/// [key_a, key_b, r] for every non-zero pair, in the item of its first value (another effect's key as type.key):
/// docs/scene-format.md, "Uncertain effects". An effect with value sets in `draws` (parallel to the effects, sets ×
/// values, file units; 0 rows: none) gets a `draws` block of its fitted values instead of an uncertainty and its
/// correlations (docs/scene-format.md, "Effects drawn from a posterior").
std::string effects_yaml_items(const std::vector<scene::EffectSpec>& effects, const std::vector<std::string>& comments,
                               const std::vector<std::vector<double>>& uncertainties = {},
                               const Eigen::MatrixXd& correlation = Eigen::MatrixXd(),
                               const std::vector<Eigen::MatrixXd>& draws = {});

/// `scene_text` with the items added to its top-level `effects:` list (created if absent); an effect of the user's own
/// (a scene's custom_effects) instead has its values, uncertainties and correlation written into its own entry.
std::string scene_with_effects(const std::string& scene_text, const std::vector<scene::EffectSpec>& effects,
                               const std::vector<std::string>& comments,
                               const std::vector<std::vector<double>>& uncertainties = {},
                               const Eigen::MatrixXd& correlation = Eigen::MatrixXd(),
                               const std::vector<Eigen::MatrixXd>& draws = {});

/// `scene_text` (a scene file read from `from_dir`) with its relative file references — `machine.tables` and
/// `measurement.measured` — rewritten relative to `to_dir`, so that the text can be saved there. Absolute paths stay.
std::string rebase_scene_paths(const std::string& scene_text, const std::filesystem::path& from_dir,
                               const std::filesystem::path& to_dir);

/// The YAML items of a `machine_changes` list ("  - {component: E_AOA, law: linear_in_time, rate_urad_per_min: 0.8}"),
/// sizes in file units under the law's key (machine::size_key), each with its fit's 1σ as a comment (`uncertainties`
/// parallel to `changes`, internal units; 0 or missing: none) and a comment line before it (`comments`). The
/// components are named as `chain` names them (the scene's; null: the CFXZAY).
std::string machine_changes_yaml_items(const std::vector<machine::ComponentChange>& changes,
                                       const std::vector<double>& uncertainties = {},
                                       const std::vector<std::string>& comments = {},
                                       const machine::KinematicChain* chain = nullptr);
/// `scene_text` with those items added to its top-level `machine_changes:` list (created if absent).
std::string scene_with_machine_changes(const std::string& scene_text, const std::vector<machine::ComponentChange>& changes,
                                       const std::vector<double>& uncertainties = {},
                                       const std::vector<std::string>& comments = {},
                                       const machine::KinematicChain* chain = nullptr);

/// `scene_text` (read from `from_dir`) with the effects added (scene_with_effects), the changed components added
/// (scene_with_machine_changes) and its paths rebased to `to_dir` (rebase_scene_paths): the text of a scene file to be
/// saved in `to_dir`.
std::string scene_text_with_effects(const std::string& scene_text, const std::filesystem::path& from_dir,
                                    const std::filesystem::path& to_dir, const std::vector<scene::EffectSpec>& effects,
                                    const std::vector<std::string>& comments,
                                    const std::vector<std::vector<double>>& uncertainties = {},
                                    const Eigen::MatrixXd& correlation = Eigen::MatrixXd(),
                                    const std::vector<machine::ComponentChange>& changes = {},
                                    const std::vector<double>& change_uncertainties = {},
                                    const std::vector<std::string>& change_comments = {},
                                    const std::vector<Eigen::MatrixXd>& draws = {},
                                    const machine::KinematicChain* chain = nullptr);

/// Reads `scene_file`, adds the effects and the changed components (scene_text_with_effects), rebases its paths to
/// `out_file`'s folder and writes it there. Throws std::runtime_error naming the file that cannot be read or written.
void write_scene_with_effects(const std::filesystem::path& scene_file, const std::vector<scene::EffectSpec>& effects,
                              const std::vector<std::string>& comments, const std::filesystem::path& out_file,
                              const std::vector<std::vector<double>>& uncertainties = {},
                              const Eigen::MatrixXd& correlation = Eigen::MatrixXd(),
                              const std::vector<machine::ComponentChange>& changes = {},
                              const std::vector<double>& change_uncertainties = {},
                              const std::vector<std::string>& change_comments = {},
                              const std::vector<Eigen::MatrixXd>& draws = {},
                              const machine::KinematicChain* chain = nullptr);

} // namespace geartopo::diagnosis
