// figure.cpp: the plot renderer (see figure.h).
#include "figure.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <unistd.h>

#include <OpenImageIO/imagebufalgo.h>

#include "error.h"

namespace retroprism::plot {

namespace {

namespace IBA = OIIO::ImageBufAlgo;
using AX = IBA::TextAlignX;
using AY = IBA::TextAlignY;

// A pixel coordinate from a value, never beyond the int range (NaN: far outside).
int pixel(double v) {
    if (!std::isfinite(v)) return -1000000;
    return int(std::lround(std::clamp(v, -1e6, 1e6)));
}

// The segment (x1, y1)-(x2, y2) clipped to the rectangle [x0, x1] x [y0, y1] (Liang & Barsky
// 1984); false when nothing of it is inside.
bool clip_segment(double& ax, double& ay, double& bx, double& by, double x0, double y0, double x1,
                  double y1) {
    double t0 = 0, t1 = 1;
    const double dx = bx - ax, dy = by - ay;
    const double p[4] = {-dx, dx, -dy, dy}, q[4] = {ax - x0, x1 - ax, ay - y0, y1 - ay};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0) {
            if (q[i] < 0) return false;
            continue;
        }
        const double t = q[i] / p[i];
        if (p[i] < 0)
            t0 = std::max(t0, t);
        else
            t1 = std::min(t1, t);
        if (t0 > t1) return false;
    }
    bx = ax + t1 * dx;
    by = ay + t1 * dy;
    ax += t0 * dx;
    ay += t0 * dy;
    return true;
}

std::string default_label(const Axis& a, double v, double step) {
    if (a.log) return fmt("1e%+.0f", v);
    return fmt(step < 0.1 ? "%.2f" : step < 1 ? "%.1f" : "%.0f", v);
}

// The tick values of an axis (log axis: decades).
std::vector<double> ticks(const Axis& a, double& step) {
    std::vector<double> out;
    step = a.log        ? (a.step > 0 ? a.step : 1)
           : a.step > 0 ? a.step
                        : nice_step(a.hi - a.lo, a.ticks);
    const double first = std::ceil(a.lo / step - 1e-9) * step;
    for (int i = 0; i <= 40 && first + i * step <= a.hi + 1e-9 * step; ++i)
        out.push_back(first + i * step);
    return out;
}

// The pixel geometry of one panel and its data-to-pixel maps.
struct Frame {
    const Panel& pan;
    int x0, y0, x1, y1;
    double px(double x) const {
        const double u = pan.x.log ? (x > 0 ? std::log10(x) : pan.x.lo - 1) : x;
        return x0 + (u - pan.x.lo) / (pan.x.hi - pan.x.lo) * (x1 - x0);
    }
    double py(double y) const {
        const double u = pan.y.log ? (y > 0 ? std::log10(y) : pan.y.lo - 1) : y;
        return y1 - (u - pan.y.lo) / (pan.y.hi - pan.y.lo) * (y1 - y0);
    }
    OIIO::ROI roi() const { return OIIO::ROI(x0, x1 + 1, y0, y1 + 1); }
};

void draw_segment(OIIO::ImageBuf& img, const Frame& f, double ax, double ay, double bx, double by,
                  const Rgb& c, int width) {
    if (!clip_segment(ax, ay, bx, by, f.x0, f.y0, f.x1, f.y1)) return;
    thick_line(img, pixel(ax), pixel(ay), pixel(bx), pixel(by), c, width, f.roi());
}

