#include "plot.h"

#include <algorithm>
#include <cstdio>

namespace retroprism::plot {

void Text::draw(OIIO::ImageBuf& img, int x, int y, const std::string& s, int size, const Rgb& color,
                OIIO::ImageBufAlgo::TextAlignX ax, OIIO::ImageBufAlgo::TextAlignY ay) {
    if (!ok) return;
    if (!OIIO::ImageBufAlgo::render_text(img, x, y, s, size, kFont, color, ax, ay)) {
        ok = false;
        std::fprintf(stderr, "%s: note: no font for labels (%s); drawing plots without text\n",
                     who_.c_str(), img.geterror().c_str());
    }
}

std::string fmt(const char* f, double v) {
    char buf[512];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

void thick_line(OIIO::ImageBuf& img, int x1, int y1, int x2, int y2, const Rgb& c, int width,
                OIIO::ROI clip) {
    const int lo = -(width - 1) / 2, hi = width / 2;
    for (int dx = lo; dx <= hi; ++dx)
        for (int dy = lo; dy <= hi; ++dy)
            OIIO::ImageBufAlgo::render_line(img, x1 + dx, y1 + dy, x2 + dx, y2 + dy, c, false,
                                            clip);
}

void dashed_vline(OIIO::ImageBuf& img, int x, int y0, int y1, const Rgb& c) {
    for (int y = y0; y < y1; y += 8)
        OIIO::ImageBufAlgo::render_line(img, x, y, x, std::min(y + 4, y1), c);
}

void dot(OIIO::ImageBuf& img, int x, int y, int r, const Rgb& c, OIIO::ROI clip) {
    const OIIO::ROI box(std::max(x - r, clip.xbegin), std::min(x + r + 1, clip.xend),
                        std::max(y - r, clip.ybegin), std::min(y + r + 1, clip.yend));
    if (box.xbegin >= box.xend || box.ybegin >= box.yend) return;
    OIIO::ImageBufAlgo::fill(img, c, box);
}

} // namespace retroprism::plot
