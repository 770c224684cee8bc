// [batch]: the node over batches (nodes/batch.h) answers as the float node does, query by query,
// at every instruction-set level this machine runs (each forced in turn), for eval, pdf and
// sample; sample and pdf agree; threads change nothing; a call allocates nothing after the
// first; and the cpp-batch backend passes `retroprism check`'s tolerance contract.
//
// Tolerance: the batch kernels run the float core's own functions on the same float inputs, so
// they differ from the scalar node only by how the compiler schedules the same operations (and,
// where a loop is vectorised, by libmvec's exp/log/sin/cos/erfc, within 4 ulp of the scalar
// ones). Each value x is compared with the node's r as |x - r| <= kRel * max(|r|, 1e-6 peak), the
// contract's per-sample bound (backends/check.h: 1e-4, ten times float arithmetic's 1e-5) with
// its floor at a millionth of the lobe's peak over the material's queries.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "batch.h"
#include "check.h"
#include "test_support.h"

// Every allocation of the test binary, counted (the allocation test reads it around its calls).
// The replacements pair malloc with free; GCC at -O1 (scripts/tsan.sh) sees operator new
// inlined into a caller and calls the free of its pointer a mismatch, which it is not here.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<long> gAllocations{0};
} // namespace

void* operator new(std::size_t n) {
    ++gAllocations;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
// Every other form, so that each allocation and its release go through the same pair (Catch2
// allocates with the nothrow form; a sanitizer's own nothrow new would meet this free).
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    ++gAllocations;
    return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n) {
    return operator new(n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
    return operator new(n, std::nothrow);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}

namespace {

using retroprism::BatchEvaluator;
using retroprism::BatchOptions;
using retroprism::Params;
using retroprism::PrismaticRetroreflector;
using retroprism::SimdLevel;
using vec3 = glm::vec3;

constexpr double kRel = 1e-4;

// Queries in structure-of-arrays form, and room for every answer.
struct Queries {
    std::size_t n = 0;
    std::vector<float> wi[3], wo[3]; // wo: u for sample
    std::vector<float> out[10];      // 9 lobe channels and the pdf
    std::vector<float> dir[3];
    std::vector<int> lobe;

    retroprism::BatchDirections in(const std::vector<float>* a) const {
        return {a[0].data(), a[1].data(), a[2].data()};
    }
    retroprism::BatchLobes lobes() {
        return {{out[0].data(), out[1].data(), out[2].data()},
                {out[3].data(), out[4].data(), out[5].data()},
                {out[6].data(), out[7].data(), out[8].data()}};
    }
    void push(const vec3& a, const vec3& b) {
        for (int c = 0; c < 3; ++c) {
            wi[c].push_back(a[c]);
            wo[c].push_back(b[c]);
        }
        ++n;
        for (auto& v : out)
            v.assign(n, -1.0f);
        for (auto& v : dir)
            v.assign(n, -1.0f);
        lobe.assign(n, -2);
    }
    vec3 at(const std::vector<float>* a, std::size_t i) const {
        return vec3(a[0][i], a[1][i], a[2][i]);
    }
};

// Pairs in the node's parameter frame: incident directions over the hemisphere, outgoing ones
// at the retro and mirror peaks and their neighbours, anywhere, below the horizon; plus
// non-unit, zero and non-finite directions, which give zeros. Fixed seed.
Queries eval_queries(const PrismaticRetroreflector<float>& node, std::uint64_t seed) {
    Queries q;
    rptest::Rng rng(seed);
    auto world = [&](const glm::dvec3& local) { return node.to_world(vec3(local)); };
    for (int i = 0; i < 600; ++i) {
        const glm::dvec3 wi = rptest::dir_deg(89.5 * rng.uniform(), 360 * rng.uniform());
        const glm::dvec3 jitter(0.05 * (rng.uniform() - 0.5), 0.05 * (rng.uniform() - 0.5), 0);
        glm::dvec3 wo;
        switch (i % 4) {
        case 0:
            wo = glm::normalize(wi + jitter);
            break;
        case 1:
            wo = glm::normalize(glm::dvec3(-wi.x, -wi.y, wi.z) + jitter);
            break;
        case 2:
            wo = rptest::dir_deg(90 * rng.uniform(), 360 * rng.uniform());
            break;
        default:
            wo = rptest::dir_deg(90.5 + 60 * rng.uniform(), 360 * rng.uniform());
        }
        q.push(world(wi), world(wo));
    }
    const float inf = INFINITY, nan = NAN;
    const vec3 up = world(glm::dvec3(0.3, 0.1, 0.9)) * 3.0f; // not unit: normalised
    q.push(up, world(glm::dvec3(-0.2, 0.4, 0.8)));
    q.push(vec3(0), up);
    q.push(up, vec3(nan, 0, 1));
    q.push(vec3(0, inf, 1), up);
    return q;
}

std::vector<Params> materials() {
    std::vector<Params> out;
    for (const rptest::Corner& c : rptest::parameter_corners())
        out.push_back(c.params);
    Params tilted; // a tilted frame
    tilted.normal = {0.2, -0.1, 1.0};
    tilted.tangent = {1.0, 0.3, 0.0};
    out.push_back(tilted);
    Params fast = tilted;
    fast.fidelity = 1;
    out.push_back(fast);
    Params tirFast = fast;
    tirFast.prism_reflection = 1;
    out.push_back(tirFast);
    return out;
}

std::vector<SimdLevel> levels() {
    std::vector<SimdLevel> out;
    for (int l = 0; l <= int(retroprism::simd_level_supported()); ++l)
        out.push_back(SimdLevel(l));
    return out;
}

// The largest error, as defined above, of batch values against the node's over the queries;
// `ref(i, c)` is the node's channel c (0-8 lobes, 9 pdf) of query i.
template <class Ref>
double worst_error(const Queries& q, Ref&& ref, int channels) {
    double worst = 0;
    for (int c = 0; c < channels; ++c) {
        double peak = 0;
        for (std::size_t i = 0; i < q.n; ++i)
            peak = std::max(peak, std::abs(double(ref(i, c))));
        for (std::size_t i = 0; i < q.n; ++i) {
            const double r = ref(i, c), x = q.out[c][i];
            REQUIRE(std::isfinite(x));
            REQUIRE(x >= 0);
            const double scale = std::max(std::abs(r), 1e-6 * peak);
            const double err = scale > 0 ? std::abs(x - r) / scale : std::abs(x - r);
            worst = std::max(worst, err);
        }
    }
    return worst;
}

float channel(const PrismaticRetroreflector<float>::Lobes& f, int c) {
    const vec3& v = c < 3 ? f.surface : c < 6 ? f.retro : f.diffuse;
    return v[c % 3];
}

} // namespace

TEST_CASE("batch: eval and pdf equal the float node's at every instruction-set level", "[batch]") {
    const std::vector<Params> all = materials();
    for (std::size_t m = 0; m < all.size(); ++m) {
        const BatchEvaluator batch(all[m]);
        const PrismaticRetroreflector<float>& node = batch.node();
        Queries q = eval_queries(node, 1000 + m);
        std::vector<PrismaticRetroreflector<float>::Eval> ref;
        for (std::size_t i = 0; i < q.n; ++i)
            ref.push_back(node.eval(q.at(q.wi, i), q.at(q.wo, i)));
        for (SimdLevel level : levels()) {
            INFO("material " << m << ", level " << retroprism::simd_level_name(level));
            BatchOptions opt;
            opt.level = level;
            batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), q.out[9].data(), opt);
            const double errEval = worst_error(
                q,
                [&](std::size_t i, int c) {
                    return c < 9 ? double(channel(ref[i].f, c)) : double(ref[i].pdf);
                },
                10);
            CHECK(errEval <= kRel);
            // f alone (no pdf requested) and the pdf alone.
            batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), nullptr, opt);
            batch.pdf(q.n, q.in(q.wi), q.in(q.wo), q.out[9].data(), opt);
            const double errF = worst_error(
                q,
                [&](std::size_t i, int c) {
                    return c < 9 ? double(channel(ref[i].f, c)) : double(ref[i].pdf);
                },
                10);
            CHECK(errF <= kRel);
            // Zero, non-finite and below-the-horizon queries answer zero.
            for (std::size_t i = q.n - 3; i < q.n; ++i)
                for (int c = 0; c < 10; ++c)
                    CHECK(q.out[c][i] == 0.0f);
        }
    }
}

