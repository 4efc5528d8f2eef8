// geartopo — a series description (YAML, docs/scene-format.md "Series files"): the scene, and per measured gear its
// measurement file, when its job started, the wheel's dressing state and the corrections active while it was ground.
// Read strictly: every unknown key, missing value, time going backwards or duplicate id an InputError at file:line.
// Units: s, strokes.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::series {

/// One measured gear of the series.
struct SeriesGear {
  std::string id;                          ///< "gear 3" unless the file names it (AQDEF K0006, tables, charts)
  std::filesystem::path measurement;       ///< any format geartopo reads (docs/measurement-formats.md)
  double start_s = 0.0;                    ///< its job's start, seconds since the series started
  std::optional<long long> start_epoch_s;  ///< the same as a date and time (s since 1970, shop time), when given
  double strokes_since_dressing = 0.0;     ///< at its job's start (given, or counted from the previous gear)
  bool dressed_before = false;             ///< a dressing event between the previous gear and this one
  std::filesystem::path corrections;       ///< a compensate run's corrections.csv active while ground; empty: none
  int line = 0;                            ///< where the gear stands in the series file
};

struct SeriesSpec {
  std::string source;                      ///< the series file as given
  std::string name;                        ///< its name (AQDEF K1002 with the scene's part), may be empty
  std::filesystem::path scene;             ///< relative paths are resolved against the series file's folder
  std::string machine;                     ///< AQDEF K1082; empty: the scene's machine name
  std::optional<long long> started_epoch_s; ///< the series' start as a date and time (`started`)
  bool dressing_known = false;             ///< any gear gives strokes_since_dressing or dressed_before
  bool diagnose_gears = false;             ///< `diagnose_gears: true`: each gear diagnosed (SeriesOptions::diagnose_gears)
  std::vector<SeriesGear> gears;           ///< in the order ground (start times increasing)
};

/// "2026-11-27T06:00:00" or "2026-11-27 06:00:00" (shop time) as seconds since 1970-01-01 00:00:00; nullopt when the
/// text is not such a date and time.
std::optional<long long> parse_date_time(const std::string& text);

/// Reads and checks a series file; `strokes_per_gear` (the scene's strokes in one job) counts the strokes since
/// dressing from one gear to the next when a gear does not give them.
SeriesSpec parse_series(const std::string& text, const std::string& source, double strokes_per_gear);
/// The scene a series file names, without reading the rest (to build the workbench that gives strokes_per_gear).
std::filesystem::path series_scene(const std::filesystem::path& file);
SeriesSpec load_series(const std::filesystem::path& file, double strokes_per_gear);
/// Whether `file` reads as a series file (a YAML map with a `scene` and a list of `gears`) rather than a scene: how
/// `geartopo report` tells the two apart. False for anything it cannot read (the scene reader then says why).
bool is_series_file(const std::filesystem::path& file);

} // namespace geartopo::series
