// wave_fft.cpp: the far field of a cube corner's exit pupil by FFT of the sampled pupil (FFTW3),
// independent of the closed-form polygon transform (see wave_optics.h).
#include <algorithm>
#include <cmath>
#include <mutex>

#include <fftw3.h>

#include "error.h"
#include "wave_optics.h"

namespace retroprism {
namespace sim {
namespace wave {

namespace {

constexpr double kPi = 3.14159265358979323846;

double sinc(double x) {
    return std::abs(x) < 1e-4 ? 1.0 - x * x / 6.0 : std::sin(x) / x;
}

bool inside_convex(const Polygon& p, const dvec2& x) {
    for (size_t j = 0; j < p.size(); ++j) {
        const dvec2 e = p[(j + 1) % p.size()] - p[j], r = x - p[j];
        if (e.x * r.y - e.y * r.x < 0) return false;
    }
    return true;
}

// The area of the convex polygon p inside the square [x, x + h] x [y, y + h].
double cell_coverage(const Polygon& p, double x, double y, double h) {
    if (inside_convex(p, {x, y}) && inside_convex(p, {x + h, y}) && inside_convex(p, {x, y + h}) &&
        inside_convex(p, {x + h, y + h}))
        return h * h;
    Polygon q = p;
    for (int side = 0; side < 4 && q.size() >= 3; ++side) {
        std::vector<double> f;
        for (const dvec2& v : q) {
            const double d[4] = {v.x - x, x + h - v.x, v.y - y, y + h - v.y};
            f.push_back(d[side]);
        }
        q = clip_polygon(q, f);
    }
    return q.size() >= 3 ? std::max(0.0, polygon_area(q)) : 0.0;
}

// A cell's share of one order's polygon.
struct Covered {
    size_t index; // row * size + column
    double area;
    dvec2 centre;
};

struct FftwBuffer {
    explicit FftwBuffer(size_t n)
        : data(static_cast<fftw_complex*>(fftw_malloc(sizeof(fftw_complex) * n))) {}
    ~FftwBuffer() { fftw_free(data); }
    FftwBuffer(const FftwBuffer&) = delete;
    FftwBuffer& operator=(const FftwBuffer&) = delete;
    fftw_complex* data;
};

std::vector<Covered> covered_cells(const Polygon& p, const dvec2& x0, double h, int size) {
    dvec2 lo(1e300), hi(-1e300);
    for (const dvec2& v : p) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    const int i0 = std::max(0, int(std::floor((lo.x - x0.x) / h)));
    const int i1 = std::min(size - 1, int(std::floor((hi.x - x0.x) / h)));
    const int j0 = std::max(0, int(std::floor((lo.y - x0.y) / h)));
    const int j1 = std::min(size - 1, int(std::floor((hi.y - x0.y) / h)));
    std::vector<Covered> cells;
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
            const double x = x0.x + i * h, y = x0.y + j * h;
            const double a = cell_coverage(p, x, y, h);
            if (a > 0)
                cells.push_back(
                    {size_t(j) * size_t(size) + size_t(i), a, dvec2(x + 0.5 * h, y + 0.5 * h)});
        }
    return cells;
}

} // namespace

FftFarField fft_far_field(const Pupil& pupil, int cellsAcross, int pad) {
    if (!(cellsAcross >= 8 && cellsAcross <= 4096))
        throw InputError("cellsAcross " + std::to_string(cellsAcross) +
                         ": expected a whole number in [8, 4096]");
    if (!(pad >= 2 && pad <= 64))
        throw InputError("pad " + std::to_string(pad) + ": expected a whole number in [2, 64]");
    FftFarField r;
    r.k0 = 2.0 * kPi / pupil.lambda_um;
    dvec2 lo(1e300), hi(-1e300);
    double areaSum = 0;
    for (const Order& o : pupil.orders) {
        for (const dvec2& v : o.exit) {
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
        const double a = polygon_area(o.exit);
        r.g_ref += a * o.g;
        areaSum += a;
    }
    r.size = 1;
    while (r.size < pad * cellsAcross)
        r.size *= 2;
    r.intensity.assign(size_t(r.size) * size_t(r.size), 0.0);
    if (areaSum <= 0) return r;
    r.g_ref /= areaSum;
    r.h = std::max(hi.x - lo.x, hi.y - lo.y) / cellsAcross;
    r.dq = 2.0 * kPi / (r.size * r.h);
    const double gz = std::sqrt(std::max(0.0, 1.0 - glm::dot(r.g_ref, r.g_ref)));
    r.ra_scale = pupil.wi.z * gz / (pupil.lambda_um * pupil.lambda_um * pupil.cell_area);
    std::vector<std::vector<Covered>> cells;
    for (const Order& o : pupil.orders)
        cells.push_back(covered_cells(o.exit, lo, r.h, r.size));

    const size_t n = size_t(r.size) * size_t(r.size);
    FftwBuffer buf(n);
    // FFTW's planner is not thread-safe (its manual, "Thread safety"); execution is.
    static std::mutex planner;
    fftw_plan plan;
    {
        const std::lock_guard<std::mutex> lock(planner);
        plan = fftw_plan_dft_2d(r.size, r.size, buf.data, buf.data, FFTW_FORWARD, FFTW_ESTIMATE);
    }
    for (int in = 0; in < 2; ++in)
        for (int c = 0; c < 3; ++c) {
            std::fill(buf.data[0], buf.data[0] + 2 * n, 0.0);
            for (size_t j = 0; j < pupil.orders.size(); ++j) {
                const Order& o = pupil.orders[j];
                const cplx amp =
                    o.field[size_t(in)][size_t(c)] * cplx(std::cos(o.phase), std::sin(o.phase));
                const dvec2 carrier = r.k0 * (o.g - r.g_ref);
                for (const Covered& cell : cells[j]) {
                    const double ph = glm::dot(carrier, cell.centre);
                    const cplx v = amp * cell.area * cplx(std::cos(ph), std::sin(ph));
                    buf.data[cell.index][0] += v.real();
                    buf.data[cell.index][1] += v.imag();
                }
            }
            fftw_execute(plan);
            // Frequency index m <-> q = (m < size/2 ? m : m - size) dq; divided by the cell's
            // transform (the box of side h) the DFT of the exact coverage is the pupil's.
            for (int row = 0; row < r.size; ++row)
                for (int col = 0; col < r.size; ++col) {
                    const int i = col < r.size / 2 ? col : col - r.size;
                    const int jj = row < r.size / 2 ? row : row - r.size;
                    const double box = sinc(0.5 * i * r.dq * r.h) * sinc(0.5 * jj * r.dq * r.h);
                    const fftw_complex& v = buf.data[size_t(row) * size_t(r.size) + size_t(col)];
                    const double norm2 = (v[0] * v[0] + v[1] * v[1]) / (box * box);
                    r.intensity[size_t(jj + r.size / 2) * size_t(r.size) +
                                size_t(i + r.size / 2)] += 0.5 * norm2;
                }
        }
    const std::lock_guard<std::mutex> lock(planner);
    fftw_destroy_plan(plan);
    return r;
}

} // namespace wave
} // namespace sim
} // namespace retroprism
