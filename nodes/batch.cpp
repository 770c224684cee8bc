// batch.cpp: the node over batches (batch.h). Each eval kernel is one loop over the core's
// per-query functions (prism_core.inc) under `#pragma omp simd`, written once (the always-inline
// templates below) and compiled once per instruction set by the RP_BATCH_ISA functions, whose
// `flatten` inlines the whole core into the loop so that GCC vectorises it; the core's exp, log,
// sin, cos and erfc calls then go to glibc's libmvec through the `simd` declarations below (this
// file is compiled with -fopenmp-simd -fno-math-errno, see CMakeLists.txt). Sample is a plain
// loop of its own (batch_sample.h).
#include "batch.h"

#include <algorithm>
#include <cmath>

#include "batch_sample.h"
#include "parallel.h"

// glibc declares its vector variants only under -ffast-math (bits/math-vector.h), whose
// finite-math assumption would fold away the core's NaN guards; the same declarations here, for
// the functions the core calls, let the vectoriser use them with IEEE semantics kept.
extern "C" {
#define RP_VECTOR_MATH(NAME) float NAME(float) __attribute__((__simd__("notinbranch")));
RP_VECTOR_MATH(expf)
RP_VECTOR_MATH(logf)
RP_VECTOR_MATH(sinf)
RP_VECTOR_MATH(cosf)
RP_VECTOR_MATH(erfcf)
RP_VECTOR_MATH(erff)
#undef RP_VECTOR_MATH
}

