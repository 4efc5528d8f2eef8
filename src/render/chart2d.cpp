// vtkChartXY on an off-screen context, fed with plain C++ primitives (line chart, bar chart, heat map).
// Custom drawing (bands, cells, reference lines, text) happens in PrimitivePlot, a vtkPlot whose Paint maps chart
// coordinates to pixels itself from the axes' end points, so that it does not depend on the chart's internal
// transforms (shift/scale of large coordinates).

#include "detail/chart2d.hpp"
#include "detail/layout.hpp"
#include "detail/offscreen.hpp"
#include "detail/overlay.hpp"

#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkChartXY.h>
#include <vtkContext2D.h>
#include <vtkContextDevice2D.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPen.h>
#include <vtkPlotBar.h>
#include <vtkPlotLine.h>
#include <vtkPlotPoints.h>
#include <vtkRect.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkTransform2D.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace geartopo::render::detail {

namespace {

/// Chart coordinates → scene pixels, from the axes' end points (valid once the chart has laid itself out).
struct PixelMap {
  double x_min = 0, x_max = 1, px0 = 0, px1 = 1;
  double y_min = 0, y_max = 1, py0 = 0, py1 = 1;
  float x(double v) const { return static_cast<float>(px0 + (v - x_min) / (x_max - x_min) * (px1 - px0)); }
  float y(double v) const { return static_cast<float>(py0 + (v - y_min) / (y_max - y_min) * (py1 - py0)); }
  float left() const { return static_cast<float>(px0); }
  float right() const { return static_cast<float>(px1); }
  float bottom() const { return static_cast<float>(py0); }
  float top() const { return static_cast<float>(py1); }

  static PixelMap of(vtkAxis* xa, vtkAxis* ya) {
    PixelMap m;
    m.x_min = xa->GetUnscaledMinimum();
    m.x_max = xa->GetUnscaledMaximum();
    m.px0 = xa->GetPoint1()[0];
    m.px1 = xa->GetPoint2()[0];
    m.y_min = ya->GetUnscaledMinimum();
    m.y_max = ya->GetUnscaledMaximum();
    m.py0 = ya->GetPoint1()[1];
    m.py1 = ya->GetPoint2()[1];
    return m;
  }
};

using PaintFn = std::function<void(vtkContext2D*, const PixelMap&)>;

class PrimitivePlot : public vtkPlot {
public:
  static PrimitivePlot* New();
  vtkTypeMacro(PrimitivePlot, vtkPlot);
  PaintFn paint;
  bool unclipped = false; ///< paint outside the plot area too (frame, labels near the edge)

