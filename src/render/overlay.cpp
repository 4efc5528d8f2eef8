// 2D text and colour bars drawn with vtkContext2D (charts and, through a vtkContextActor, 3D views).

#include "detail/overlay.hpp"
#include "geartopo/render/colour_map.hpp"
#include "detail/layout.hpp"

#include <vtkBrush.h>
#include <vtkContext2D.h>
#include <vtkContextDevice2D.h>
#include <vtkContextItem.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPen.h>
#include <vtkStdString.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace geartopo::render::detail {

namespace {

struct BarTicks {
  std::vector<double> values;
  std::vector<std::string> labels;
};

/// Nice ticks inside the range plus both ends (the ends labelled with one decimal more); a nice tick closer than
/// `min_gap` (as a share of the range) to an end label is dropped.
BarTicks bar_ticks(Range range, double min_gap) {
  const double span = range.max - range.min;
  const double step = nice_step(span, 6);
  const int decimals = decimals_for_step(step);
  BarTicks t;
  t.values.push_back(range.min);
  t.labels.push_back(format_value(range.min, std::max(decimals, 1)));
  for (double v : nice_ticks(range, 6)) {
    if (v - range.min < min_gap * span || range.max - v < min_gap * span) continue;
    t.values.push_back(v);
    t.labels.push_back(format_value(v, decimals));
  }
  t.values.push_back(range.max);
  t.labels.push_back(format_value(range.max, std::max(decimals, 1)));
  return t;
}

float tick_label_px(int px) { return static_cast<float>(std::lround(0.9 * px)); }

class OverlayItem : public vtkContextItem {
public:
  static OverlayItem* New();
  vtkTypeMacro(OverlayItem, vtkContextItem);
  Overlay overlay;

  bool Paint(vtkContext2D* painter) override {
    for (const OverlayText& t : overlay.texts) draw_text(painter, t);
    if (overlay.bar) draw_colour_bar(painter, *overlay.bar);
    return true;
  }
};
vtkStandardNewMacro(OverlayItem);

} // namespace

void style_text(vtkTextProperty* property, int px, Rgb colour, bool bold) {
  const std::string& file = font_file(bold);
  if (!file.empty()) {
    property->SetFontFamily(VTK_FONT_FILE);
    property->SetFontFile(file.c_str());
  } else {
    property->SetFontFamilyToArial();
    property->SetBold(bold);
  }
  property->SetFontSize(px);
  property->SetColor(colour.r / 255.0, colour.g / 255.0, colour.b / 255.0);
  property->SetOpacity(1.0);
  property->SetBackgroundOpacity(0.0);
  property->SetFrame(false);
  property->SetShadow(false);
  property->SetItalic(false);
}

TextRaster rasterise_text(const std::string& text, int px, Rgb colour, bool bold, float angle_deg) {
  TextRaster r;
  if (text.empty()) return r;
  vtkNew<vtkTextProperty> property;
  style_text(property, px, colour, bold);
  property->SetOrientation(angle_deg);
  property->SetJustificationToLeft();
  property->SetVerticalJustificationToBottom();
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  vtkNew<vtkImageData> image;
  int dims[2] = {0, 0};
  if (renderer == nullptr || !renderer->RenderString(property, vtkStdString(text), image, dims, 72)) return r;
  int extent[6];
  image->GetExtent(extent);
  const int iw = extent[1] - extent[0] + 1;
  const int ih = extent[3] - extent[2] + 1;
  const int w = std::min(dims[0], iw);
  const int h = std::min(dims[1], ih);
  if (w <= 0 || h <= 0 || image->GetNumberOfScalarComponents() != 4) return r;
  // One transparent pixel all round: the texture that draws it then never wraps glyph pixels onto the opposite
  // edge (VTK's own text quads do, leaving faint marks under digits).
  r.width = w + 2;
  r.height = h + 2;
  r.rgba.assign(static_cast<std::size_t>(r.width) * r.height * 4, 0);
  const auto* src = static_cast<const unsigned char*>(image->GetScalarPointer());
  for (int y = 0; y < h; ++y)
    std::copy_n(src + static_cast<std::size_t>(y) * iw * 4, static_cast<std::size_t>(w) * 4,
                r.rgba.data() + (static_cast<std::size_t>(y + 1) * r.width + 1) * 4);
  return r;
}