namespace retroprism {

namespace {

using f32::real;
using f32::vec3;

// Queries per kernel call (its set-up, such as the material's constants, is per call).
constexpr std::size_t kBlock = 256;

// A block's results: the kernels write each array of results to the caller's array where it is
// given and to a scratch array of the block's where it is null, so that the vector loop stores
// unconditionally and nothing is copied.
constexpr int kOutputs = 13; // surface rgb, retro rgb, diffuse rgb, pdf, sampled wo xyz
struct Sink {
    float* v[kOutputs];
    int* lobe;
};
struct Scratch {
    float v[kOutputs][kBlock];
    int lobe[kBlock];
};

struct Frame {
    vec3 n, t, b;
};

struct Job {
    const f32::rp_material* m;
    Frame frame;
    BatchDirections wi, wo; // wo: u for sample
    BatchLobes f;
    float* pdf;
    BatchSamples samples;
};

// A batch's arrays in locals, read as not aliasing the block the kernels write.
struct Loader {
    const float* __restrict x;
    const float* __restrict y;
    const float* __restrict z;
    Loader(const BatchDirections& d, std::size_t b) : x(d.x + b), y(d.y + b), z(d.z + b) {}
    vec3 operator()(int i) const { return vec3(x[i], y[i], z[i]); }
};

// The material classes with a branch-free evaluation: the averaged ERA of the paper's cube
// (no cant, no dihedral errors) in the paper's (not reciprocal) form with an isotropic retro lobe,
// with ideal prisms in either fidelity tier or uncoated ones in the fast tier (its table). Their
// kernels copy the material with its mode fields set to constants, so that the core's branches on
// them fold away when it is inlined into the loop; every other material runs the core as it is
// (Mode::General).
enum class Mode { General, IdealExact, IdealFast, TirFast };

Mode mode_of(const f32::rp_material& m) {
    if (m.era_mode != f32::RP_ERA_AVERAGED || m.canted != 0 || m.dihedral != 0 ||
        m.reciprocal != 0 || m.retro_anisotropic != 0)
        return Mode::General;
    if (m.prism_reflection == f32::RP_PRISM_IDEAL)
        return m.fidelity == f32::RP_FIDELITY_FAST ? Mode::IdealFast : Mode::IdealExact;
    if (m.prism_reflection == f32::RP_PRISM_TIR && m.fidelity == f32::RP_FIDELITY_FAST)
        return Mode::TirFast;
    return Mode::General;
}

template <Mode M>
inline __attribute__((always_inline)) f32::rp_material specialised(const f32::rp_material& from) {
    f32::rp_material m = from;
    if constexpr (M != Mode::General) {
        m.era_mode = f32::RP_ERA_AVERAGED;
        m.canted = 0;
        m.dihedral = 0;
        // The dihedral lobe's widths, 0 whenever `dihedral` is (rp_prepare): constants here, so
        // that its ring and spread code (two more exp per query) folds away as well.
        m.ring_par = real(0);
        m.ring_tilt = real(0);
        m.spread2 = real(0);
        m.reciprocal = 0;
        m.retro_anisotropic = 0;
        m.prism_reflection = M == Mode::TirFast ? f32::RP_PRISM_TIR : f32::RP_PRISM_IDEAL;
        m.fidelity = M == Mode::IdealExact ? f32::RP_FIDELITY_EXACT : f32::RP_FIDELITY_FAST;
    }
    return m;
}

// The answer to one query of eval: its lobes and pdf.
struct Answer {
    f32::rp_lobes r;
    real pdf;
};

// One query of eval, as the node's. Its locals live here rather than in the loop body, where
// `omp simd` would make the addressed ones arrays per lane, which the vectoriser cannot read.
template <bool WantPdf, Mode M>
inline __attribute__((always_inline)) Answer eval_query(const f32::rp_material& m, const Frame& fr,
                                                        vec3 wiWorld, vec3 woWorld) {
    Answer a;
    vec3 wi, wo;
    a.pdf = real(0);
    // A direction the frame rejects comes back as 0, below the horizon.
    f32::rp_to_local(fr.n, fr.t, fr.b, wiWorld, wi);
    f32::rp_to_local(fr.n, fr.t, fr.b, woWorld, wo);
    if constexpr (M == Mode::General) {
        f32::rp_eval_impl(m, wi, wo, WantPdf, a.r, a.pdf);
    } else {
        // rp_eval_impl without its early return, whose condition would make every table read
        // of the vector loop a masked gather: pairs it rejects (a direction below the horizon,
        // zero weight) are evaluated at the normal and their results replaced by zeros.
        const bool above =
            (wi.z >= f32::RP_MIN_COS) & (wo.z >= f32::RP_MIN_COS) & (m.weight > real(0));
        wi = vec3(above ? wi.x : real(0), above ? wi.y : real(0), above ? wi.z : real(1));
        wo = vec3(above ? wo.x : real(0), above ? wo.y : real(0), above ? wo.z : real(1));
        f32::rp_incident s;
        if constexpr (WantPdf)
            f32::rp_incident_setup(m, wi, s);
        else
            f32::rp_incident_lobes(m, wi, s);
        f32::rp_eval_lobes_pdf(m, s, wi, wo, WantPdf, a.r, a.pdf);
        const real keep = above ? real(1) : real(0);
        a.r.surface *= keep;
        a.r.retro *= keep;
        a.r.diffuse *= keep;
        a.pdf *= keep;
    }
    return a;
}

inline __attribute__((always_inline)) void store(const Sink& out, int k, const Answer& a) {
    out.v[0][k] = a.r.surface.x;
    out.v[1][k] = a.r.surface.y;
    out.v[2][k] = a.r.surface.z;
    out.v[3][k] = a.r.retro.x;
    out.v[4][k] = a.r.retro.y;
    out.v[5][k] = a.r.retro.z;
    out.v[6][k] = a.r.diffuse.x;
    out.v[7][k] = a.r.diffuse.y;
    out.v[8][k] = a.r.diffuse.z;
    out.v[9][k] = a.pdf;
}

// Query k of a block: nothing addressable in the vector loop's body itself (see eval_query).
template <bool WantPdf, Mode M>
inline __attribute__((always_inline)) void one_query(const f32::rp_material& m, const Frame& fr,
                                                     const Loader& loadI, const Loader& loadO,
                                                     int k, const Sink& out) {
    store(out, k, eval_query<WantPdf, M>(m, fr, loadI(k), loadO(k)));
}

// Queries [b, b + count) into out: eval (with the pdf when WantPdf) in material mode M.
template <bool WantPdf, Mode M>
inline __attribute__((always_inline)) void query_block(const Job& job, std::size_t b,
                                                       std::size_t count, const Sink& out) {
    const f32::rp_material m = specialised<M>(*job.m);
    const Frame fr = job.frame;
    const Loader loadI(job.wi, b), loadO(job.wo, b);
    const int end = int(count);
#pragma omp simd
    for (int k = 0; k < end; ++k)
        one_query<WantPdf, M>(m, fr, loadI, loadO, k, out);
}

enum class Kind { Eval, EvalPdf, Sample };

template <Kind K, Mode M>
inline __attribute__((always_inline)) void run_block(const Job& job, std::size_t b,
                                                     std::size_t count, const Sink& out) {
    query_block<K == Kind::EvalPdf, M>(job, b, count, out);
}

// The eval kernels of one instruction set, by kind (eval, eval + pdf) and material mode.
using BlockFn = void (*)(const Job&, std::size_t, std::size_t, const Sink&);
struct Kernels {
    BlockFn eval[2][4];
};

// Sample over one block, with every array of results given (Sink): one kernel for every
// instruction set (batch_sample.h).
void sample_kernel(const Job& job, std::size_t b, std::size_t count, const Sink& out) {
    const float* const wi[3] = {job.wi.x + b, job.wi.y + b, job.wi.z + b};
    const float* const u[3] = {job.wo.x + b, job.wo.y + b, job.wo.z + b};
    batch_detail::sample_block(*job.m, job.frame.n, job.frame.t, job.frame.b, wi, u, out.v,
                               out.lobe, count);
}

#define RP_BATCH_MODES(NAME, K)                                                                    \
    {                                                                                              \
        NAME<K, Mode::General>, NAME<K, Mode::IdealExact>, NAME<K, Mode::IdealFast>,               \
            NAME<K, Mode::TirFast>                                                                 \
    }
// The sanitizer builds (-DRP_NO_FORCED_INLINE, scripts/sanitize.sh) keep the core's calls as
// calls instead of inlining all of it into each of the 32 kernels: instrumented and flattened,
// this file alone took 6.5 min to compile. Their kernels are the same loops over the same
// queries, not vectorised.
#ifdef RP_NO_FORCED_INLINE
#define RP_BATCH_FLATTEN
#else
#define RP_BATCH_FLATTEN flatten,
#endif
#define RP_BATCH_ISA(NAME, ...)                                                                    \
    template <Kind K, Mode M>                                                                      \
    __VA_ARGS__ __attribute__((RP_BATCH_FLATTEN noinline)) void NAME(                              \
        const Job& job, std::size_t b, std::size_t count, const Sink& out) {                       \
        run_block<K, M>(job, b, count, out);                                                       \
    }                                                                                              \
    const Kernels NAME##_kernels = {                                                               \
        {RP_BATCH_MODES(NAME, Kind::Eval), RP_BATCH_MODES(NAME, Kind::EvalPdf)}};

RP_BATCH_ISA(block_baseline, )
RP_BATCH_ISA(block_sse42, RP_TARGET_SSE42)
RP_BATCH_ISA(block_avx2, RP_TARGET_AVX2)
RP_BATCH_ISA(block_avx512, RP_TARGET_AVX512)
#undef RP_BATCH_ISA
#undef RP_BATCH_FLATTEN
#undef RP_BATCH_MODES

const Kernels& kernels(SimdLevel level) {
    switch (std::min(level, simd_level_supported())) {
    case SimdLevel::Avx512:
        return block_avx512_kernels;
    case SimdLevel::Avx2:
        return block_avx2_kernels;
    case SimdLevel::Sse42:
        return block_sse42_kernels;
    default:
        return block_baseline_kernels;
    }
}

// Where block b's results go (see Sink).
Sink sink_of(const Job& job, Kind kind, std::size_t b, Scratch& scratch) {
    const BatchLobes& f = kind == Kind::Sample ? job.samples.f : job.f;
    float* const given[kOutputs] = {f.surface.r,   f.surface.g,
                                    f.surface.b,   f.retro.r,
                                    f.retro.g,     f.retro.b,
                                    f.diffuse.r,   f.diffuse.g,
                                    f.diffuse.b,   kind == Kind::Sample ? job.samples.pdf : job.pdf,
                                    job.samples.x, job.samples.y,
                                    job.samples.z};
    Sink out;
    for (int c = 0; c < kOutputs; ++c)
        out.v[c] = given[c] ? given[c] + b : scratch.v[c];
    out.lobe = job.samples.lobe ? job.samples.lobe + b : scratch.lobe;
    return out;
}

// [begin, end) in blocks through one kernel.
void run_range(const Job& job, BlockFn fn, Kind kind, std::size_t begin, std::size_t end) {
    Scratch scratch;
    for (std::size_t b = begin; b < end; b += kBlock)
        fn(job, b, std::min(kBlock, end - b), sink_of(job, kind, b, scratch));
}

void run(const Job& job, Kind kind, std::size_t n, const BatchOptions& options) {
    const BlockFn fn =
        kind == Kind::Sample
            ? sample_kernel
            : kernels(options.level).eval[kind == Kind::EvalPdf ? 1 : 0][int(mode_of(*job.m))];
    if (options.threads == 1 || n <= options.grain) {
        run_range(job, fn, kind, 0, n);
        return;
    }
    // The callable captures one reference, so that std::function holds it without allocating.
    const struct {
        const Job& job;
        BlockFn fn;
        Kind kind;
    } call{job, fn, kind};
    parallel_ranges(n, options.threads, options.grain, [&call](std::size_t b, std::size_t e) {
        run_range(call.job, call.fn, call.kind, b, e);
    });
}

} // namespace