  bool Paint(vtkContext2D* painter) override {
    if (!paint || GetXAxis() == nullptr || GetYAxis() == nullptr) return true;
    const PixelMap map = PixelMap::of(GetXAxis(), GetYAxis());
    painter->PushMatrix();
    vtkNew<vtkTransform2D> identity;
    painter->SetTransform(identity);
    if (unclipped) painter->GetDevice()->EnableClipping(false);
    paint(painter, map);
    if (unclipped) painter->GetDevice()->EnableClipping(true);
    painter->PopMatrix();
    return true;
  }
  void GetBounds(double bounds[4]) override { bounds[0] = bounds[1] = bounds[2] = bounds[3] = 0.0; }
};
vtkStandardNewMacro(PrimitivePlot);

void set_pen(vtkPen* pen, Rgb c, double width, bool dashed, unsigned char alpha = 255) {
  pen->SetColor(c.r, c.g, c.b, alpha);
  pen->SetWidth(static_cast<float>(width));
  pen->SetLineType(dashed ? vtkPen::DASH_LINE : vtkPen::SOLID_LINE);
}

void set_brush(vtkBrush* brush, Rgb c, double opacity) {
  brush->SetColor(c.r, c.g, c.b, static_cast<unsigned char>(std::lround(std::clamp(opacity, 0.0, 1.0) * 255)));
}

vtkSmartPointer<vtkTable> xy_table(const std::vector<double>& x, const std::vector<double>& y) {
  vtkNew<vtkDoubleArray> xs;
  xs->SetName("x");
  vtkNew<vtkDoubleArray> ys;
  ys->SetName("y");
  xs->SetNumberOfValues(static_cast<vtkIdType>(x.size()));
  ys->SetNumberOfValues(static_cast<vtkIdType>(y.size()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    xs->SetValue(static_cast<vtkIdType>(i), x[i]);
    ys->SetValue(static_cast<vtkIdType>(i), y[i]);
  }
  auto table = vtkSmartPointer<vtkTable>::New();
  table->AddColumn(xs);
  table->AddColumn(ys);
  return table;
}

int marker_style(Marker m) {
  switch (m) {
  case Marker::none: return vtkPlotPoints::NONE;
  case Marker::circle: return vtkPlotPoints::CIRCLE;
  case Marker::square: return vtkPlotPoints::SQUARE;
  case Marker::diamond: return vtkPlotPoints::DIAMOND;
  case Marker::cross: return vtkPlotPoints::CROSS;
  case Marker::plus: return vtkPlotPoints::PLUS;
  }
  return vtkPlotPoints::NONE;
}

struct Ticks {
  std::vector<double> positions;
  std::vector<std::string> labels;
};

/// The caller's ticks, or nice ticks about every 4.5 font sizes along an axis of `length_px`.
Ticks make_ticks(Range range, int px, double length_px, const std::vector<double>& custom,
                 const std::vector<std::string>& custom_labels) {
  Ticks t;
  if (!custom.empty()) {
    t.positions = custom;
    const int decimals = custom.size() > 1 ? decimals_for_step(std::abs(custom[1] - custom[0])) : 0;
    for (std::size_t i = 0; i < custom.size(); ++i) // unlabelled custom ticks show their value
      t.labels.push_back(i < custom_labels.size() ? custom_labels[i] : format_value(custom[i], decimals));
    return t;
  }
  const int target = std::clamp(static_cast<int>(length_px / (4.5 * px)), 3, 10);
  const int decimals = decimals_for_step(nice_step(range.max - range.min, target));
  t.positions = nice_ticks(range, target);
  for (double v : t.positions) t.labels.push_back(format_value(v, decimals));
  return t;
}

double widest(const std::vector<std::string>& labels, int px) {
  double w = 0.0;
  for (const std::string& s : labels) w = std::max(w, text_width_estimate(s, px));
  return w;
}

/// The axis itself draws only its line and the grid; ticks, labels and titles are drawn by draw_axes() so that
/// their placement does not depend on VTK's label layout.
void set_axis(vtkAxis* axis, Range range, bool grid, const Ticks& ticks) {
  axis->SetTitle("");
  axis->SetLabelsVisible(false);
  axis->SetTicksVisible(false);
  axis->SetRangeLabelsVisible(false);
  axis->SetBehavior(vtkAxis::FIXED);
  axis->SetRange(range.min, range.max);
  axis->GetPen()->SetColor(colours::text.r, colours::text.g, colours::text.b, 255);
  axis->GetPen()->SetWidth(1.2F);
  axis->GetGridPen()->SetColor(222, 222, 222, 255);
  axis->GetGridPen()->SetWidth(1.0F);
  axis->SetGridVisible(grid);
  vtkNew<vtkDoubleArray> positions;
  vtkNew<vtkStringArray> labels;
  for (double t : ticks.positions) {
    positions->InsertNextValue(t);
    labels->InsertNextValue(""); // VTK still lays out hidden labels; draw_axes() writes the real ones
  }
  axis->SetCustomTickPositions(positions, labels);
}

struct LegendEntry {
  enum class Kind { line, band, bar, outline } kind = Kind::line;
  std::string label;
  Rgb colour;
  double width = 2.0;
  bool dashed = false;
  Marker marker = Marker::none;
  double marker_size = 7.0;
  double opacity = 1.0;
};

const std::string& label_of(const LegendEntry& e) { return e.label; }
const std::string& label_of(const std::string& label) { return label; }

void draw_hatch(vtkContext2D* p, float x0, float y0, float x1, float y1, float step) {
  for (float k = std::floor((x0 - y1) / step) * step; k <= x1 - y0; k += step) {
    const float ya = std::max(y0, x0 - k), yb = std::min(y1, x1 - k);
    if (yb > ya) p->DrawLine(ya + k, ya, yb + k, yb);
  }
}

constexpr float kLegendGap = 1.2F;      // between entries of a row above the plot (× px)
constexpr float kLegendRowPitch = 1.5F; // between rows above the plot (× px)

/// An entry's width in a legend row above the plot: symbol, gap, label (px).
float legend_entry_width(const std::string& label, int px) {
  const int lpx = static_cast<int>(std::lround(0.9 * px));
  return 2.2F * static_cast<float>(px) + 0.5F * static_cast<float>(lpx) + static_cast<float>(text_size(label, lpx).first);
}

template <class Entries> float legend_row_width(const Entries& entries, std::size_t begin, std::size_t end, int px) {
  float w = 0.0F;
  for (std::size_t i = begin; i < end; ++i) w += legend_entry_width(label_of(entries[i]), px);
  return w + static_cast<float>(end - begin - 1) * kLegendGap * static_cast<float>(px);
}

/// The first entry of each row of a legend above the plot whose rows may be `width` px wide: entries in order,
/// a new row when the next would not fit (a single entry wider than `width` gets a row of its own).
template <class Entries> std::vector<std::size_t> legend_row_starts(const Entries& entries, int px, float width) {
  std::vector<std::size_t> starts{0};
  for (std::size_t i = 1; i < entries.size(); ++i)
    if (legend_row_width(entries, starts.back(), i + 1, px) > width) starts.push_back(i);
  return starts;
}

/// The legend box at `corner` of the plot area, `offset` px further inwards vertically (below / above a text
/// block in the same corner).
void draw_legend(vtkContext2D* p, const PixelMap& m, const std::vector<LegendEntry>& entries, LegendPlace place, int px,
                 float offset) {
  if (entries.empty() || place == LegendPlace::none) return;
  const int lpx = static_cast<int>(std::lround(0.9 * px));
  const float row = 1.45F * static_cast<float>(lpx);
  const float pad = 0.5F * static_cast<float>(lpx);
  const float symbol = 2.2F * static_cast<float>(px);
  float text_w = 0.0F;
  for (const LegendEntry& e : entries) text_w = std::max(text_w, static_cast<float>(text_size(e.label, lpx).first));
  const float inset = 0.5F * static_cast<float>(px);
  // Symbol left edges and row centres of the entries.
  std::vector<float> xs;
  std::vector<float> ys;
  if (place == LegendPlace::above) {
    // Rows right-aligned over the plot area's top edge, no box; the first row highest.
    const std::vector<std::size_t> starts = legend_row_starts(entries, px, m.right() - 0.5F * static_cast<float>(px));
    for (std::size_t r = 0; r < starts.size(); ++r) {
      const std::size_t end = r + 1 < starts.size() ? starts[r + 1] : entries.size();
      float x = m.right() - legend_row_width(entries, starts[r], end, px);
      const float y = m.top() + 0.9F * static_cast<float>(px) +
                      static_cast<float>(starts.size() - 1 - r) * kLegendRowPitch * static_cast<float>(px);
      for (std::size_t i = starts[r]; i < end; ++i) {
        xs.push_back(x);
        ys.push_back(y);
        x += legend_entry_width(entries[i].label, px) + kLegendGap * static_cast<float>(px);
      }
    }
  } else {
    const float w = pad + symbol + 0.5F * static_cast<float>(lpx) + text_w + pad;
    const float h = 2 * pad + row * static_cast<float>(entries.size()) - 0.2F * row;
    const bool left = place == LegendPlace::top_left || place == LegendPlace::bottom_left;
    const bool top = place == LegendPlace::top_left || place == LegendPlace::top_right;
    const float x0 = left ? m.left() + inset : m.right() - inset - w;
    const float y0 = top ? m.top() - inset - offset - h : m.bottom() + inset + offset;
    set_pen(p->GetPen(), {150, 150, 150}, 1.0, false);
    set_brush(p->GetBrush(), colours::white, 0.92);
    p->DrawRect(x0, y0, w, h);
    for (std::size_t i = 0; i < entries.size(); ++i) {
      xs.push_back(x0 + pad);
      ys.push_back(y0 + h - pad - row * (static_cast<float>(i) + 0.4F));
    }
  }
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const LegendEntry& e = entries[i];
    const float yc = ys[i];
    const float sx0 = xs[i];
    const float sx1 = sx0 + symbol;
    const float sh = 0.7F * row;
    switch (e.kind) {
    case LegendEntry::Kind::line: {
      set_pen(p->GetPen(), e.colour, e.width, e.dashed);
      p->DrawLine(sx0, yc, sx1, yc);
      if (e.marker != Marker::none) {
        set_pen(p->GetPen(), e.colour, 1.0, false);
        set_brush(p->GetBrush(), e.colour, 1.0);
        float point[2] = {0.5F * (sx0 + sx1), yc};
        p->GetPen()->SetWidth(static_cast<float>(e.marker_size));
        p->DrawMarkers(marker_style(e.marker), false, point, 1);
      }
      break;
    }
    case LegendEntry::Kind::band:
      set_pen(p->GetPen(), e.colour, 1.0, false);
      set_brush(p->GetBrush(), e.colour, std::max(e.opacity, 0.35));
      p->DrawRect(sx0, yc - 0.5F * sh, symbol, sh);
      break;
    case LegendEntry::Kind::bar:
      set_pen(p->GetPen(), {60, 60, 60}, 0.8, false);
      set_brush(p->GetBrush(), e.colour, 1.0);
      p->DrawRect(sx0, yc - 0.5F * sh, symbol, sh);
      break;
    case LegendEntry::Kind::outline:
      set_pen(p->GetPen(), colours::black, 1.0, false, 150);
      draw_hatch(p, sx0, yc - 0.5F * sh, sx1, yc + 0.5F * sh, 6.0F);
      set_pen(p->GetPen(), colours::black, std::max(2.0, 0.12 * px), false);
      p->GetBrush()->SetOpacity(0);
      p->DrawRect(sx0, yc - 0.5F * sh, symbol, sh);
      break;
    }
    OverlayText t;
    t.x = sx1 + 0.5F * static_cast<float>(lpx);
    t.y = yc;
    t.text = e.label;
    t.px = lpx;
    t.v = VAlign::centre;
    draw_text(p, t);
  }
  p->GetPen()->SetLineType(vtkPen::SOLID_LINE);
}

struct AxesText {
  Ticks x_ticks;
  Ticks y_ticks;
  std::string x_label;
  std::string y_label;
  int px = 18;
  float left_margin = 0.0F; // px from the image's left edge to the plot area
};

/// Outward ticks, tick labels and axis titles round the plot area.
void draw_axes(vtkContext2D* p, const PixelMap& m, const AxesText& a) {
  const float tick = 0.35F * static_cast<float>(a.px);
  const int label_px = static_cast<int>(std::lround(0.9 * a.px));
  set_pen(p->GetPen(), colours::text, 1.2, false);
  for (std::size_t i = 0; i < a.x_ticks.positions.size(); ++i) {
    const float x = m.x(a.x_ticks.positions[i]);
    if (x < m.left() - 0.5F || x > m.right() + 0.5F) continue;
    p->DrawLine(x, m.bottom(), x, m.bottom() - tick);
    OverlayText t;
    t.x = x;
    t.y = m.bottom() - tick - 0.3F * static_cast<float>(a.px);
    t.text = a.x_ticks.labels[i];
    t.px = label_px;
    t.h = HAlign::centre;
    t.v = VAlign::top;
    draw_text(p, t);
  }
  for (std::size_t i = 0; i < a.y_ticks.positions.size(); ++i) {
    const float y = m.y(a.y_ticks.positions[i]);
    if (y < m.bottom() - 0.5F || y > m.top() + 0.5F) continue;
    p->DrawLine(m.left(), y, m.left() - tick, y);
    OverlayText t;
    t.x = m.left() - tick - 0.3F * static_cast<float>(a.px);
    t.y = y;
    t.text = a.y_ticks.labels[i];
    t.px = label_px;
    t.h = HAlign::right;
    t.v = VAlign::centre;
    draw_text(p, t);
  }
  OverlayText xt;
  xt.x = 0.5F * (m.left() + m.right());
  xt.y = m.bottom() - tick - 0.3F * static_cast<float>(a.px) - 1.35F * static_cast<float>(label_px);
  xt.text = a.x_label;
  xt.px = a.px;
  xt.h = HAlign::centre;
  xt.v = VAlign::top;
  draw_text(p, xt);
  OverlayText yt;
  yt.x = m.left() - a.left_margin + 0.5F * static_cast<float>(a.px);
  yt.y = 0.5F * (m.bottom() + m.top());
  yt.text = a.y_label;
  yt.px = a.px;
  yt.h = HAlign::left;
  yt.v = VAlign::centre;
  yt.angle_deg = 90.0F;
  draw_text(p, yt);
}

} // namespace

