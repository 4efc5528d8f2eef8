// geartopo — flank topology and trace files: one format for predictions and measurements (docs/grinding.md).
//
// topology CSV, header exactly:  tooth,flank,row,col,diameter_mm,z_mm,deviation_um[,design_um]
//   tooth 1..z; flank left|right; row 1..R from root to tip; col 1..C from the datum face; z from the datum face;
//   deviation along the flank normal from the design, plus material positive; design_um the design there.
// traces CSV, header exactly:    tooth,flank,trace,roll_length_mm,diameter_mm,z_mm,deviation_um[,design_um]
//   trace profile|helix.
// Readers are strict: every bad line, field or value is an error naming file:line:column and the field, and nothing
// of a bad file is returned.
#pragma once

#include "geartopo/core/flank.hpp"
#include "geartopo/grinding/topology.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace geartopo::grinding {

inline constexpr const char* kTopologyHeader = "tooth,flank,row,col,diameter_mm,z_mm,deviation_um";
inline constexpr const char* kTracesHeader = "tooth,flank,trace,roll_length_mm,diameter_mm,z_mm,deviation_um";
/// The optional last column of both files: the drawing's design value at the point (µm, plus material;
/// gears/flank_modifications.hpp), beside deviation_um, the deviation FROM that design. geartopo writes it always;
/// a file without it is taken as measured against the bare involute (design 0).
inline constexpr const char* kDesignColumn = "design_um";

/// The largest |deviation_um| a topology or traces file may hold (1 mm): beyond it the readers refuse the value.
inline constexpr double kMaxDeviationUm = 1000.0;

/// One row of a topology file.
struct TopologyRow {
  int tooth = 0;
  geartopo::Flank flank = geartopo::Flank::Left;
  int row = 0, col = 0;
  double diameter_mm = 0.0, z_mm = 0.0, deviation_um = 0.0;
  int line = 0; ///< 1-based line in the file it was read from (0 when made in memory)
  double design_um = 0.0; ///< the design the deviation is measured from (kDesignColumn; 0 when the file has none)
};

enum class GridKind { Topology, Dense };

void write_topology_csv(std::ostream& out, const std::vector<FlankTopology>& topo, GridKind kind = GridKind::Topology);
/// The same file from rows (header included): what measured or synthesised data is written as.
void write_topology_rows(std::ostream& out, const std::vector<TopologyRow>& rows);
void write_traces_csv(std::ostream& out, const std::vector<FlankTopology>& topo);
void write_topology_csv(const std::filesystem::path& file, const std::vector<FlankTopology>& topo,
                        GridKind kind = GridKind::Topology);
void write_traces_csv(const std::filesystem::path& file, const std::vector<FlankTopology>& topo);

/// Reads a topology file. `teeth` bounds the tooth numbers (1..teeth). Throws std::runtime_error
/// "file:line:column: field: message" on the first problem: missing or reordered columns, a non-number, NaN or inf,
/// |deviation_um| > kMaxDeviationUm, an unknown flank, a tooth outside 1..teeth, a row or column < 1, a non-positive diameter, a duplicate
/// (tooth, flank, row, col). Comment lines ('#'), blank lines, CRLF line ends and a UTF-8 byte-order mark are accepted.
std::vector<TopologyRow> read_topology_csv(std::istream& in, const std::string& source, int teeth);
std::vector<TopologyRow> read_topology_csv(const std::filesystem::path& file, int teeth);

/// Reads a traces file back into per-flank traces (grid and dense left empty), ordered by tooth then left, right.
/// Same strictness as read_topology_csv; positions within each trace must increase (roll length for profile
/// traces, z for helix traces).
std::vector<FlankTopology> read_traces_csv(std::istream& in, const std::string& source, int teeth);
std::vector<FlankTopology> read_traces_csv(const std::filesystem::path& file, int teeth);

/// True when the first line that is neither blank nor a comment is the traces header (a UTF-8 byte-order mark and
/// CRLF are allowed). Reads from the stream's start and rewinds it.
bool starts_like_traces_csv(std::istream& in);

/// The line of the header when it ends with kDesignColumn (a topology or traces file that says what its deviations
/// are measured from), 0 otherwise. Reads from the stream's start and rewinds it.
int design_column_line(std::istream& in);

/// Topology rows of simulated flanks (the 7×9 grid), for comparison and files.
std::vector<TopologyRow> topology_rows(const std::vector<FlankTopology>& topo, GridKind kind = GridKind::Topology);

} // namespace geartopo::grinding
