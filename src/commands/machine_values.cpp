// geartopo — measured traces with the measuring machine's own values beside them (machine_values.hpp).
#include "geartopo/commands/machine_values.hpp"

#include "geartopo/commands/limits.hpp"
#include "geartopo/report/machine_values_report.hpp"

#include "geartopo/core/input_error.hpp"

#include <fmt/format.h>

#include <regex>

namespace geartopo::commands {

TracesWithMachineValues read_traces_with_machine_values(const workbench::Workbench& wb, const std::string& traces,
                                                        const std::string& values_file,
                                                        const measurement::KlingelnbergOptions& mka,
                                                        const ValuesArgument& argument,
                                                        measurement::MeasuredAgainst against) {
  TracesWithMachineValues r;
  r.traces = measurement::read_any_traces(traces, wb.setup, mka, against);
  r.warnings = std::move(r.traces.warnings);
  r.traces.warnings.clear();
  if (!values_file.empty()) {
    if (!r.traces.klingelnberg)
      throw ArgumentError(argument.name, traces + " is not a Klingelnberg export: the value file evaluates an "
                                                  "export's curves (.mka)");
    r.machine_values = measurement::read_klingelnberg_values(values_file);
    if (!r.machine_values->unknown_lines.empty())
      r.warnings.push_back(fmt::format("{}: result lines not read (sizes and other codes): {}", values_file,
                                       fmt::join(r.machine_values->unknown_lines, ", ")));
  } else if (r.traces.klingelnberg) {
    // A value file beside the export is not read unless named: a stale one would be compared silently.
    if (const auto beside = measurement::value_file_beside(traces))
      r.warnings.push_back(fmt::format("{} beside the export is not read: give {} to compare the machine's profile and "
                                       "helix values",
                                       *beside, fmt::format(fmt::runtime(argument.give), *beside)));
  }
  return r;
}

workbench::IsoResult evaluate_measured_traces(const workbench::Workbench& wb, const measurement::MeasuredTraces& traces,
                                              const std::string& file, const workbench::IsoOptions& iso) {
  try {
    return workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), traces.flanks, iso);
  } catch (const std::invalid_argument& e) {
    // "tooth 1 left flank, profile: trace refused: …" (evaluation/src/trace.cpp): the export's head of that trace.
    static const std::regex named(R"(^tooth (\d+) (left|right) flank, (profile|helix))");
    const std::string message = e.what();
    std::smatch m;
    int line = 0;
    std::string field;
    if (std::regex_search(message, m, named)) {
      field = fmt::format("tooth {} {} {}", m[1].str(), m[2].str(), m[3].str());
      if (traces.export_file)
        for (const auto& t : traces.export_file->traces)
          if (std::to_string(t.tooth) == m[1].str() && (t.flank == Flank::Left) == (m[2].str() == "left") &&
              (t.kind == measurement::TraceKind::Profile) == (m[3].str() == "profile")) {
            line = t.line;
            break;
          }
    }
    throw InputError(file, line, 0, field, message);
  }
}

MachineValuesResult machine_values(const workbench::Workbench& wb, const TracesWithMachineValues& read,
                                   const workbench::IsoResult& iso) {
  MachineValuesResult r;
  r.json = nlohmann::json::object();
  const auto& exported = read.traces.export_file;
  if (exported && !exported->pitch.empty()) {
    r.pitch = workbench::compare_machine_pitch(exported->pitch, iso.evaluation);
    r.json["machine_pitch_table"] = report::machine_pitch_table_json(*r.pitch);
  }
  if (read.machine_values) {
    r.flank_values = workbench::compare_machine_flank_values(*read.machine_values, wb.setup.geometry(),
                                                             wb.setup.ranges(), read.traces.flanks, iso.evaluation,
                                                             exported ? &*exported : nullptr);
    r.json["machine_flank_values"] = report::machine_flank_values_json(*r.flank_values, *read.machine_values);
  }
  return r;
}

} // namespace geartopo::commands