struct ChartBuilder::Impl {
  ChartFrame frame;
  Offscreen offscreen; // first member: the context outlives every VTK object below
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  std::vector<PaintFn> overlay; // painted after every series, unclipped
  TextBlock text_block;
  Overlay scene_overlay; // title, colour bar
  AxesText axes;
  std::vector<LegendEntry> legend;

  explicit Impl(const ChartFrame& f) : frame(f), offscreen(f.size.width, f.size.height) {
    view->SetRenderWindow(offscreen.window());
    view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    view->GetScene()->AddItem(chart);
    const int px = frame.px;
    const int label_px = static_cast<int>(std::lround(0.9 * px));
    const double W = frame.size.width;
    const double H = frame.size.height;
    // The plot area is placed explicitly (AXES_TO_RECT): margins from the fonts and the tick labels, so that
    // nothing is clipped at the image edges whatever the labels are.
    const float reserve = frame.colour_bar ? colour_bar_reserve(*frame.colour_bar, frame.colour_bar_label, px) : 0.0F;
    const double bottom = 0.35 * px + 0.3 * px + 1.25 * label_px + (frame.x_label.empty() ? 0.6 : 2.1) * px;
    const double first_guess_w = W - reserve - 8.0 * px;
    const Ticks x_ticks = make_ticks(frame.x_range, px, first_guess_w, frame.x_ticks, frame.x_tick_labels);
    const std::string last_x_label = x_ticks.labels.empty() ? std::string() : x_ticks.labels.back();
    const double right = std::max(reserve + 0.6 * px, 0.5 * text_width_estimate(last_x_label, label_px) + 0.9 * px);
    // A legend above the plot: its rows as draw_legend() breaks them at the plot area's right edge.
    const std::size_t legend_rows =
        frame.legend != LegendPlace::above ? 0
        : frame.legend_labels.empty()      ? 1
                                           : legend_row_starts(frame.legend_labels, px,
                                                               static_cast<float>(W - right - 0.5 * px)).size();
    const double top = (frame.title.empty() ? 1.2 * px : 2.9 * px) +
                       (legend_rows == 0 ? 0.0 : 1.6 * px + (legend_rows - 1) * kLegendRowPitch * px);
    const Ticks y_ticks = make_ticks(frame.y_range, px, H - top - bottom, {}, {});
    const double left =
        0.35 * px + 0.3 * px + widest(y_ticks.labels, label_px) + 0.4 * px + (frame.y_label.empty() ? 0.4 : 2.0) * px;
    chart->SetLayoutStrategy(vtkChart::AXES_TO_RECT);
    chart->SetSize(vtkRectf(static_cast<float>(left), static_cast<float>(bottom), static_cast<float>(W - left - right),
                            static_cast<float>(H - bottom - top)));
    set_axis(chart->GetAxis(vtkAxis::BOTTOM), frame.x_range, frame.grid, x_ticks);
    set_axis(chart->GetAxis(vtkAxis::LEFT), frame.y_range, frame.grid, y_ticks);
    axes = {x_ticks, y_ticks, frame.x_label, frame.y_label, px, static_cast<float>(left)};
    for (int side : {vtkAxis::TOP, vtkAxis::RIGHT}) chart->GetAxis(side)->SetVisible(false);
    if (!frame.title.empty()) {
      OverlayText t;
      t.x = static_cast<float>(0.5 * (left + W - right));
      t.y = static_cast<float>(H - 1.5 * px);
      t.text = frame.title;
      t.px = static_cast<int>(std::lround(1.2 * px));
      t.bold = true;
      t.h = HAlign::centre;
      t.v = VAlign::centre;
      scene_overlay.texts.push_back(t);
    }
    chart->SetShowLegend(false); // drawn by draw_legend()
  }

