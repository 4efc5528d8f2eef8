// geartopo — reads gear.modifications.table (docs/modifications.md, "The design"): a designed topology point by point.
//
// CSV, header exactly:  flank,diameter_mm,z_mm,design_um
//   flank left|right; diameter and z (from the datum face) in mm; the design value in µm, plus material positive.
//   Per flank a full grid: every diameter with every z, once (any order of rows, any spacing); lines starting with
//   '#' are comments. Every problem is an InputError naming file:line:column and the field.
#pragma once

#include "geartopo/gears/flank_modifications.hpp"

#include <filesystem>

namespace geartopo::scene {

gears::DesignTable read_design_table(const std::filesystem::path& file);

} // namespace geartopo::scene