SimdLevel simd_level_supported() {
    static const SimdLevel level = [] {
        __builtin_cpu_init();
        if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
            __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq"))
            return SimdLevel::Avx512;
        if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
            __builtin_cpu_supports("bmi2"))
            return SimdLevel::Avx2;
        if (__builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("popcnt"))
            return SimdLevel::Sse42;
        return SimdLevel::Baseline;
    }();
    return level;
}

const char* simd_level_name(SimdLevel level) {
    switch (level) {
    case SimdLevel::Avx512:
        return "avx512";
    case SimdLevel::Avx2:
        return "avx2";
    case SimdLevel::Sse42:
        return "sse4.2";
    default:
        return "baseline";
    }
}

BatchEvaluator::BatchEvaluator(const Params& params) : node_(params) {
    n_ = node_.to_world(vec3(0, 0, 1));
    t_ = node_.to_world(vec3(1, 0, 0));
    b_ = node_.to_world(vec3(0, 1, 0));
}

void BatchEvaluator::eval(std::size_t n, BatchDirections wi, BatchDirections wo, BatchLobes f,
                          float* pdf, const BatchOptions& options) const {
    const Job job{&node_.core_material(), {n_, t_, b_}, wi, wo, f, pdf, {}};
    run(job, pdf ? Kind::EvalPdf : Kind::Eval, n, options);
}

void BatchEvaluator::pdf(std::size_t n, BatchDirections wi, BatchDirections wo, float* pdf,
                         const BatchOptions& options) const {
    eval(n, wi, wo, BatchLobes(), pdf, options);
}

void BatchEvaluator::sample(std::size_t n, BatchDirections wi, BatchDirections u, BatchSamples out,
                            const BatchOptions& options) const {
    const Job job{&node_.core_material(), {n_, t_, b_}, wi, u, BatchLobes(), nullptr, out};
    run(job, Kind::Sample, n, options);
}

} // namespace retroprism