  PrimitivePlot* add_primitive(PaintFn paint) {
    vtkNew<PrimitivePlot> plot;
    plot->paint = std::move(paint);
    plot->SetLegendVisibility(false);
    chart->AddPlot(plot);
    return plot;
  }
};

ChartBuilder::ChartBuilder(const ChartFrame& frame) : impl_(std::make_unique<Impl>(frame)) {}
ChartBuilder::~ChartBuilder() = default;

void ChartBuilder::add_band(const Band& band) {
  const auto paint = [band](vtkContext2D* p, const PixelMap& m) {
    p->GetPen()->SetLineType(vtkPen::NO_PEN);
    set_brush(p->GetBrush(), band.colour, band.opacity);
    if (band.orientation == Orientation::horizontal) {
      const float y0 = m.y(std::min(band.from, band.to));
      const float y1 = m.y(std::max(band.from, band.to));
      p->DrawRect(m.left(), y0, m.right() - m.left(), y1 - y0);
    } else {
      const float x0 = m.x(std::min(band.from, band.to));
      const float x1 = m.x(std::max(band.from, band.to));
      p->DrawRect(x0, m.bottom(), x1 - x0, m.top() - m.bottom());
    }
    p->GetPen()->SetLineType(vtkPen::SOLID_LINE);
  };
  impl_->add_primitive(paint);
  if (!band.label.empty())
    impl_->legend.push_back(
        {LegendEntry::Kind::band, band.label, band.colour, 1.0, false, Marker::none, 0.0, band.opacity});
}

