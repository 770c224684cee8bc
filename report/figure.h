// figure.h: the project's one plot renderer, on OpenImageIO's drawing (ImageBufAlgo render_text,
// render_line, render_box, fill). A Figure is a grid of Panels; a Panel has two axes (linear or
// log, ticks at nice steps or every decade), a title, vertical marker lines, text and Series
// (lines, or points with optional +-2 standard error bars and labels that stack instead of
// overlapping), or an image; the Figure adds a title, row and column heads, an axis label, a
// legend, caption lines and a colour bar. Colours come from plot.h's palette.
//
// Conventions: values are data coordinates; on a log axis, lo and hi are decades (log10) and
// values <= 0 sit below the axis, so a curve plunges out of view instead of vanishing. Pixel
// sizes are those of the PNG.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "plot.h"

namespace retroprism::plot {

struct Axis {
    double lo = 0, hi = 1; // data range (log axis: decades)
    bool log = false;
    // Ticks: every `step` from the first multiple of it in range (0: a nice step for about
    // `ticks` intervals; log axis: whole decades, every `step` of them, 1 when 0).
    double step = 0;
    int ticks = 4;
    bool grid = true; // grid lines at the ticks
    // The label of a tick value (log axis: the decade) and the tick step; none: "1e%+.0f" on a
    // log axis, else two, one or no decimals for steps below 0.1, 1 and above.
    std::function<std::string(double value, double step)> label;
    int label_size = 12;
};

// Linear: [0, 1.08 max] of the values (1 when none is positive). Log: the `decades` below the
// first whole decade above the largest value (plus `margin` decades of headroom).
void fit_linear(Axis& a, const std::vector<double>& values);
void fit_log(Axis& a, const std::vector<double>& values, double decades, double margin);

struct Series {
    std::vector<double> x, y;
    Rgb color = kText;
    bool points = false;             // false: a polyline (broken at NaN); true: a point per value
    int width = 2;                   // line width, or the point's half-size
    std::vector<double> err;         // points: bars of +-2 err (empty: none)
    std::vector<Rgb> colors;         // points: a colour per point (empty: `color`)
    std::vector<std::string> labels; // points: a label per point, stacked downward to not
                                     // overlap, joined to the point by a leader line if moved
};

// A vertical line across the panel, with an optional label at its top or bottom.
struct Marker {
    double x = 0;
    Rgb color = kAxis;
    bool dashed = true;
    std::string label;
    bool label_bottom = false;
    bool label_left = false; // the label's end at the line (else its start)
    int label_size = 14;
};

// Text at a data position.
struct Note {
    double x = 0, y = 0;
    std::string text;
    Rgb color = kDimText;
    int size = 14;
    OIIO::ImageBufAlgo::TextAlignX ax = OIIO::ImageBufAlgo::TextAlignX::Left;
    OIIO::ImageBufAlgo::TextAlignY ay = OIIO::ImageBufAlgo::TextAlignY::Baseline;
};

struct Panel {
    std::string heading; // centred above the panel (size 20)
    std::string title;   // small, left above the panel (size 13)
    std::string x_label; // centred below the panel's tick labels (size 15)
    std::vector<std::pair<std::string, Rgb>> lines_below; // text lines under the panel
    Axis x, y;
    bool frame = true; // background, ticks and box (false: only the contents)
    std::vector<Series> series;
    std::vector<Marker> markers;
    std::vector<Note> notes;
    // Drawn over the panel's area before the series, pixel for pixel (the same size as the
    // panel); pixels whose alpha (channel 3) is 0 are left out.
    std::optional<OIIO::ImageBuf> image;
};

struct LegendEntry {
    std::string label;
    Series style; // a line, or a point (points = true)
};

// A vertical colour bar right of the panels over the panel height: `map` (an OIIO colour map)
// from lo (bottom) to hi (top), ticks every whole unit.
struct ColorBar {
    std::string map = "inferno";
    double lo = 0, hi = 1;
    std::function<std::string(double)> label; // of a tick (none: "%.0f")
};

struct Figure {
    std::string title;
    int title_size = 22;
    std::string subtitle; // a dim line under the title
    int cols = 1;
    int panel_width = 300, panel_height = 190;
    // Around each panel inside its cell: room for tick labels, titles and text below.
    int pad_left = 58, pad_right = 14, pad_top = 34, pad_bottom = 40;
    int top = 96;  // pixel row of the first cell
    int left = 30; // pixel column of the first cell (row heads: make room)
    std::vector<std::string> col_heads, row_heads;
    std::vector<Panel> panels; // row-major
    std::string x_label;       // centred under all panels
    std::vector<LegendEntry> legend;
    std::vector<std::string> caption;
    std::optional<ColorBar> color_bar;
};

// The figure as an RGB float image; text is drawn with `text` (nothing when no font).
OIIO::ImageBuf render(const Figure& fig, Text& text);

// Writes an image as an 8-bit PNG under a temporary name, then renames it; InputError when it
// cannot.
void write_png(const OIIO::ImageBuf& img, const std::string& path);

// 1, 2 or 5 times a power of ten, about range / target.
double nice_step(double range, int target);

} // namespace retroprism::plot