void draw_axes(OIIO::ImageBuf& img, const Frame& f, Text& text) {
    const Panel& pan = f.pan;
    IBA::fill(img, kPlotBackground, f.roi());
    double step = 0;
    for (double v : ticks(pan.y, step)) {
        const int y = pixel(f.y1 - (v - pan.y.lo) / (pan.y.hi - pan.y.lo) * (f.y1 - f.y0));
        if (pan.y.grid) IBA::render_line(img, f.x0, y, f.x1, y, kGrid, false, f.roi());
        text.draw(img, f.x0 - 6, y,
                  pan.y.label ? pan.y.label(v, step) : default_label(pan.y, v, step),
                  pan.y.label_size, kDimText, AX::Right, AY::Center);
    }
    for (double v : ticks(pan.x, step)) {
        const int x = pixel(f.x0 + (v - pan.x.lo) / (pan.x.hi - pan.x.lo) * (f.x1 - f.x0));
        if (pan.x.grid) IBA::render_line(img, x, f.y0, x, f.y1, kGrid, false, f.roi());
        text.draw(img, x, f.y1 + 4 + pan.x.label_size,
                  pan.x.label ? pan.x.label(v, step) : default_label(pan.x, v, step),
                  pan.x.label_size, kDimText, AX::Center);
    }
}

void draw_image(OIIO::ImageBuf& img, const Frame& f, const OIIO::ImageBuf& src) {
    const int w = src.spec().width, h = src.spec().height, n = src.nchannels();
    std::vector<float> px(size_t(std::max(n, 4)));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            src.getpixel(x, y, px.data(), n);
            if (n >= 4 && !(px[3] > 0)) continue;
            img.setpixel(f.x0 + x, f.y0 + y, px.data(), 3);
        }
}

// Point labels stacked downward where they would overlap (7 px per character at size 13); a
// leader line joins a moved label to its point.
void draw_point_labels(OIIO::ImageBuf& img, const Frame& f, const Series& s, Text& text) {
    struct Box {
        int x0, y0, x1, y1;
    };
    std::vector<Box> placed;
    for (size_t i = 0; i < s.labels.size() && i < s.x.size(); ++i) {
        const int px = pixel(f.px(s.x[i])), py = pixel(f.py(s.y[i]));
        Box b{px + 8, py - 17, px + 8 + 7 * int(s.labels[i].size()), py - 3};
        auto overlaps = [&](const Box& a) {
            for (const Box& q : placed)
                if (a.x0 < q.x1 && q.x0 < a.x1 && a.y0 < q.y1 && q.y0 < a.y1) return true;
            return false;
        };
        while (overlaps(b)) {
            b.y0 += 15;
            b.y1 += 15;
        }
        placed.push_back(b);
        if (b.y1 != py - 3) IBA::render_line(img, px + 3, py + 3, b.x0 - 2, b.y1 - 5, kDimText);
        text.draw(img, b.x0, b.y1 - 3, s.labels[i], 13, kText);
    }
}

void draw_series(OIIO::ImageBuf& img, const Frame& f, const Series& s, Text& text) {
    const bool logY = f.pan.y.log;
    if (!s.points) {
        bool have = false;
        double ax = 0, ay = 0;
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (std::isnan(s.y[i])) {
                have = false;
                continue;
            }
            const double bx = f.px(s.x[i]), by = f.py(s.y[i]);
            if (have) draw_segment(img, f, ax, ay, bx, by, s.color, s.width);
            ax = bx;
            ay = by;
            have = true;
        }
        return;
    }
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!std::isfinite(s.y[i]) || (logY && !(s.y[i] > 0))) continue;
        const Rgb& c = s.colors.empty() ? s.color : s.colors[i];
        const double x = f.px(s.x[i]);
        if (!s.err.empty()) {
            const double e = std::isfinite(s.err[i]) ? s.err[i] : 0.0;
            const double lo = std::max(s.y[i] - 2 * e, logY ? s.y[i] * 0.1 : 0.0);
            draw_segment(img, f, x, f.py(lo), x, f.py(s.y[i] + 2 * e), c, 1);
        }
        dot(img, pixel(x), pixel(f.py(s.y[i])), s.width, c, f.roi());
    }
    draw_point_labels(img, f, s, text);
}

void draw_markers(OIIO::ImageBuf& img, const Frame& f, Text& text) {
    for (const Marker& m : f.pan.markers) {
        const double xd = f.px(m.x);
        if (xd < f.x0 - 0.5 || xd > f.x1 + 0.5) continue;
        const int x = pixel(xd);
        if (m.dashed)
            dashed_vline(img, x, f.y0, f.y1, m.color);
        else
            IBA::render_line(img, x, f.y0, x, f.y1, m.color);
        if (m.label.empty()) continue;
        text.draw(img, m.label_left ? x - 4 : x + 4, m.label_bottom ? f.y1 - 8 : f.y0 - 6, m.label,
                  m.label_size, m.color, m.label_left ? AX::Right : AX::Left);
    }
}