void ChartBuilder::add_line(const Series& s, Rgb colour) {
  vtkPlot* plot = impl_->chart->AddPlot(vtkChart::LINE);
  plot->SetInputData(xy_table(s.x, s.y), 0, 1);
  plot->SetColor(colour.r, colour.g, colour.b, 255);
  plot->SetWidth(static_cast<float>(s.width));
  plot->GetPen()->SetLineType(s.dashed ? vtkPen::DASH_LINE : vtkPen::SOLID_LINE);
  plot->SetLegendVisibility(false);
  if (!s.name.empty())
    impl_->legend.push_back({LegendEntry::Kind::line, s.name, colour, s.width, s.dashed, s.marker, s.marker_size, 1.0});
  if (auto* points = vtkPlotPoints::SafeDownCast(plot)) {
    points->SetMarkerStyle(marker_style(s.marker));
    points->SetMarkerSize(static_cast<float>(s.marker_size));
  }
}

void ChartBuilder::add_bars(const std::vector<double>& x, const std::vector<double>& y, const std::string& name,
                            Rgb colour, double bar_width_fraction) {
  impl_->chart->SetBarWidthFraction(static_cast<float>(bar_width_fraction));
  vtkPlot* plot = impl_->chart->AddPlot(vtkChart::BAR);
  plot->SetInputData(xy_table(x, y), 0, 1);
  plot->SetColor(colour.r, colour.g, colour.b, 255);
  plot->GetPen()->SetColor(60, 60, 60, 255);
  plot->GetPen()->SetWidth(0.8F);
  plot->SetLegendVisibility(false);
  if (!name.empty())
    impl_->legend.push_back({LegendEntry::Kind::bar, name, colour, 1.0, false, Marker::none, 0.0, 1.0});
}

