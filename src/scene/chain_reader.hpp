// geartopo scene, private — the machine's kinematic chain a scene names (docs/scene-format.md, `machine.chain`): a
// preset by name, an inline description (machine/kinematic_chain.hpp's ChainSpec fields) or a YAML file of one
// (`machine.chain_file`, relative to the scene). A refused chain (ChainError: axis and field) is located at that
// axis' field in the file it was read from.
#pragma once

#include "yaml_reader.hpp"

#include "geartopo/machine/kinematic_chain.hpp"

#include <filesystem>

namespace geartopo::scene {

/// The chain of the scene's `machine` map `m`: its `chain` or `chain_file` key (not both), the CFXZAY when neither
/// is given. Strokes are the description's (the scene's `strokes` are applied afterwards). Throws InputError.
const machine::KinematicChain& read_chain(MapReader& m, const std::filesystem::path& base);

} // namespace geartopo::scene
