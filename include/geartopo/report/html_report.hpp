// geartopo — the report page: one self-contained, offline index.html (inline CSS, images by relative path only)
// gathering the figures, the ISO 1328-1 tables before and after, compensation and diagnosis.
#pragma once

#include "geartopo/report/figures.hpp"
#include "geartopo/pipeline/pipeline.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::report {

struct ReportOptions {
  /// The date in the header block (e.g. "2026-11-22"); unset: the run's UTC date, or SOURCE_DATE_EPOCH when set.
  std::optional<std::string> date;
};

void write_html_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r,
                       const std::vector<Figure>& figures, const ReportOptions& options = {});

/// Figures, index.html and figures.json (the manifest: file, size, data and colour ranges, and for trace figures each
/// chart's data, tolerance box and axis range) into dir. `before`: render_before_figures of this gear, drawn already
/// (empty: drawn here).
std::vector<Figure> write_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r,
                                 const ReportOptions& options = {}, std::vector<Figure> before = {});

} // namespace geartopo::report