void ChartBuilder::add_cells(std::vector<ChartCell> cells, int text_px) {
  const auto paint = [cells = std::move(cells), text_px](vtkContext2D* p, const PixelMap& m) {
    p->GetPen()->SetLineType(vtkPen::NO_PEN);
    float min_w = 1e9F;
    float min_h = 1e9F;
    for (const ChartCell& c : cells) {
      const float x0 = m.x(c.x0), x1 = m.x(c.x1), y0 = m.y(c.y0), y1 = m.y(c.y1);
      set_brush(p->GetBrush(), c.colour, 1.0);
      p->DrawRect(std::min(x0, x1), std::min(y0, y1), std::abs(x1 - x0), std::abs(y1 - y0));
      min_w = std::min(min_w, std::abs(x1 - x0));
      min_h = std::min(min_h, std::abs(y1 - y0));
    }
    // Thin white cell borders where the cells are large enough to need them.
    if (min_w > 10.0F && min_h > 10.0F) {
      set_pen(p->GetPen(), colours::white, 1.0, false);
      p->GetBrush()->SetOpacity(0);
      for (const ChartCell& c : cells) {
        const float x0 = m.x(c.x0), x1 = m.x(c.x1), y0 = m.y(c.y0), y1 = m.y(c.y1);
        p->DrawRect(std::min(x0, x1), std::min(y0, y1), std::abs(x1 - x0), std::abs(y1 - y0));
      }
    }
    // Hatching: 45° lines on a global 9 px grid so that neighbouring cells join up.
    set_pen(p->GetPen(), colours::black, 1.0, false, 150);
    const float step = 9.0F;
    for (const ChartCell& c : cells) {
      if (!c.hatched) continue;
      const float X0 = std::min(m.x(c.x0), m.x(c.x1)), X1 = std::max(m.x(c.x0), m.x(c.x1));
      const float Y0 = std::min(m.y(c.y0), m.y(c.y1)), Y1 = std::max(m.y(c.y0), m.y(c.y1));
      draw_hatch(p, X0, Y0, X1, Y1, step);
    }
    // Values.
    for (const ChartCell& c : cells) {
      if (c.text.empty()) continue;
      const float w = std::abs(m.x(c.x1) - m.x(c.x0)), h = std::abs(m.y(c.y1) - m.y(c.y0));
      if (text_width_estimate(c.text, text_px) > w - 4.0 || 1.15 * text_px > h) continue;
      OverlayText t;
      t.x = 0.5F * (m.x(c.x0) + m.x(c.x1));
      t.y = 0.5F * (m.y(c.y0) + m.y(c.y1));
      t.text = c.text;
      t.px = text_px;
      t.colour = c.text_colour;
      t.h = HAlign::centre;
      t.v = VAlign::centre;
      draw_text(p, t);
    }
    p->GetPen()->SetLineType(vtkPen::SOLID_LINE);
  };
  impl_->add_primitive(paint);
}