std::pair<int, int> text_size(const std::string& text, int px, bool bold) {
  if (text.empty()) return {0, 0};
  vtkNew<vtkTextProperty> property;
  style_text(property, px, colours::text, bold);
  int bbox[4] = {0, 0, 0, 0};
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  if (renderer == nullptr || !renderer->GetBoundingBox(property, vtkStdString(text), bbox, 72)) return {0, 0};
  return {bbox[1] - bbox[0] + 1, bbox[3] - bbox[2] + 1};
}

namespace {

/// `r` on a white halo of `radius` px (alpha dilated with a square kernel), composited "text over halo".
TextRaster with_halo(const TextRaster& r, int radius) {
  TextRaster out;
  out.width = r.width + 2 * radius;
  out.height = r.height + 2 * radius;
  out.rgba.assign(static_cast<std::size_t>(out.width) * out.height * 4, 0);
  const auto alpha_at = [&](int x, int y) -> int {
    if (x < 0 || y < 0 || x >= r.width || y >= r.height) return 0;
    return r.rgba[(static_cast<std::size_t>(y) * r.width + x) * 4 + 3];
  };
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      int halo = 0;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) halo = std::max(halo, alpha_at(x - radius + dx, y - radius + dy));
      const int sx = x - radius;
      const int sy = y - radius;
      const double at = alpha_at(sx, sy) / 255.0;
      const double ah = halo / 255.0;
      const double a = at + ah * (1.0 - at);
      unsigned char* o = &out.rgba[(static_cast<std::size_t>(y) * out.width + x) * 4];
      if (a <= 0.0) continue;
      for (int c = 0; c < 3; ++c) {
        const double text = at > 0.0 ? r.rgba[(static_cast<std::size_t>(sy) * r.width + sx) * 4 + c] : 0.0;
        o[c] = static_cast<unsigned char>(std::lround((text * at + 255.0 * ah * (1.0 - at)) / a));
      }
      o[3] = static_cast<unsigned char>(std::lround(255.0 * a));
    }
  return out;
}

} // namespace

void draw_text(vtkContext2D* painter, const OverlayText& t) {
  TextRaster r = rasterise_text(t.text, t.px, t.colour, t.bold, t.angle_deg);
  if (r.width == 0) return;
  if (t.halo) r = with_halo(r, std::max(2, t.px / 6));
  const float w = static_cast<float>(r.width);
  const float h = static_cast<float>(r.height);
  const float dx = t.h == HAlign::left ? 0.0F : t.h == HAlign::centre ? 0.5F * w : w;
  const float dy = t.v == VAlign::bottom ? 0.0F : t.v == VAlign::centre ? 0.5F * h : h;
  // Whole-pixel corner: the text stays sharp.
  const float x = std::round(t.x - dx);
  const float y = std::round(t.y - dy);
  if (t.box) {
    const float pad = 0.2F * static_cast<float>(t.px);
    painter->GetPen()->SetLineType(vtkPen::NO_PEN);
    painter->GetBrush()->SetColor(255, 255, 255, 215);
    painter->DrawRect(x - pad, y - pad, w + 2 * pad, h + 2 * pad);
    painter->GetPen()->SetLineType(vtkPen::SOLID_LINE);
  }
  vtkNew<vtkImageData> image;
  image->SetDimensions(r.width, r.height, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 4);
  std::copy(r.rgba.begin(), r.rgba.end(), static_cast<unsigned char*>(image->GetScalarPointer()));
  painter->DrawImage(x, y, image);
}

float colour_bar_reserve(Range range, const std::string& label, int px) {
  const BarTicks ticks = bar_ticks(range, 0.06);
  double label_w = 0.0;
  for (const std::string& s : ticks.labels) label_w = std::max(label_w, text_width_estimate(s, tick_label_px(px)));
  const double bar_w = std::max(16.0, 1.2 * px);
  const double title_h = label.empty() ? 0.0 : 1.3 * px;
  return static_cast<float>(0.8 * px + bar_w + 0.5 * px + label_w + 0.6 * px + title_h + 0.8 * px);
}

