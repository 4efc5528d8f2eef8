// The report page as a customer sees it, in Debian's headless Chromium: the screenshot is not blank, nothing is wider
// than a 1400 px window, every image loads, and print-to-PDF gives a real PDF of several pages. Skipped (with the
// reason) when chromium is not installed. Also: every trace chart's scale holds its data and its tolerance box.
// The report is the one of report_fixture.hpp (written once per program).
#include "geartopo/render/image.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <unistd.h>

#include "app/report_fixture.hpp"

namespace {

std::string page_text_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool chromium_present() { return std::system("command -v chromium > /dev/null 2>&1") == 0; }

/// Headless Chromium with a fresh profile, no network, no GPU; extra arguments appended. Returns the exit status.
int run_chromium(const fs::path& profile, const std::string& args, const fs::path& log) {
  const std::string cmd = "env -u DISPLAY chromium --headless --no-sandbox --disable-gpu --no-first-run "
                          "--disable-background-networking --disable-component-update --disable-sync --hide-scrollbars "
                          "--user-data-dir=" + profile.string() + " " + args + " > " + log.string() + " 2>&1";
  return std::system(cmd.c_str());
}

} // namespace

TEST_F(ReportTest, PageHeaderCarriesTheInjectedDate) {
  ASSERT_EQ(code_, 0);
  // SOURCE_DATE_EPOCH 1700000000 s is 2023-11-14T22:13:20Z.
  EXPECT_NE(page_text_of(*dir_ / "index.html").find("2023-11-14"), std::string::npos);
}

TEST_F(ReportTest, PageScreenshotAt1400PxIsNotBlank) {
  ASSERT_EQ(code_, 0);
  if (!chromium_present()) GTEST_SKIP() << "chromium is not installed (Debian package 'chromium'): page not checked";
  const fs::path png = *dir_ / "check_screenshot.png";
  ASSERT_EQ(run_chromium(*dir_ / "profile_shot", "--window-size=1400,2400 --screenshot=" + png.string() + " file://" +
                                                          (*dir_ / "index.html").string(),
                         *dir_ / "shot.log"),
            0)
      << page_text_of(*dir_ / "shot.log");
  const auto s = geartopo::render::image_stats(png);
  EXPECT_EQ(s.width, 1400);
  EXPECT_GT(s.variance, 100.0);            // text, tables and figures, not one flat colour
  EXPECT_GT(s.non_background_share, 0.05); // a real share of the window is drawn on
}

TEST_F(ReportTest, PageNothingOverflowsA1400PxWindowAndEveryImageLoads) {
  ASSERT_EQ(code_, 0);
  if (!chromium_present()) GTEST_SKIP() << "chromium is not installed (Debian package 'chromium'): page not checked";
  // A copy of the page with a probe script that writes the page width and the images that did not load into the DOM.
  std::string html = page_text_of(*dir_ / "index.html");
  const std::string probe =
      "<script>window.addEventListener('load',()=>{const im=[...document.images];"
      "const bad=im.filter(i=>!(i.complete&&i.naturalWidth>0)).map(i=>i.getAttribute('src'));"
      "const p=document.createElement('pre');p.id='probe';p.textContent='PROBE scrollWidth='+"
      "document.documentElement.scrollWidth+' images='+im.length+' broken='+bad.length+' ['+bad.join(',')+'] END';"
      "document.body.appendChild(p);});</script>";
  const auto at = html.rfind("</body>");
  ASSERT_NE(at, std::string::npos);
  html.insert(at, probe);
  std::ofstream(*dir_ / "probe.html") << html;
  const fs::path dom = *dir_ / "probe_dom.html";
  ASSERT_EQ(run_chromium(*dir_ / "profile_dom", "--window-size=1400,1000 --virtual-time-budget=20000 --dump-dom file://" +
                                                         (*dir_ / "probe.html").string() + " > " + dom.string() + " 2>/dev/null; true",
                         *dir_ / "dom.log"),
            0);
  const std::string out = page_text_of(dom);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"(PROBE scrollWidth=(\d+) images=(\d+) broken=(\d+) \[([^\]]*)\] END)")))
      << "the probe did not run: " << out.substr(0, 400);
  EXPECT_LE(std::stoi(m[1]), 1400) << "the page is wider than the window";
  EXPECT_GE(std::stoi(m[2]), 10) << "too few images";
  EXPECT_EQ(std::stoi(m[3]), 0) << "images that did not load: " << m[4];
}

TEST_F(ReportTest, PagePrintToPdfGivesAPdfOfSeveralPages) {
  ASSERT_EQ(code_, 0);
  if (!chromium_present()) GTEST_SKIP() << "chromium is not installed (Debian package 'chromium'): page not checked";
  const fs::path pdf = *dir_ / "report.pdf";
  ASSERT_EQ(run_chromium(*dir_ / "profile_pdf", "--no-pdf-header-footer --print-to-pdf=" + pdf.string() + " file://" +
                                                         (*dir_ / "index.html").string(),
                         *dir_ / "pdf.log"),
            0)
      << page_text_of(*dir_ / "pdf.log");
  const std::string bytes = page_text_of(pdf);
  ASSERT_GT(bytes.size(), 100'000u) << "a report with a dozen figures is more than 100 kB";
  EXPECT_EQ(bytes.substr(0, 5), "%PDF-");
  // Page objects: "/Type /Page" not followed by "s" (that is the page tree).
  const std::regex page_object(R"(/Type\s*/Page(?!s))");
  const auto pages = std::distance(std::sregex_iterator(bytes.begin(), bytes.end(), page_object), std::sregex_iterator());
  EXPECT_GE(pages, 5) << "the report should print to several A4 pages";
}

// Each trace chart's deviation axis holds the whole trace and the whole tolerance box, and is not blown up beyond a
// couple of ticks around them (the old fixed ±12 µm scale flattened sub-µm form). Truth: the ranges the charts were
// drawn with, from figures.json, against the data and box recorded next to them.
TEST_F(ReportTest, PageEveryTraceChartScaleSpansItsDataAndToleranceBox) {
  ASSERT_EQ(code_, 0);
  const auto man = nlohmann::json::parse(std::ifstream(*dir_ / "figures.json"));
  int charts = 0;
  for (const auto& f : man) {
    if (!f.contains("charts")) continue;
    for (const auto& c : f["charts"]) {
      const double dlo = c["data_range_um"][0], dhi = c["data_range_um"][1];
      const double tlo = c["tolerance_box_um"][0], thi = c["tolerance_box_um"][1];
      const double alo = c["axis_range_um"][0], ahi = c["axis_range_um"][1];
      EXPECT_LE(alo, std::min(dlo, tlo)) << c["panel"];
      EXPECT_GE(ahi, std::max(dhi, thi)) << c["panel"];
      EXPECT_GT(thi - tlo, 0.0) << c["panel"] << ": no tolerance box drawn";
      // Not absurdly wide: at most 3 × what it must show (data ∪ box, or the asked minimum span 2 F_T).
      const double must = std::max(std::max(dhi, thi) - std::min(dlo, tlo), c["min_span_um"].get<double>());
      EXPECT_LE(ahi - alo, 3.0 * must) << c["panel"];
      ++charts;
    }
  }
  EXPECT_EQ(charts, 8); // two teeth × two flanks × profile and helix
}