void ChartBuilder::add_outline(std::vector<ChartSegment> segments, const std::string& label) {
  const int px = impl_->frame.px;
  const auto paint = [segments = std::move(segments), px](vtkContext2D* p, const PixelMap& m) {
    set_pen(p->GetPen(), colours::black, std::max(2.5, 0.17 * px), false);
    for (const ChartSegment& s : segments) p->DrawLine(m.x(s.x0), m.y(s.y0), m.x(s.x1), m.y(s.y1));
  };
  impl_->add_primitive(paint);
  if (!label.empty())
    impl_->legend.push_back({LegendEntry::Kind::outline, label, colours::black, 1.0, false, Marker::none, 0.0, 1.0});
}

void ChartBuilder::add_ref_line(const RefLine& line) {
  const int px = impl_->frame.px;
  impl_->overlay.push_back([line, px](vtkContext2D* p, const PixelMap& m) {
    set_pen(p->GetPen(), line.colour, line.width, line.dashed);
    OverlayText t;
    t.text = line.label;
    t.px = static_cast<int>(std::lround(0.8 * px));
    t.colour = line.colour;
    t.box = true;
    if (line.orientation == Orientation::horizontal) {
      const float y = m.y(line.at);
      if (y < m.bottom() - 0.5F || y > m.top() + 0.5F) return;
      p->DrawLine(m.left(), y, m.right(), y);
      t.x = m.right() - 0.3F * px;
      t.y = y + 0.25F * px;
      t.h = HAlign::right;
    } else {
      const float x = m.x(line.at);
      if (x < m.left() - 0.5F || x > m.right() + 0.5F) return;
      p->DrawLine(x, m.bottom(), x, m.top());
      t.x = x + 0.3F * px;
      t.y = m.top() - 0.4F * px;
      t.v = VAlign::top;
    }
    p->GetPen()->SetLineType(vtkPen::SOLID_LINE);
    draw_text(p, t);
  });
}

