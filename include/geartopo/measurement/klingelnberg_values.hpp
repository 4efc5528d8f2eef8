// geartopo — the value file of a Klingelnberg-style export (".mew", "HEADER KS.MW.FILE"): the measuring machine's own
// evaluation of the curves it writes beside it in the ".mka" (f_Hα, f_fα, F_α, f_Hβ, f_fβ, F_β per tooth and flank,
// their statistics, pitch and runout values), read strictly: every flank-deviation code is decoded and cross-checked
// against its label. The structure, the codes and what rests on one source: docs/measurement-formats.md, "Value file".
// Units: µm (values), as in the file.
#pragma once

#include "geartopo/core/flank.hpp"

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::measurement {

/// The six ISO 1328-1 flank quantities a value file carries per tooth and flank.
enum class MachineQuantity { ProfileSlope, ProfileForm, ProfileTotal, HelixSlope, HelixForm, HelixTotal };
inline constexpr MachineQuantity kMachineQuantities[] = {MachineQuantity::ProfileSlope, MachineQuantity::ProfileForm,
                                                         MachineQuantity::ProfileTotal, MachineQuantity::HelixSlope,
                                                         MachineQuantity::HelixForm,    MachineQuantity::HelixTotal};
/// "f_Hα", "f_fα", "F_α", "f_Hβ", "f_fβ", "F_β".
const char* symbol(MachineQuantity q);

/// What a result line's statistic digit S says (code G MM S T).
enum class MachineStatistic { Tooth, Mean, Variation, Max, Min };

/// One decoded flank-deviation result line "GMMST : label : value".
struct MachineFlankValue {
  int code = 0;                      ///< the five digits
  char group = 'p';                  ///< 'h' helix (lead, G = 1) or 'p' profile (G = 2)
  int measurand = 1;                 ///< MM: 1 slope, 4 total, 7 form; 2/3, 5/6, 8/9 at a second position; 16 f_Ko
  std::optional<MachineQuantity> quantity; ///< the quantity of MM 1, 4, 7; nullopt for the others
  char position = 0;                 ///< the second position's letter of the label (f/k helix, u/o profile), else 0
  MachineStatistic statistic = MachineStatistic::Tooth;
  Flank flank = Flank::Left;
  int slot = 0;                      ///< T: 1 … 5 in the order of the measured teeth, 0 for statistics
  int tooth = 0;                     ///< the label's tooth number (statistic Tooth), else 0
  std::optional<double> value_um;    ///< nullopt for the placeholders −9999.0 (not measured) and 8999.0 (not available)
  std::string label;
  int line = 0;
};

/// A pitch or runout value, found by its label (`fp max`, `fu max`, `Fp`, `Fpz/8`, `Fr`, `Rp`, `Rs`).
struct MachinePitchValue {
  std::string name;              ///< the label's name, e.g. "fp max"
  std::optional<Flank> flank;    ///< when the label names one
  std::optional<double> value_um; ///< nullopt for a placeholder
  int code = 0, line = 0;
};

/// A numbered header line kept as text (settings 165, 178, 179, 180 and the ranges).
struct MachineHeaderSetting {
  std::string text; ///< after the code's colon, trimmed
  std::optional<int> number; ///< the first whole-number field after the setting's name ("LVORZ: 1: DIN" → 1)
  int line = 0;
};

struct KlingelnbergValues {
  std::string source;
  std::vector<std::string> preamble;       ///< "KEY value ! comment" lines, as written (TYPE, UNITS, …)
  std::vector<std::string> filters;        ///< the preamble's FILTER lines, as written ("FILTER LEAD:    F:S 2")
  std::map<int, MachineHeaderSetting> settings; ///< header lines 165 (R_FHB), 178 (LVORZ), 179 (BZGFL), 180 (BZGPR)
  std::vector<MachineFlankValue> flank_values;  ///< every flank-deviation line, in file order
  std::vector<MachinePitchValue> pitch_values;
  std::vector<std::string> unknown_lines;  ///< result lines not read (sizes, other codes): "code label (line N)"
  int placeholders = 0;                    ///< −9999.0 / 8999.0 among the values read

  /// The value of one quantity, tooth and flank (statistic Tooth, first position); nullptr when absent.
  const MachineFlankValue* find(MachineQuantity q, int tooth, Flank flank) const;
  /// Header line 179 says f_Hβ is referred to the face width b (BZGFL 1, [V]), not to L_β.
  bool helix_slope_referred_to_face_width() const;
};

/// The placeholders of a value file: not measured, not available. Never numbers.
inline constexpr double kMachineNotMeasured = -9999.0, kMachineNotAvailable = 8999.0;

/// Parses a value file's text (UTF-8 with or without BOM, or latin-1; CRLF or LF; decimal point or, throughout, decimal
/// comma). Throws InputError "file:line: field: message" for: a first line that is not "HEADER KS.MW.FILE", a result
/// line without a number, a code that does not decode (group, measurand, statistic, slot), a label that does not say
/// what its code says (quantity, flank, statistic, position, tooth), a code given twice, a slot carrying two tooth
/// numbers or a tooth in two slots, a value beyond ±1000 µm.
KlingelnbergValues parse_klingelnberg_values(std::string_view text, const std::string& source);
KlingelnbergValues read_klingelnberg_values(const std::string& file);

/// The value file the machine writes beside an export (same stem, `.mew`) when one is there; callers say it is not
/// read unless named (a stale one would be compared silently).
std::optional<std::string> value_file_beside(const std::string& export_file);

} // namespace geartopo::measurement