void draw_panel(OIIO::ImageBuf& img, const Frame& f, Text& text) {
    const Panel& pan = f.pan;
    if (pan.frame) draw_axes(img, f, text);
    if (pan.image) draw_image(img, f, *pan.image);
    draw_markers(img, f, text);
    for (const Series& s : pan.series)
        draw_series(img, f, s, text);
    for (const Note& n : pan.notes)
        text.draw(img, pixel(f.px(n.x)), pixel(f.py(n.y)), n.text, n.size, n.color, n.ax, n.ay);
    if (pan.frame) IBA::render_box(img, f.x0, f.y0, f.x1, f.y1, kAxis);
    const int cx = (f.x0 + f.x1) / 2;
    if (!pan.heading.empty()) text.draw(img, cx, f.y0 - 30, pan.heading, 20, kText, AX::Center);
    if (!pan.title.empty()) text.draw(img, f.x0 + 6, f.y0 - 8, pan.title, 13, kDimText);
    if (!pan.x_label.empty()) text.draw(img, cx, f.y1 + 44, pan.x_label, 15, kDimText, AX::Center);
    for (size_t i = 0; i < pan.lines_below.size(); ++i)
        text.draw(img, f.x0, f.y1 + 74 + 22 * int(i), pan.lines_below[i].first, 15,
                  pan.lines_below[i].second);
}

void draw_color_bar(OIIO::ImageBuf& img, const ColorBar& cb, int bx, int top, int height,
                    Text& text) {
    const int bw = 22;
    OIIO::ImageBuf ramp(OIIO::ImageSpec(1, height, 1, OIIO::TypeDesc::FLOAT));
    for (int y = 0; y < height; ++y) {
        const float tv = 1.0f - float(y) / float(std::max(1, height - 1));
        ramp.setpixel(0, y, &tv);
    }
    const OIIO::ImageBuf colored = IBA::color_map(ramp, 0, cb.map);
    for (int y = 0; y < height; ++y) {
        float c[3];
        colored.getpixel(0, y, c, 3);
        IBA::render_line(img, bx, top + y, bx + bw, top + y, Rgb{c[0], c[1], c[2]});
    }
    IBA::render_box(img, bx, top, bx + bw, top + height - 1, kAxis);
    for (int d = int(std::ceil(cb.lo)); d <= int(std::floor(cb.hi)); ++d) {
        const int y = top + int(std::lround((cb.hi - d) / (cb.hi - cb.lo) * (height - 1)));
        IBA::render_line(img, bx + bw, y, bx + bw + 5, y, kAxis);
        text.draw(img, bx + bw + 9, y, cb.label ? cb.label(d) : fmt("%.0f", d), 15, kDimText,
                  AX::Left, AY::Center);
    }
}

int legend_width(const std::vector<LegendEntry>& legend) {
    int w = 0;
    for (const LegendEntry& e : legend)
        w += 60 + 8 * int(e.label.size());
    return w;
}

// The legend, the caption and the axis label under the panels, from row `y` on.
void draw_footer(OIIO::ImageBuf& img, const Figure& fig, int y, int panelsWidth, Text& text) {
    if (!fig.x_label.empty()) {
        text.draw(img, fig.left + panelsWidth / 2, y, fig.x_label, 15, kText, AX::Center);
        y += 18;
    }
    if (!fig.legend.empty()) {
        int lx = fig.left;
        const int ly = y + 8;
        for (const LegendEntry& e : fig.legend) {
            if (e.style.points)
                dot(img, lx + 17, ly, std::max(e.style.width, 2), e.style.color, img.roi());
            else
                thick_line(img, lx, ly, lx + 34, ly, e.style.color, e.style.width,
                           OIIO::ROI::All());
            text.draw(img, lx + 42, ly, e.label, 14, kText, AX::Left, AY::Center);
            lx += 60 + 8 * int(e.label.size());
        }
        y += 30;
    }
    for (size_t i = 0; i < fig.caption.size(); ++i)
        text.draw(img, 20, y + 8 + 22 * int(i), fig.caption[i], 13, kDimText);
}

} // namespace

