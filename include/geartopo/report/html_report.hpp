// geartopo — the report page: one self-contained, offline index.html (inline CSS, images by relative path only)
// gathering the figures, the ISO 1328-1 tables before and after, compensation and diagnosis.
#pragma once

#include "geartopo/report/figures.hpp"
#include "geartopo/pipeline/pipeline.hpp"

#include <filesystem>
#include <vector>

namespace geartopo::report {

void write_html_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r,
                       const std::vector<Figure>& figures);

/// Figures, index.html and figures.json (the manifest: file, size, data and colour ranges) into dir.
std::vector<Figure> write_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r);

} // namespace geartopo::report
