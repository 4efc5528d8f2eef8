#include "geartopo/measurement/any_measurement.hpp"

#include "geartopo/files/input_file.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/surfaces/point_cloud.hpp"

#include <fmt/format.h>

#include <filesystem>

namespace geartopo::measurement {

std::vector<MeasuredPoint> read_point_cloud_measurement(const std::string& file, const gears::InvoluteHelicoid& flanks,
                                                        double max_offset_mm) {
  const auto cloud = surfaces::read_point_cloud(std::filesystem::path(file));
  const auto samples = surfaces::assign_to_flanks(cloud, flanks, max_offset_mm, file);
  std::vector<MeasuredPoint> out;
  out.reserve(samples.size());
  for (const auto& s : samples) {
    MeasuredPoint p;
    p.tooth = s.tooth;
    p.flank = s.flank;
    p.roll_length_mm = s.roll_length_mm;
    p.diameter_mm = s.diameter_mm;
    p.z_mm = s.z_mm;
    p.deviation_um = units::um_from_mm(s.normal_distance_mm);
    p.line = static_cast<int>(s.line);
    p.id = s.id;
    out.push_back(p);
  }
  return out;
}

namespace {

// UTF-16 or NUL bytes are named as such before the format is guessed from the first line (a UTF-16 export would
// otherwise read as a topology CSV with a bad header). Rewinds the stream.
void refuse_utf16_stream(std::istream& in, const std::string& file) {
  std::string head(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  in.clear();
  in.seekg(0);
  refuse_utf16(head, file);
}

/// The line of the file's header with a design column (0: none). Such a file says what its deviations are measured
/// from: a declaration besides is refused.
int design_header_line(std::istream& in, const std::string& file, MeasuredAgainst against) {
  const int design_header = grinding::design_column_line(in);
  if (design_header > 0 && against != MeasuredAgainst::as_file)
    throw InputError(file, design_header, 0, grinding::kDesignColumn,
                     fmt::format("the file says what its deviations are measured from (its {} column): \"measured "
                                 "against: {}\" is for a file without one",
                                 grinding::kDesignColumn, to_string(against)));
  return design_header;
}

} // namespace

void declare_reference(std::vector<MeasuredPoint>& points, MeasuredAgainst against, const gears::FlankDesign& design) {
  for (auto& p : points) {
    if (against == MeasuredAgainst::design) p.design_um = design.at_um(p.flank, p.roll_length_mm, p.z_mm);
    p.reference_declared = against != MeasuredAgainst::as_file;
  }
}

std::vector<MeasuredPoint> read_any_measurement(const std::string& file, const grinding::GrindingSetup& setup,
                                                std::vector<std::string>* warnings, const KlingelnbergOptions& mka,
                                                ReadCounts* counts, MeasuredAgainst against) {
  auto in = input::open_input_file(file, input::kMaxMeasurementBytes, "measurement");
  if (counts) *counts = {};
  refuse_utf16_stream(in, file);
  const int design_header = design_header_line(in, file, against);
  std::vector<MeasuredPoint> points;
  // First: an export's header lines and trace heads are not numbers, so neither other reader would take it anyway.
  if (looks_like_klingelnberg(in)) {
    auto res = klingelnberg_points(read_klingelnberg(file, mka.keep_going), setup.geometry(), mka);
    if (warnings) warnings->insert(warnings->end(), res.warnings.begin(), res.warnings.end());
    if (counts) *counts = {res.undefined_values, res.off_flank_points};
    points = std::move(res.points);
  } else if (grinding::starts_like_traces_csv(in)) {
    points = read_traces_measurement(file, setup.geometry());
  } else if (surfaces::starts_like_point_cloud(in)) {
    points = read_point_cloud_measurement(file, setup.flanks());
  } else {
    points = read_measurement(file, setup.geometry());
  }
  if (design_header == 0) declare_reference(points, against, setup.design());
  refer_to_design(points, setup.design()); // the model's deviations are from the scene's drawing too
  return points;
}

MeasuredTraces read_any_traces(const std::string& file, const grinding::GrindingSetup& setup, const KlingelnbergOptions& mka,
                               MeasuredAgainst against) {
  MeasuredTraces t;
  const auto& g = setup.geometry();
  auto in = input::open_input_file(file, input::kMaxMeasurementBytes, "traces file");
  refuse_utf16_stream(in, file);
  const int design_header = design_header_line(in, file, against); // refuses a declaration for a file with the column
  if (design_header == 0 && against == MeasuredAgainst::as_file && !setup.design().empty())
    t.warnings.push_back(fmt::format(
        "{} has no {} column: its deviations are read as measured against the bare involute, while the scene's "
        "drawing has modifications; if the measuring machine evaluated against the drawing, say so "
        "(--measured-against design; Python: measured_against=\"design\"), else declare involute to silence this",
        file, grinding::kDesignColumn));
  t.klingelnberg = looks_like_klingelnberg(in);
  if (t.klingelnberg) {
    t.export_file = read_klingelnberg(file, mka.keep_going);
    t.flanks = klingelnberg_traces(*t.export_file, g, mka, &t.warnings);
  } else {
    t.flanks = grinding::read_traces_csv(file, g.teeth());
  }
  if (against == MeasuredAgainst::design) // the file's deviations are from the drawing: keep them
    for (auto& ft : t.flanks)
      for (auto* trace : {&ft.profile, &ft.helix})
        for (auto& p : *trace) p.design_um = setup.design().at_um(ft.flank, p.roll_length_mm, p.z_mm);
  refer_to_design(t.flanks, setup.design());
  return t;
}

} // namespace geartopo::measurement