double nice_step(double range, int target) {
    const double raw = range / target;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

void fit_linear(Axis& a, const std::vector<double>& values) {
    double vmax = 0;
    for (double v : values)
        if (std::isfinite(v)) vmax = std::max(vmax, v);
    a.log = false;
    a.lo = 0;
    a.hi = vmax > 0 ? vmax * 1.08 : 1;
}

void fit_log(Axis& a, const std::vector<double>& values, double decades, double margin) {
    double vmax = 0;
    for (double v : values)
        if (std::isfinite(v)) vmax = std::max(vmax, v);
    a.log = true;
    a.hi = vmax > 0 ? std::ceil(std::log10(vmax) + margin) : 0;
    a.lo = a.hi - decades;
}

OIIO::ImageBuf render(const Figure& fig, Text& text) {
    const int cellW = fig.pad_left + fig.panel_width + fig.pad_right;
    const int cellH = fig.pad_top + fig.panel_height + fig.pad_bottom;
    const int rows = (int(fig.panels.size()) + fig.cols - 1) / std::max(1, fig.cols);
    const int panelsWidth = fig.cols * cellW + (fig.color_bar ? 90 : 0);
    const int W = std::max(fig.left + panelsWidth + 20, fig.left + legend_width(fig.legend) + 20);
    const int footer = 8 + (fig.x_label.empty() ? 0 : 18) + (fig.legend.empty() ? 0 : 30) +
                       22 * int(fig.caption.size()) + 14;
    const int H = fig.top + rows * cellH + footer;
    OIIO::ImageBuf img(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    IBA::fill(img, kBackground);
    text.draw(img, 20, 34, fig.title, fig.title_size, kText);
    if (!fig.subtitle.empty()) text.draw(img, 20, 62, fig.subtitle, 15, kDimText);
    for (int c = 0; c < fig.cols && c < int(fig.col_heads.size()); ++c)
        text.draw(img, fig.left + c * cellW + fig.pad_left + fig.panel_width / 2, fig.top - 18,
                  fig.col_heads[size_t(c)], 17, kText, AX::Center);
    for (int r = 0; r < rows && r < int(fig.row_heads.size()); ++r)
        text.draw(img, 14, fig.top + r * cellH + fig.pad_top + fig.panel_height / 2,
                  fig.row_heads[size_t(r)], 16, kText, AX::Left, AY::Center);
    for (size_t i = 0; i < fig.panels.size(); ++i) {
        const int r = int(i) / fig.cols, c = int(i) % fig.cols;
        const int x0 = fig.left + c * cellW + fig.pad_left, y0 = fig.top + r * cellH + fig.pad_top;
        draw_panel(img, Frame{fig.panels[i], x0, y0, x0 + fig.panel_width, y0 + fig.panel_height},
                   text);
    }
    if (fig.color_bar)
        draw_color_bar(img, *fig.color_bar, fig.left + fig.cols * cellW + 4, fig.top + fig.pad_top,
                       fig.panel_height, text);
    draw_footer(img, fig, fig.top + rows * cellH + 8, fig.cols * cellW, text);
    return img;
}

void write_png(const OIIO::ImageBuf& img, const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path dst(path);
    const fs::path tmp =
        dst.parent_path() / ("." + dst.filename().string() + ".tmp" + std::to_string(getpid()));
    if (!img.write(tmp.string(), OIIO::TypeDesc::UINT8, "png")) {
        const std::string err = img.geterror();
        std::error_code ec;
        fs::remove(tmp, ec);
        throw InputError(path + ": cannot write (" + err + ")");
    }
    std::error_code ec;
    fs::rename(tmp, dst, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw InputError(path + ": cannot write (" + ec.message() + ")");
    }
}

} // namespace retroprism::plot
