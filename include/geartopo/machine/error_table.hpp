// geartopo — measured error tables (CSV) → ErrorSource (docs/error-components.md, "Tables").
//
// Format:
//   # comment lines start with '#', blank lines are ignored
//   x_mm,delta_xx_um,delta_yx_um        ← header: position column "<axis>_<unit>", then "<component>_<unit>"
//   0,0.0,0.0
//   100,2.5,-0.8                        ← positions strictly increasing, every value a finite number
// Position units: mm (um accepted) for x, y, z; deg or rad for a and c. Value units: um (µm), nm, mm for δ;
// urad (µrad), mrad, rad, arcsec for ε. Every component column must belong to the axis of the position
// column (delta_xx, delta_yx, … against x_mm). C tables are periodic and must span exactly [0, 360] deg
// (or [0, 2π] rad) with equal values in the first and last row. Values are interpolated by a C² cubic
// spline (not-a-knot, or periodic for C). That a table covers its axis' stroke is checked by MachineModel.
// A column "u_<component>_<unit>" (e.g. u_delta_xx_um, any order among the columns) gives the standard uncertainty
// (k = 1) of that component's column at each row: its component's column must be in the same file; values ≥ 0,
// finite and bounded like the table values; units of the component's kind; C tables closed (first = last). It is
// interpolated like the values (ErrorSource::uncertainty) and drawn fully correlated along the axis
// (ErrorSource::drawn; docs/error-components.md, "Uncertainty columns").
// Units inside: mm and rad.
#pragma once

#include "geartopo/core/input_error.hpp"
#include "geartopo/machine/error_source.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::machine {

/// The largest geometric error a table may hold, in internal units: 1 mm for a length (δ), 10 mrad for an angle (ε).
/// Real axes err by µm and µrad; a value beyond these is a wrong unit (µm written as nm, mm as µm) or a broken file,
/// refused at its row and column (issue 18: 1e12 µm used to be accepted and ruined every simulation).
inline constexpr double kMaxTableLengthMm = 1.0;
inline constexpr double kMaxTableAngleRad = 0.01;

/// Every component column of one table file, in column order, each with its `u_` column if the file has one.
/// Throws InputError.
std::vector<ErrorSource> load_error_tables(const std::filesystem::path& path);
/// The same with the components and the position column named as `chain` names them (its axis letters in lower case,
/// its component names: kinematic_chain.hpp); a name of another chain is unknown.
std::vector<ErrorSource> load_error_tables(const std::filesystem::path& path, const KinematicChain& chain);
/// The column of `expected` in a table file (the file may hold other components of the same axis).
/// Throws InputError, also when the file has no column for `expected`.
ErrorSource load_error_table(const std::filesystem::path& path, ComponentId expected);
/// Same as load_error_tables from text in memory; `source` names it in messages.
std::vector<ErrorSource> parse_error_tables(std::string_view text, const std::string& source,
                                           const KinematicChain& chain = cfxzay());

} // namespace geartopo::machine