ColourBar place_colour_bar(Range range, const std::string& label, int px, ImageSize size, float bottom, float top) {
  ColourBar bar;
  bar.range = range;
  bar.label = label;
  bar.px = px;
  bar.w = static_cast<float>(std::max(16.0, 1.2 * px));
  const float available = std::max(top - bottom, 60.0F);
  bar.h = 0.8F * available;
  bar.x = static_cast<float>(size.width) - colour_bar_reserve(range, label, px) + 0.8F * static_cast<float>(px);
  bar.y = bottom + 0.5F * (available - bar.h);
  return bar;
}

void draw_colour_bar(vtkContext2D* painter, const ColourBar& bar) {
  const Range r = bar.range;
  const double span = r.max - r.min;
  if (!(span > 0.0)) return;
  // Gradient: thin quads with per-vertex colours; a break at 0 keeps the near-white centre exact.
  std::vector<double> stops;
  constexpr int segments = 96;
  for (int i = 0; i <= segments; ++i) stops.push_back(r.min + span * i / segments);
  if (r.min < 0.0 && r.max > 0.0) stops.push_back(0.0);
  std::sort(stops.begin(), stops.end());
  const auto y_of = [&](double v) { return bar.y + static_cast<float>((v - r.min) / span) * bar.h; };
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
    const double a = stops[i];
    const double b = stops[i + 1];
    if (b - a <= 0.0) continue;
    const Rgb ca = colour_for(a, r);
    const Rgb cb = colour_for(b, r);
    float points[8] = {bar.x, y_of(a), bar.x + bar.w, y_of(a), bar.x + bar.w, y_of(b), bar.x, y_of(b)};
    unsigned char colours[16] = {ca.r, ca.g, ca.b, 255, ca.r, ca.g, ca.b, 255,
                                 cb.r, cb.g, cb.b, 255, cb.r, cb.g, cb.b, 255};
    painter->GetDevice()->DrawColoredPolygon(points, 4, colours, 4);
  }
  // Frame and ticks.
  vtkPen* pen = painter->GetPen();
  pen->SetLineType(vtkPen::SOLID_LINE);
  pen->SetColor(colours::text.r, colours::text.g, colours::text.b, 255);
  pen->SetWidth(1.0F);
  painter->GetBrush()->SetOpacity(0);
  painter->DrawRect(bar.x, bar.y, bar.w, bar.h);
  const BarTicks ticks = bar_ticks(r, 1.6 * bar.px / std::max(bar.h, 1.0F));
  const int label_px = static_cast<int>(tick_label_px(bar.px));
  const float tick = 0.3F * static_cast<float>(bar.px);
  float label_right = bar.x + bar.w;
  for (std::size_t i = 0; i < ticks.values.size(); ++i) {
    const float y = y_of(ticks.values[i]);
    painter->DrawLine(bar.x + bar.w, y, bar.x + bar.w + tick, y);
    OverlayText t;
    t.x = bar.x + bar.w + tick + 0.25F * static_cast<float>(bar.px);
    t.y = y;
    t.text = ticks.labels[i];
    t.px = label_px;
    t.v = VAlign::centre;
    draw_text(painter, t);
    label_right = std::max(label_right, t.x + static_cast<float>(text_width_estimate(t.text, label_px)));
  }
  if (!bar.label.empty()) {
    OverlayText t;
    t.x = label_right + 0.5F * static_cast<float>(bar.px);
    t.y = bar.y + 0.5F * bar.h;
    t.text = bar.label;
    t.px = bar.px;
    t.h = HAlign::left;
    t.v = VAlign::centre;
    t.angle_deg = 90.0F;
    draw_text(painter, t);
  }
}

vtkContextItem* new_overlay_item(Overlay overlay) {
  OverlayItem* item = OverlayItem::New();
  item->overlay = std::move(overlay);
  return item;
}

} // namespace geartopo::render::detail
