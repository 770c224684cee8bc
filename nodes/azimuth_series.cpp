// azimuth_series.cpp: a material's azimuth averages (rp_azimuth_average: the averaged ERA of
// canted prisms, times R1 R2 R3 when uncoated, and the metallised prisms' face hits; the paper's
// cube's E for uncoated prisms in the exact tier) as piecewise Chebyshev series in
// t = tan(theta_t) (the layout rp_azimuth_series reads, prism_core.inc), so that the C++ node
// evaluates them in a few tens of operations instead of integrating over azimuth at every call.
//
// The series interpolates the integral itself at Chebyshev points of each interval. The
// intervals end where the integrand's break points appear, vanish or cross the ends of the
// integrated range (the averages are smooth between, kinked at some of them: the onset of total
// internal reflection on a face, the ERA's corners); each interval is halved until the series
// matches the integral at the points between its nodes to within tolerance.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <list>
#include <mutex>
#include <pthread.h>
#include <vector>

#include "prismatic_retroreflector.h"

namespace retroprism {

namespace {

constexpr int kTerms = f64::RP_SERIES_TERMS;
// Largest difference between a series and its integral accepted at the check points of an
// interval: 1e-8 of the largest value on the interval, or 1e-11 of the function's largest where
// that is more (near the ends of its support). Relative, because near eta = 1 uncoated prisms'
// E is below 1e-14 and the backends must still agree on it; far below the integral's own error
// (5.6e-7 absolute for uncoated prisms, the Gauss-Legendre rule's) and a float's rounding.
constexpr double kRelativeTolerance = 1e-8;
constexpr double kFloorTolerance = 1e-11;
// Intervals narrower than this fraction of the range are kept whatever their error (a kink the
// break points do not mark: the series then holds the integral's values at the kink's two
// sides' nodes).
constexpr double kMinWidth = 1e-7;
// Samples of t that locate a change of the break count before bisection.
constexpr int kScanPoints = 4096;
// Samples of t that find each function's largest value (the scale of kFloorTolerance).
constexpr int kScalePoints = 32;

using Values = std::array<double, 2>;

struct Integral {
    const AzimuthAverage& a;
    int functions;
    Values operator()(double t) const {
        const f64::vec2 v = f64::rp_azimuth_average(a.face_z, a.face_xy, a.face_phi, a.phi_end, t,
                                                    a.eta, a.tir, a.hits);
        return {v.x, v.y};
    }
    int breaks(double t) const {
        return f64::rp_azimuth_breaks(a.face_z, a.face_xy, a.face_phi, a.phi_end, t, a.eta, a.tir)
            .n;
    }
};

// t in (0, t_end) where the number of azimuth break points changes, to double precision.
std::vector<double> structure_changes(const Integral& f, double tEnd) {
    std::vector<double> out;
    double prevT = 0.0;
    int prevN = f.breaks(prevT);
    for (int i = 1; i <= kScanPoints; ++i) {
        const double t = tEnd * i / kScanPoints;
        const int n = f.breaks(t);
        if (n != prevN) {
            double lo = prevT, hi = t;
            for (int k = 0; k < 60 && hi - lo > 1e-15 * tEnd; ++k) {
                const double mid = 0.5 * (lo + hi);
                (f.breaks(mid) == prevN ? lo : hi) = mid;
            }
            const double at = 0.5 * (lo + hi);
            if (at > kMinWidth * tEnd && at < tEnd * (1.0 - kMinWidth)) out.push_back(at);
        }
        prevT = t;
        prevN = n;
    }
    return out;
}

struct Piece {
    double lo, hi;
    std::array<std::array<double, kTerms>, 2> c;
    Values largest; // of |f| at the nodes
};

// The series over [lo, hi] through their values at the kTerms Chebyshev points of the first
// kind (Trefethen, Approximation Theory and Approximation Practice, ch. 3: the discrete cosine
// transform of the values).
Piece fit(double lo, double hi, const Integral& f) {
    Piece p{lo, hi, {}, {0.0, 0.0}};
    std::array<Values, kTerms> v;
    for (int k = 0; k < kTerms; ++k) {
        const double u = std::cos(M_PI * (k + 0.5) / kTerms);
        v[size_t(k)] = f(0.5 * (lo + hi) + 0.5 * (hi - lo) * u);
        for (size_t q = 0; q < 2; ++q)
            p.largest[q] = std::max(p.largest[q], std::abs(v[size_t(k)][q]));
    }
    for (size_t q = 0; q < 2; ++q)
        for (int j = 0; j < kTerms; ++j) {
            double s = 0.0;
            for (int k = 0; k < kTerms; ++k)
                s += v[size_t(k)][q] * std::cos(M_PI * j * (k + 0.5) / kTerms);
            p.c[q][size_t(j)] = (j == 0 ? 1.0 : 2.0) * s / kTerms;
        }
    return p;
}

double series_at(const std::array<double, kTerms>& c, double u) {
    double b1 = 0.0, b2 = 0.0;
    for (int j = kTerms - 1; j >= 1; --j) {
        const double b0 = c[size_t(j)] + 2.0 * u * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    return c[0] + u * b1 - b2;
}

// The largest error at the interval's ends and the points halfway (in angle) between its nodes,
// where an interpolant's error peaks, in units of each function's tolerance.
double check_error(const Piece& p, const Integral& f, const Values& floor) {
    double worst = 0.0;
    for (int k = 0; k <= kTerms; ++k) {
        const double u = std::cos(M_PI * k / kTerms);
        const Values v = f(0.5 * (p.lo + p.hi) + 0.5 * (p.hi - p.lo) * u);
        for (size_t q = 0; q < size_t(f.functions); ++q) {
            const double err = std::abs(series_at(p.c[q], u) - v[q]);
            const double tolerance = std::max(kRelativeTolerance * p.largest[q], floor[q]);
            worst = std::max(worst, tolerance > 0.0 ? err / tolerance : err > 0.0 ? INFINITY : 0.0);
        }
    }
    return worst;
}

// Appends [lo, hi]'s series, halved until within tolerance or minWidth wide.
void refine(double lo, double hi, double minWidth, const Integral& f, const Values& floor,
            std::vector<Piece>& out) {
    Piece p = fit(lo, hi, f);
    if (check_error(p, f, floor) <= 1.0 || hi - lo <= minWidth) {
        out.push_back(p);
        return;
    }
    const double mid = 0.5 * (lo + hi);
    refine(lo, mid, minWidth, f, floor, out);
    refine(mid, hi, minWidth, f, floor, out);
}

std::vector<double> make_series(const AzimuthAverage& a) {
    const Integral f{a, a.hits ? 2 : 1};
    std::vector<double> ends = {0.0};
    for (double t : structure_changes(f, a.t_end))
        ends.push_back(t);
    ends.push_back(a.t_end);
    Values largest = {0.0, 0.0};
    for (int i = 0; i <= kScalePoints; ++i) {
        const Values v = f(a.t_end * i / kScalePoints);
        for (size_t q = 0; q < 2; ++q)
            largest[q] = std::max(largest[q], std::abs(v[q]));
    }
    const Values floor = {kFloorTolerance * largest[0], kFloorTolerance * largest[1]};
    std::vector<Piece> pieces;
    for (size_t i = 0; i + 1 < ends.size(); ++i)
        refine(ends[i], ends[i + 1], kMinWidth * a.t_end, f, floor, pieces);
    std::vector<double> s = {double(pieces.size()), double(f.functions), pieces.front().lo};
    for (const Piece& p : pieces)
        s.push_back(p.hi);
    for (const Piece& p : pieces)
        for (size_t q = 0; q < size_t(f.functions); ++q)
            s.insert(s.end(), p.c[q].begin(), p.c[q].end());
    return s;
}

// The series made last, most recent first: a series is a function of its AzimuthAverage alone,
// so nodes of one material (a renderer's instances of a sheeting, a script's nodes in a loop)
// make it once per process. Keys compare bit for bit; lookups and insertions hold the mutex, a
// series is made outside it (two threads that miss the same key both make it, the same bits,
// and the second finds the first's entry when it inserts).
struct SeriesCache {
    struct Entry {
        AzimuthAverage key;
        std::vector<double> series;
    };
    std::mutex mutex;
    std::list<Entry> entries;
    SeriesCacheStats stats;
};

// The cache, with the mutex held across fork() (pthread_atfork), so that a child forked while
// another thread looked up a series finds it unlocked.
SeriesCache& series_cache() {
    static SeriesCache* cache = [] {
        static SeriesCache c;
        pthread_atfork([] { c.mutex.lock(); }, [] { c.mutex.unlock(); }, [] { c.mutex.unlock(); });
        return &c;
    }();
    return *cache;
}

bool same_bits(double x, double y) {
    return std::memcmp(&x, &y, sizeof x) == 0;
}

bool same_average(const AzimuthAverage& x, const AzimuthAverage& y) {
    for (int k = 0; k < 3; ++k)
        if (!same_bits(x.face_z[k], y.face_z[k]) || !same_bits(x.face_xy[k], y.face_xy[k]) ||
            !same_bits(x.face_phi[k], y.face_phi[k]))
            return false;
    return same_bits(x.phi_end, y.phi_end) && same_bits(x.eta, y.eta) &&
           same_bits(x.t_end, y.t_end) && x.tir == y.tir && x.hits == y.hits;
}

// The entry of key a moved to the front, or false; the caller holds the mutex.
bool to_front(SeriesCache& cache, const AzimuthAverage& a) {
    for (auto it = cache.entries.begin(); it != cache.entries.end(); ++it) {
        if (!same_average(it->key, a)) continue;
        cache.entries.splice(cache.entries.begin(), cache.entries, it);
        return true;
    }
    return false;
}

} // namespace

std::vector<double> azimuth_series(const AzimuthAverage& a) {
    SeriesCache& cache = series_cache();
    {
        std::lock_guard<std::mutex> lock(cache.mutex);
        if (to_front(cache, a)) {
            ++cache.stats.hits;
            return cache.entries.front().series;
        }
        ++cache.stats.misses;
    }
    std::vector<double> series = make_series(a);
    std::lock_guard<std::mutex> lock(cache.mutex);
    if (!to_front(cache, a)) {
        cache.entries.push_front({a, series});
        if (cache.entries.size() > size_t(kSeriesCacheEntries)) cache.entries.pop_back();
        cache.stats.entries = int(cache.entries.size());
    }
    return series;
}

SeriesCacheStats azimuth_series_cache_stats() {
    SeriesCache& cache = series_cache();
    std::lock_guard<std::mutex> lock(cache.mutex);
    return cache.stats;
}

} // namespace retroprism
