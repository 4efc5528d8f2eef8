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
#include <utility>
#include <vector>
#include <unistd.h>

#include "report/report_fixture.hpp"

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

/// The page `html` with the probe `script` put before </body>, laid out by headless Chromium in a window `width` px wide
/// (files named after `name` in `dir`), and the DOM it dumps after loading: where the probe writes its findings. Empty
/// when the page has no </body>.
std::string probed_dom(const fs::path& dir, std::string html, const std::string& script, const std::string& name, int width) {
  const auto at = html.rfind("</body>");
  if (at == std::string::npos) return {};
  html.insert(at, script);
  std::ofstream(dir / (name + ".html")) << html;
  const fs::path dom = dir / (name + "_dom.html");
  run_chromium(dir / ("profile_" + name),
               "--window-size=" + std::to_string(width) + ",1000 --virtual-time-budget=20000 --dump-dom file://" +
                   (dir / (name + ".html")).string() + " > " + dom.string() + " 2>/dev/null; true",
               dir / (name + ".log"));
  return page_text_of(dom);
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
  const std::string out = probed_dom(*dir_, html, probe, "probe", 1400);
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

// Issue 25: the printed report cut the all-teeth table at the right edge. Every table (and figure) must fit the A4
// printable width: 210 mm − 2 × 12 mm margins (the page's @page rule) = 186 mm = 703 CSS px. Truth: Chromium's own
// layout of the page with its print rules applied, at that width — a copy of the page whose probe script moves every
// @media print rule into the screen cascade, then reports each table and image whose right edge passes 703 px.
TEST_F(ReportTest, PrintEveryTableFitsTheA4PrintableWidth) {
  ASSERT_EQ(code_, 0);
  if (!chromium_present()) GTEST_SKIP() << "chromium is not installed (Debian package 'chromium'): print width not checked";
  std::string html = page_text_of(*dir_ / "index.html");
  ASSERT_NE(html.find("@page{size:A4;margin:12mm}"), std::string::npos) << "the print width below assumes these margins";
  const std::string probe =
      "<script>window.addEventListener('load',()=>{let css='';"
      "for(const sh of document.styleSheets)for(const r of sh.cssRules)"
      "if(r instanceof CSSMediaRule&&r.media.mediaText.includes('print'))for(const q of r.cssRules)css+=q.cssText+'\\n';"
      "const st=document.createElement('style');st.textContent=css;document.head.appendChild(st);"
      "const limit=703.5;const wide=[];let n=0;"
      "for(const e of document.querySelectorAll('table,img')){++n;const b=e.getBoundingClientRect();"
      "if(b.right>limit||b.left<-0.5){const t=(e.tagName==='IMG'?e.getAttribute('src'):(e.querySelector('th')||e).textContent)"
      ".slice(0,40).replace(/\\s+/g,' ');wide.push(e.tagName+' '+Math.round(b.right)+'px '+t);}}"
      "const p=document.createElement('pre');p.id='probe';p.textContent='PROBE checked='+n+' wide='+wide.length+' ['+"
      "wide.join(' | ')+'] END';document.body.appendChild(p);});</script>";
  const std::string out = probed_dom(*dir_, html, probe, "print_probe", 703);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"(PROBE checked=(\d+) wide=(\d+) \[([^\]]*)\] END)")))
      << "the probe did not run: " << out.substr(0, 400);
  EXPECT_GE(std::stoi(m[1]), 20) << "too few tables and images checked";
  EXPECT_EQ(std::stoi(m[2]), 0) << "wider than the A4 printable width (703 px): " << m[3];
}

// The printed first page is the customer's summary: classes before → predicted after, the diagnosis, no nominal
// after-state; and no page is left mostly empty by the layout. Truth: the PDF Chromium prints, read back with
// poppler's pdftotext (skipped without poppler-utils).
TEST_F(ReportTest, PrintFirstPageIsTheSummaryAndNoPageIsMostlyEmpty) {
  ASSERT_EQ(code_, 0);
  if (!chromium_present()) GTEST_SKIP() << "chromium is not installed (Debian package 'chromium'): PDF not checked";
  if (std::system("command -v pdftotext > /dev/null 2>&1") != 0) GTEST_SKIP() << "pdftotext (poppler-utils) is not installed";
  const fs::path pdf = *dir_ / "summary_check.pdf";
  ASSERT_EQ(run_chromium(*dir_ / "profile_pdf2", "--no-pdf-header-footer --print-to-pdf=" + pdf.string() + " file://" +
                                                          (*dir_ / "index.html").string(),
                         *dir_ / "pdf2.log"),
            0);
  ASSERT_EQ(std::system(("pdftotext -layout -f 1 -l 1 " + pdf.string() + " " + (*dir_ / "page1.txt").string()).c_str()), 0);
  const std::string page1 = page_text_of(*dir_ / "page1.txt");
  EXPECT_NE(page1.find("predicted after"), std::string::npos) << page1;
  EXPECT_NE(page1.find("overall flank"), std::string::npos) << page1;
  EXPECT_NE(page1.find("Diagnosis"), std::string::npos) << page1;
  EXPECT_NE(page1.find("Flank topology before"), std::string::npos) << "the topology picture's caption: " << page1;
  EXPECT_EQ(page1.find("corrected by itself"), std::string::npos) << page1; // the nominal after-state's label
  EXPECT_EQ(page1.find("nominal after"), std::string::npos) << page1;
  // Every page but the last carries text on most of its height: a page whose text ends in its upper half was left
  // half empty (a forced break, or a block too tall for what was left of it). pdftotext -bbox gives each word's box.
  ASSERT_EQ(std::system(("pdftotext -bbox " + pdf.string() + " " + (*dir_ / "words.html").string()).c_str()), 0);
  const std::string words = page_text_of(*dir_ / "words.html");
  const std::regex page_re(R"re(<page width="([0-9.]+)" height="([0-9.]+)">)re"), word_re(R"re(yMax="([0-9.]+)")re");
  std::vector<std::pair<double, double>> pages; // (height, lowest text)
  for (auto it = std::sregex_iterator(words.begin(), words.end(), page_re); it != std::sregex_iterator(); ++it)
    pages.push_back({std::stod((*it)[2]), 0.0});
  ASSERT_GE(pages.size(), 5u);
  std::size_t from = 0;
  for (size_t k = 0; k < pages.size(); ++k) {
    const std::size_t start = words.find("<page ", from), stop = words.find("</page>", start);
    const std::string body = words.substr(start, stop - start);
    for (auto it = std::sregex_iterator(body.begin(), body.end(), word_re); it != std::sregex_iterator(); ++it)
      pages[k].second = std::max(pages[k].second, std::stod((*it)[1]));
    from = stop;
  }
  for (size_t k = 0; k + 1 < pages.size(); ++k)
    EXPECT_GT(pages[k].second, 0.6 * pages[k].first) << "page " << k + 1 << " of " << pages.size() << " ends its text at "
                                                     << pages[k].second << " of " << pages[k].first << " pt";
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
