#include "batch.h"

#include <functional>
#include <optional>

#include "parallel.h"

namespace retroprism::python {

namespace {

// Rows per thread at least: a row costs 0.1-3 us, a thread ~20 us to start.
constexpr std::size_t kGrain = 1024;

template <class Real>
const PrismaticRetroreflector<Real>& node_of(const Node& n) {
    if constexpr (sizeof(Real) == sizeof(float))
        return n.f32;
    else
        return n.f64;
}

template <class Real>
typename PrismaticRetroreflector<Real>::vec3 row(const Batch& b, std::size_t i) {
    const Real* p = static_cast<const Real*>(b.data()) + 3 * i;
    return typename PrismaticRetroreflector<Real>::vec3(p[0], p[1], p[2]);
}

template <class Real, class V>
void store(Real* out, std::size_t i, const V& v) {
    out[3 * i] = v.x;
    out[3 * i + 1] = v.y;
    out[3 * i + 2] = v.z;
}

// body(begin, end) over the rows, spread over every core with the GIL released.
void run_rows(std::size_t n, std::size_t grain,
              const std::function<void(std::size_t, std::size_t)>& body) {
    pyb::gil_scoped_release release;
    parallel_ranges(n, 0, grain, body);
}

// (N, 3) arrays named by `names`, and their data.
template <class Real>
pyb::dict rows3(std::size_t n, std::initializer_list<const char*> names, Real** data) {
    pyb::dict d;
    for (const char* name : names) {
        pyb::array_t<Real> a = new_array<Real>({n, 3});
        *data++ = a.mutable_data();
        d[name] = a;
    }
    return d;
}

template <class Real>
pyb::dict eval_rows(const Node& n, const Batch& wi, const Batch& wo, bool withPdf) {
    const PrismaticRetroreflector<Real>& node = node_of<Real>(n);
    Real* out[4];
    pyb::dict d = rows3<Real>(wi.n, {"f", "surface", "retro", "diffuse"}, out);
    Real* pdfData = nullptr;
    if (withPdf) {
        pyb::array_t<Real> pdf = new_array<Real>({wi.n});
        pdfData = pdf.mutable_data();
        d["pdf"] = pdf;
    }
    run_rows(wi.n, kGrain, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            typename PrismaticRetroreflector<Real>::Lobes f;
            if (withPdf) {
                const auto e = node.eval(row<Real>(wi, i), row<Real>(wo, i));
                f = e.f;
                pdfData[i] = e.pdf;
            } else {
                f = node.f(row<Real>(wi, i), row<Real>(wo, i));
            }
            store(out[0], i, f.total());
            store(out[1], i, f.surface);
            store(out[2], i, f.retro);
            store(out[3], i, f.diffuse);
        }
    });
    return d;
}

template <class Real>
pyb::dict sample_rows(const Node& n, const Batch& wi, const Batch& u) {
    const PrismaticRetroreflector<Real>& node = node_of<Real>(n);
    Real* out[5];
    pyb::dict d = rows3<Real>(wi.n, {"wo", "f", "surface", "retro", "diffuse"}, out);
    pyb::array_t<Real> pdf = new_array<Real>({wi.n});
    pyb::array_t<int> lobe = new_array<int>({wi.n});
    pyb::array_t<bool> valid = new_array<bool>({wi.n});
    Real* pdfData = pdf.mutable_data();
    int* lobeData = lobe.mutable_data();
    bool* validData = valid.mutable_data();
    run_rows(wi.n, kGrain, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            using Sample = typename PrismaticRetroreflector<Real>::Sample;
            const std::optional<Sample> s = node.sample(row<Real>(wi, i), row<Real>(u, i));
            const Sample v = s ? *s : Sample();
            store(out[0], i, v.wo);
            store(out[1], i, v.f.total());
            store(out[2], i, v.f.surface);
            store(out[3], i, v.f.retro);
            store(out[4], i, v.f.diffuse);
            pdfData[i] = v.pdf;
            lobeData[i] = v.lobe;
            validData[i] = bool(s);
        }
    });
    d["pdf"] = pdf;
    d["lobe"] = lobe;
    d["valid"] = valid;
    return d;
}

template <class Real>
pyb::dict albedo_rows(const Node& n, const Batch& wi, int grid) {
    const PrismaticRetroreflector<Real>& node = node_of<Real>(n);
    Real* out[4];
    pyb::dict d = rows3<Real>(wi.n, {"surface", "retro", "diffuse", "total"}, out);
    // A row is a grid x grid quadrature: one row per hand-out.
    run_rows(wi.n, 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const auto a = node.albedo(row<Real>(wi, i), grid);
            store(out[0], i, a.surface);
            store(out[1], i, a.retro);
            store(out[2], i, a.diffuse);
            store(out[3], i, a.total());
        }
    });
    return d;
}

template <class Real>
pyb::array retro_fraction_rows(const Node& n, const Batch& wi) {
    const PrismaticRetroreflector<Real>& node = node_of<Real>(n);
    pyb::array_t<Real> e = new_array<Real>({wi.n});
    Real* data = e.mutable_data();
    run_rows(wi.n, kGrain, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            data[i] = node.retro_fraction(row<Real>(wi, i));
    });
    return e;
}

} // namespace

pyb::dict eval_batch(const Node& node, const Batch& wi, const Batch& wo, bool withPdf) {
    return wi.precision == Precision::Float ? eval_rows<float>(node, wi, wo, withPdf)
                                            : eval_rows<double>(node, wi, wo, withPdf);
}

pyb::dict sample_batch(const Node& node, const Batch& wi, const Batch& u) {
    return wi.precision == Precision::Float ? sample_rows<float>(node, wi, u)
                                            : sample_rows<double>(node, wi, u);
}

pyb::dict albedo_batch(const Node& node, const Batch& wi, int grid) {
    return wi.precision == Precision::Float ? albedo_rows<float>(node, wi, grid)
                                            : albedo_rows<double>(node, wi, grid);
}

pyb::array retro_fraction_batch(const Node& node, const Batch& wi) {
    return wi.precision == Precision::Float ? retro_fraction_rows<float>(node, wi)
                                            : retro_fraction_rows<double>(node, wi);
}

} // namespace retroprism::python