TEST_CASE("batch: sample equals the float node's and agrees with pdf", "[batch]") {
    const std::vector<Params> all = materials();
    for (std::size_t m = 0; m < all.size(); ++m) {
        const BatchEvaluator batch(all[m]);
        const PrismaticRetroreflector<float>& node = batch.node();
        Queries q = eval_queries(node, 2000 + m);
        rptest::Rng rng(3000 + m);
        for (std::size_t i = 0; i < q.n; ++i)
            for (int c = 0; c < 3; ++c)
                q.wo[c][i] = float(rng.uniform()); // u
        for (SimdLevel level : levels()) {
            INFO("material " << m << ", level " << retroprism::simd_level_name(level));
            BatchOptions opt;
            opt.level = level;
            retroprism::BatchSamples out{q.dir[0].data(), q.dir[1].data(), q.dir[2].data(),
                                         q.lobes(),       q.out[9].data(), q.lobe.data()};
            batch.sample(q.n, q.in(q.wi), q.in(q.wo), out, opt);
            long sampled = 0;
            for (std::size_t i = 0; i < q.n; ++i) {
                const auto s = node.sample(q.at(q.wi, i), q.at(q.wo, i));
                REQUIRE((q.lobe[i] >= 0) == s.has_value());
                if (!s) {
                    CHECK(q.out[9][i] == 0.0f);
                    continue;
                }
                ++sampled;
                CHECK(q.lobe[i] == s->lobe);
                const vec3 wo = q.at(q.dir, i);
                // The same direction: the same code on the same numbers, to float rounding.
                CHECK(glm::length(wo - s->wo) <= 1e-6f);
                CHECK(std::abs(q.out[9][i] - s->pdf) <= kRel * s->pdf);
            }
            CHECK(sampled > long(q.n) / 2);
            // The batch pdf at the sampled directions is the sample's pdf (the node's own
            // consistency, [consistency]), through a batch eval.
            std::vector<float> pdfAt(q.n);
            batch.pdf(q.n, q.in(q.wi), q.in(q.dir), pdfAt.data(), opt);
            for (std::size_t i = 0; i < q.n; ++i)
                if (q.lobe[i] >= 0) {
                    const vec3 wo = q.at(q.dir, i);
                    CHECK(std::abs(pdfAt[i] - node.pdf(q.at(q.wi, i), wo)) <=
                          kRel * node.pdf(q.at(q.wi, i), wo));
                }
        }
    }
}

