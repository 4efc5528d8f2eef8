// geartopo — a documented subset of the Klingelnberg (P-series / GINA) text export of profile and helix traces
// (".mka", "KS.MK.FILE"), read into measured flank points, and written by `geartopo synth --format klingelnberg`.
// The subset, its options and what is uncertain: docs/measurement-formats.md.
// Units: positions mm, deviations µm (the file's and geartopo's), angles deg in the file.
#pragma once

#include "geartopo/core/flank.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <iosfwd>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::measurement {

/// How the N values of a profile trace are spread over the measuring range da … de. The evidence (gearcore's
/// regression on 68 real files: printed f_Hα reproduced to 0.04 µm) is for roll length; Diameter is for exports that
/// space evenly in diameter.
enum class ProfileSpacing { RollLength, Diameter };
/// Which direction the file's deviations are measured in. Transverse (base tangent in the transverse plane, ISO 1328
/// charts) is converted to the flank normal by × cos β_b; Normal is taken as it is. [M]: no source states it.
enum class DeviationDirection { Transverse, Normal };
/// Raw: the file carries the probe's raw sign (gearcore: profile left × −1, profile right × +1, helix × −1 give the DIN
/// sign, plus material positive); Din: the values already carry the DIN sign. [M]: shown on spur gears only.
enum class SignConvention { Raw, Din };

struct KlingelnbergOptions {
  ProfileSpacing spacing = ProfileSpacing::RollLength;
  DeviationDirection direction = DeviationDirection::Transverse;
  SignConvention signs = SignConvention::Raw;
  /// Called every 4096 lines while an export is parsed and once per trace after (a 64 MB export takes seconds): a
  /// Ctrl-C check that may throw to stop, as grinding::SimulationOptions::keep_going. May be empty.
  std::function<void()> keep_going;
};

enum class TraceKind { Profile, Helix };

/// One numbered header line "NN : label [unit]..: values".
struct KlingelnbergHeaderLine {
  std::string label;          ///< the text before the first ':', dot leaders removed
  std::vector<double> values; ///< every number after it
  int line = 0;
};

struct KlingelnbergTrace {
  TraceKind kind = TraceKind::Profile;
  int tooth = 0;
  Flank flank = Flank::Left;
  bool topography = false;    ///< from a TOPOGRAFIE block
  char position_symbol = 'z'; ///< 'z': axial position of a profile; 'd': diameter, 'x': roll length of a helix trace
  double position_mm = 0.0;
  std::vector<double> values_um; ///< raw, as in the file; NaN for the undefined value
  std::vector<int> value_lines;  ///< line of each value
  int announced_values = 0;      ///< "<n> Werte" of the head; the parser checks that exactly n follow
  int line = 0;                  ///< line of the head
};

struct KlingelnbergPitchRow {
  int tooth = 0;
  Flank flank = Flank::Left;
  double fp_um = 0.0, Fp_um = 0.0, Fr_um = 0.0;
  int line = 0;
};

struct KlingelnbergFile {
  std::string source;
  std::map<int, KlingelnbergHeaderLine> codes;          ///< numbered header lines by code (21 m_n, 22 z, …)
  std::map<std::string, KlingelnbergHeaderLine> ranges; ///< "da" "de" "d1" "d2" "ba" "be" "b1" "b2" by their symbol
  std::vector<KlingelnbergTrace> traces;
  std::vector<KlingelnbergPitchRow> pitch;
  std::vector<std::string> skipped_blocks; ///< blocks not read, "title (line N)"
  int undefined_points = 0;                ///< values equal to the undefined value −2147483.648
  int last_line = 0;
};

/// The undefined value of the export; any value at or below it + 1 is undefined (gearcore does the same).
inline constexpr double kKlingelnbergUndefined = -2147483.648;

/// Parses the text of an export (UTF-8 with or without BOM, or latin-1; CRLF, LF or CR alone; decimal points or, throughout,
/// decimal commas; German or English labels: docs/measurement-formats.md). Throws InputError
/// (file:line: field: message) on a malformed head, a value that is not a number, or a count that does not match.
/// `keep_going` (may be empty): KlingelnbergOptions::keep_going.
KlingelnbergFile parse_klingelnberg(std::string_view text, const std::string& source,
                                    const std::function<void()>& keep_going = {});
KlingelnbergFile read_klingelnberg(const std::string& file, const std::function<void()>& keep_going = {});

/// Throws InputError naming `source` when `head` (a file's first bytes) is UTF-16 (byte-order mark FF FE or FE FF,
/// or a NUL byte between the characters): every measurement reader takes UTF-8 or latin-1 only,
/// and says so rather than failing on the first header it cannot match.
void refuse_utf16(std::string_view head, const std::string& source);

/// True when the stream's first 64 KiB hold a "HEADER KS." line or a "Zahn-Nr." ("Tooth-No.") trace head. Rewinds
/// the stream.
bool looks_like_klingelnberg(std::istream& in);

struct KlingelnbergPoints {
  std::vector<MeasuredPoint> points;
  std::vector<std::size_t> trace_of_point; ///< per point: its trace, an index into KlingelnbergFile::traces
  std::vector<std::string> warnings; ///< skipped blocks, undefined and off-flank points, unchecked header values
  std::size_t undefined_values = 0;  ///< values equal to the undefined value: no point
  std::size_t off_flank_points = 0;  ///< points off the active flank: skipped
};

/// The traces as measured points on the gear: positions from the measuring ranges (profile da … de, helix ba … be;
/// two values in a range line are the left and the right flank), deviations along the flank normal with the DIN sign.
/// The header's normal module (21) and number of teeth (22) must match the gear: else InputError naming both values.
/// Points off the active flank (d_Ff … d_a, 0 … b, 1 µm slack) are skipped and counted in a warning. Nothing usable
/// left: InputError.
KlingelnbergPoints klingelnberg_points(const KlingelnbergFile& file, const gears::GearGeometry& g,
                                       const KlingelnbergOptions& options = {});

/// The export as one profile and one helix trace per flank, for the ISO 1328-1 evaluator (`geartopo evaluate
/// --traces`): of each flank's profile traces the one nearest mid face width, of its helix traces the one nearest the
/// middle of the active profile in roll length; Profil/Flankenlinie traces are preferred to TOPOGRAFIE lines.
/// Deviations along the flank normal with the DIN sign, as klingelnberg_points. Flanks with only one kind are left
/// out and named in `warnings`; no flank with both: InputError.
std::vector<grinding::FlankTopology> klingelnberg_traces(const KlingelnbergFile& file, const gears::GearGeometry& g,
                                                         const KlingelnbergOptions& options = {},
                                                         std::vector<std::string>* warnings = nullptr);

/// Writes topology rows (a full rows × cols grid per flank, evenly in roll length and in z as geartopo's grids are)
/// as an export of TOPOGRAFIE profile traces, one per column, in the given convention: the inverse of the reader.
void write_klingelnberg(std::ostream& out, const gears::GearGeometry& g, const std::vector<grinding::TopologyRow>& rows,
                        const KlingelnbergOptions& options = {});

} // namespace geartopo::measurement
