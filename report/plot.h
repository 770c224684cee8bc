// plot.h: the project's dark palette and the drawing primitives under the plot renderer
// (figure.h), on OpenImageIO ImageBufAlgo: text that degrades to nothing without a font, thick
// and dashed lines, dots.
#pragma once

#include <array>
#include <string>
#include <utility>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

namespace retroprism::plot {

using Rgb = std::array<float, 3>;
inline const Rgb kBackground = {0.055f, 0.06f, 0.075f};
inline const Rgb kPlotBackground = {0.09f, 0.095f, 0.115f};
inline const Rgb kGrid = {0.22f, 0.23f, 0.27f};
inline const Rgb kAxis = {0.6f, 0.62f, 0.66f};
inline const Rgb kText = {0.88f, 0.89f, 0.92f};
inline const Rgb kDimText = {0.62f, 0.64f, 0.68f};
// surface, retro, diffuse, total
inline const Rgb kLobeColor[4] = {
    {0.30f, 0.72f, 1.0f}, {1.0f, 0.45f, 0.18f}, {0.40f, 0.88f, 0.35f}, {1.0f, 1.0f, 1.0f}};
// Four series of one kind (the accuracy study's analytic variants): orange, blue, yellow, violet.
inline const Rgb kSeriesColor[4] = {
    {1.0f, 0.45f, 0.18f}, {0.30f, 0.72f, 1.0f}, {0.95f, 0.85f, 0.25f}, {0.85f, 0.4f, 0.95f}};
inline const Rgb kTeal = {0.15f, 0.65f, 0.65f};
inline const Rgb kRing = {0.45f, 0.45f, 0.5f}; // reference circles drawn over data
inline const char* const kFont = "DejaVuSans";

// Text drawing that degrades to nothing (with one note on stderr, naming `who`) when no font
// can be found.
struct Text {
    explicit Text(std::string who = "retroprism") : who_(std::move(who)) {}
    bool ok = true;
    void draw(OIIO::ImageBuf& img, int x, int y, const std::string& s, int size, const Rgb& color,
              OIIO::ImageBufAlgo::TextAlignX ax = OIIO::ImageBufAlgo::TextAlignX::Left,
              OIIO::ImageBufAlgo::TextAlignY ay = OIIO::ImageBufAlgo::TextAlignY::Baseline);

  private:
    std::string who_;
};

// printf-style formatting of one number.
std::string fmt(const char* f, double v);

// A line of the given thickness (1 or more pixels), clipped to `clip`.
void thick_line(OIIO::ImageBuf& img, int x1, int y1, int x2, int y2, const Rgb& c, int width,
                OIIO::ROI clip);

// A vertical dashed line from y0 to y1 (4 pixels on, 4 off).
void dashed_vline(OIIO::ImageBuf& img, int x, int y0, int y1, const Rgb& c);

// A filled square of side 2 r + 1 centred at (x, y), clipped to `clip`.
void dot(OIIO::ImageBuf& img, int x, int y, int r, const Rgb& c, OIIO::ROI clip);

} // namespace retroprism::plot