TEST_CASE("batch: threads change nothing", "[batch][threads]") {
    Params p;
    p.fidelity = 1;
    const BatchEvaluator batch(p);
    Queries q;
    rptest::Rng rng(77);
    for (int i = 0; i < 20000; ++i)
        q.push(vec3(rptest::dir_deg(89 * rng.uniform(), 360 * rng.uniform())),
               vec3(rptest::dir_deg(89 * rng.uniform(), 360 * rng.uniform())));
    batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), q.out[9].data());
    const std::vector<float> one = q.out[4], onePdf = q.out[9];
    BatchOptions opt;
    opt.threads = 4;
    opt.grain = 1000;
    batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), q.out[9].data(), opt);
    CHECK(q.out[4] == one);
    CHECK(q.out[9] == onePdf);
}

TEST_CASE("batch: no allocation per call after the first", "[batch]") {
    const BatchEvaluator batch{Params()};
    Queries q = eval_queries(batch.node(), 5);
    retroprism::BatchSamples out{q.dir[0].data(), q.dir[1].data(), q.dir[2].data(),
                                 q.lobes(),       q.out[9].data(), q.lobe.data()};
    batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), q.out[9].data());
    batch.sample(q.n, q.in(q.wi), q.in(q.wo), out);
    const long before = gAllocations.load();
    for (int k = 0; k < 10; ++k) {
        batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), q.out[9].data());
        batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), nullptr);
        batch.pdf(q.n, q.in(q.wi), q.in(q.wo), q.out[9].data());
        batch.sample(q.n, q.in(q.wi), q.in(q.wo), out);
    }
    CHECK(gAllocations.load() - before == 0);
    // The counter counts: a vector's growth is seen.
    std::vector<int> v(10);
    CHECK(gAllocations.load() - before == 1);
}

TEST_CASE("batch: no allocation per call after the first on every core", "[batch][threads]") {
    // A batch spread over the cores runs on the process's pool of workers (util/parallel.h),
    // started by the first parallel call: the calls after it start no thread and allocate
    // nothing, whatever the threads asked for (more than the cores: the pool's workers take
    // the ranges in turn).
    const BatchEvaluator batch{Params()};
    Queries q;
    rptest::Rng rng(91);
    for (int i = 0; i < 8000; ++i)
        q.push(vec3(rptest::dir_deg(89 * rng.uniform(), 360 * rng.uniform())),
               vec3(rptest::dir_deg(89 * rng.uniform(), 360 * rng.uniform())));
    retroprism::BatchSamples out{q.dir[0].data(), q.dir[1].data(), q.dir[2].data(),
                                 q.lobes(),       q.out[9].data(), q.lobe.data()};
    for (int threads : {0, 2, 5}) {
        INFO("threads " << threads);
        BatchOptions opt;
        opt.threads = threads;
        opt.grain = 500;
        batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), q.out[9].data(), opt);
        const long before = gAllocations.load();
        for (int k = 0; k < 10; ++k) {
            batch.eval(q.n, q.in(q.wi), q.in(q.wo), q.lobes(), q.out[9].data(), opt);
            batch.pdf(q.n, q.in(q.wi), q.in(q.wo), q.out[9].data(), opt);
            batch.sample(q.n, q.in(q.wi), q.in(q.wo), out, opt);
        }
        CHECK(gAllocations.load() - before == 0);
    }
}

TEST_CASE("batch: the cpp-batch backend passes the tolerance contract", "[batch]") {
    const retroprism::CheckReport r = retroprism::check_backend("cpp-batch");
    INFO("max err " << r.max_err << " at " << r.worst << ", failures " << r.failures);
    CHECK(r.samples > 0);
    CHECK(r.passed);
}
