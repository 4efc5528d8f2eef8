// The report pages' shared pieces (private to geartopo_report): the page style and HTML escaping.
#pragma once

#include <string>

namespace geartopo::report::detail {

/// The <style> element of every report page (screen and A4 print rules).
const char* page_style();
/// s with & < > " escaped.
std::string html_escape(const std::string& s);
/// The run's date (UTC, ISO 8601): SOURCE_DATE_EPOCH when set, else now.
std::string page_date();

} // namespace geartopo::report::detail