void ChartBuilder::add_annotation(const Annotation& a) {
  const int px = impl_->frame.px;
  impl_->overlay.push_back([a, px](vtkContext2D* p, const PixelMap& m) {
    OverlayText t;
    t.x = m.x(a.x);
    t.y = m.y(a.y);
    t.text = a.text;
    t.px = static_cast<int>(std::lround(0.85 * px));
    t.colour = a.colour;
    t.h = a.align;
    t.v = VAlign::centre;
    draw_text(p, t);
  });
}

void ChartBuilder::set_text_block(const TextBlock& block) { impl_->text_block = block; }

void ChartBuilder::render(const std::filesystem::path& png) {
  Impl& im = *impl_;
  const int px = im.frame.px;
  const TextBlock block = im.text_block;
  auto overlay = std::move(im.overlay);
  auto paint = [overlay = std::move(overlay), block, px, axes = im.axes, legend = im.legend,
                place = im.frame.legend](vtkContext2D* p, const PixelMap& m) {
    for (const PaintFn& f : overlay) f(p, m);
    draw_axes(p, m, axes);
    // Frame round the plot area.
    set_pen(p->GetPen(), colours::text, 1.2, false);
    p->GetBrush()->SetOpacity(0);
    p->DrawRect(m.left(), m.bottom(), m.right() - m.left(), m.top() - m.bottom());
    const bool same_corner = (block.corner == Corner::top_left && place == LegendPlace::top_left) ||
                             (block.corner == Corner::top_right && place == LegendPlace::top_right) ||
                             (block.corner == Corner::bottom_left && place == LegendPlace::bottom_left) ||
                             (block.corner == Corner::bottom_right && place == LegendPlace::bottom_right);
    if (block.lines.empty()) {
      draw_legend(p, m, legend, place, px, 0.0F);
      return;
    }
    // Corner text block on a white box.
    const int tpx = static_cast<int>(std::lround(0.9 * px));
    float width = 0.0F;
    for (const std::string& line : block.lines) width = std::max(width, static_cast<float>(text_size(line, tpx).first));
    const float line_h = 1.35F * static_cast<float>(tpx);
    const float pad = 0.5F * static_cast<float>(tpx);
    const float box_w = width + 2 * pad;
    const float box_h = line_h * static_cast<float>(block.lines.size()) + pad;
    const float inset = 0.5F * static_cast<float>(px);
    const bool left = block.corner == Corner::top_left || block.corner == Corner::bottom_left;
    const bool top = block.corner == Corner::top_left || block.corner == Corner::top_right;
    const float x0 = left ? m.left() + inset : m.right() - inset - box_w;
    const float y0 = top ? m.top() - inset - box_h : m.bottom() + inset;
    set_pen(p->GetPen(), {150, 150, 150}, 1.0, false);
    set_brush(p->GetBrush(), colours::white, 0.92);
    p->DrawRect(x0, y0, box_w, box_h);
    for (std::size_t i = 0; i < block.lines.size(); ++i) {
      OverlayText t;
      t.x = x0 + pad;
      t.y = y0 + box_h - pad * 0.5F - line_h * (static_cast<float>(i) + 0.5F);
      t.text = block.lines[i];
      t.px = tpx;
      t.v = VAlign::centre;
      draw_text(p, t);
    }
    draw_legend(p, m, legend, place, px, same_corner ? box_h + 0.4F * static_cast<float>(px) : 0.0F);
  };
  PrimitivePlot* top = im.add_primitive(std::move(paint));
  top->unclipped = true;
  if (im.frame.colour_bar) {
    const vtkRectf plot = im.chart->GetSize();
    im.scene_overlay.bar = place_colour_bar(*im.frame.colour_bar, im.frame.colour_bar_label, px, im.frame.size,
                                            plot.GetY(), plot.GetY() + plot.GetHeight());
  }
  im.view->GetScene()->AddItem(vtkSmartPointer<vtkContextItem>::Take(new_overlay_item(std::move(im.scene_overlay))));
  im.offscreen.save_png(png);
}

} // namespace geartopo::render::detail
