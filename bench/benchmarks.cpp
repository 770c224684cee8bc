#include "benchmarks.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>

#include "baselines.h"
#include "batch.h"
#include "batch_baseline.h"
#include "prismatic_retroreflector.h"
#include "variants.h"

namespace retroprism::bench {

namespace {

// A core namespace as a type: its functions (RP_CORE_MEMBERS) and its material preparation.
#define RP_ADAPTER(NAME, NS)                                                                       \
    struct NAME {                                                                                  \
        using real = NS::real;                                                                     \
        RP_CORE_MEMBERS(NS)                                                                        \
        static material prepare(const Params& p) {                                                 \
            return NS::rp_prepare(                                                                 \
                real(p.weight), vec3(p.diffuse_color[0], p.diffuse_color[1], p.diffuse_color[2]),  \
                vec3(p.retro_color[0], p.retro_color[1], p.retro_color[2]), real(p.specular),      \
                real(p.roughness), real(p.ior), p.prism_reflection, real(p.metal_reflectance),     \
                p.era_mode, real(p.orientation), real(p.cant_angle), real(p.dihedral_error),       \
                real(p.dihedral_spread), real(p.prism_pitch), real(p.abbe_number),                 \
                real(p.wavelength), p.retro_lobe, p.reciprocal ? 1 : 0, p.fidelity);               \
        }                                                                                          \
    };

RP_ADAPTER(Double, f64)
RP_ADAPTER(Float, f32)
RP_ADAPTER(RetroF32, variants::retro_f32)
RP_ADAPTER(RetroDiffuseF32, variants::retro_diffuse_f32)
RP_ADAPTER(AveragedIdealF32, variants::averaged_ideal_f32)
RP_ADAPTER(AveragedIdealFastF32, variants::averaged_ideal_fast_f32)
RP_ADAPTER(AveragedTirF32, variants::averaged_tir_f32)
RP_ADAPTER(AveragedTirFastF32, variants::averaged_tir_fast_f32)
#undef RP_ADAPTER

struct Pair {
    glm::dvec3 wi, wo;
};

// The direction pairs every row is timed and measured on (fixed seed): incident directions
// over the hemisphere, outgoing ones a third each near the retro peak, near the mirror
// direction and anywhere.
const std::vector<Pair>& pairs() {
    static const std::vector<Pair> set = [] {
        std::vector<Pair> out;
        std::uint64_t state = 12345;
        auto uniform = [&]() {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return double(state >> 11) * 0x1.0p-53;
        };
        auto dir = [](double cosTheta, double phi) {
            double s = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
            return glm::dvec3(s * std::cos(phi), s * std::sin(phi), cosTheta);
        };
        for (int i = 0; i < kPairs; ++i) {
            glm::dvec3 wi = dir(0.05 + 0.95 * uniform(), 2 * M_PI * uniform());
            glm::dvec3 wo;
            const glm::dvec3 jitter(0.06 * (uniform() - 0.5), 0.06 * (uniform() - 0.5), 0.0);
            if (i % 3 == 0)
                wo = glm::normalize(wi + jitter);
            else if (i % 3 == 1)
                wo = glm::normalize(glm::dvec3(-wi.x, -wi.y, wi.z) + jitter);
            else
                wo = dir(0.02 + 0.98 * uniform(), 2 * M_PI * uniform());
            if (wo.z < 0.01) wo = glm::normalize(glm::dvec3(wo.x, wo.y, 0.01));
            out.push_back({wi, wo});
        }
        return out;
    }();
    return set;
}

template <class A>
struct Prepared {
    typename A::material m;
    std::shared_ptr<const std::vector<typename A::real>> series; // m's, as the node attaches it
    std::vector<typename A::vec3> wi, wo, u;
    explicit Prepared(const Params& p)
        : m(A::prepare(sanitize(p))), series(attach_azimuth_series(m)) {
        using real = typename A::real;
        std::uint64_t state = 99;
        auto uniform = [&]() {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return real(double(state >> 11) * 0x1.0p-53);
        };
        for (const Pair& q : pairs()) {
            wi.push_back(typename A::vec3(q.wi));
            wo.push_back(typename A::vec3(q.wo));
            u.push_back(typename A::vec3(uniform(), uniform(), uniform()));
        }
    }
};

// f alone (rp_eval_f), as the baselines are timed.
template <class A>
void bm_eval(benchmark::State& state, Params p) {
    Prepared<A> d(p);
    typename A::lobes r;
    for (auto _ : state) {
        for (int i = 0; i < kPairs; ++i) {
            A::eval_f(d.m, d.wi[size_t(i)], d.wo[size_t(i)], r);
            benchmark::DoNotOptimize(r);
        }
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kPairs);
}

// A node made each iteration: of p itself (kept), or of p with its ior moved one float step
// up each time, back to p's after 1000 steps (made).
void bm_construct(benchmark::State& state, Params p, bool kept) {
    const float ior = float(p.ior);
    float moved = ior;
    int k = 0;
    for (auto _ : state) {
        if (!kept) {
            p.ior = moved;
            if (++k < 1000) {
                moved = std::nextafter(moved, 2.0f);
            } else {
                k = 0;
                moved = ior;
            }
        }
        PrismaticRetroreflector<float> node(p);
        benchmark::DoNotOptimize(node.core_material().azimuth_series);
    }
}

// kPairs shading points (shading_rows): point i's incident direction is pair i's, its light
// directions the outgoing directions of pairs i to i + kShadingLights - 1 (cyclically), its
// BSDF sample's random numbers Prepared's; each call from wi, or from incident(wi) (reuse).
void bm_shading(benchmark::State& state, Params p, bool reuse) {
    using Node = PrismaticRetroreflector<float>;
    const Node node(p);
    const Prepared<Float> d(p);
    for (auto _ : state) {
        for (int i = 0; i < kPairs; ++i) {
            const Node::vec3& wi = d.wi[size_t(i)];
            const Node::vec3& u = d.u[size_t(i)];
            if (reuse) {
                const Node::Incident in = node.incident(wi);
                for (int k = 0; k < kShadingLights; ++k)
                    benchmark::DoNotOptimize(node.eval(in, d.wo[size_t((i + k) % kPairs)]));
                benchmark::DoNotOptimize(node.sample(in, u));
            } else {
                for (int k = 0; k < kShadingLights; ++k)
                    benchmark::DoNotOptimize(node.eval(wi, d.wo[size_t((i + k) % kPairs)]));
                benchmark::DoNotOptimize(node.sample(wi, u));
            }
        }
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kPairs);
}

// f and the sampling pdf (rp_eval), as a renderer's light loop with MIS asks for them.
template <class A>
void bm_eval_pdf(benchmark::State& state, Params p) {
    Prepared<A> d(p);
    typename A::lobes r;
    typename A::real pdf = 0;
    for (auto _ : state) {
        for (int i = 0; i < kPairs; ++i) {
            A::eval(d.m, d.wi[size_t(i)], d.wo[size_t(i)], r, pdf);
            benchmark::DoNotOptimize(r);
            benchmark::DoNotOptimize(pdf);
        }
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kPairs);
}

template <class A>
void bm_sample(benchmark::State& state, Params p) {
    Prepared<A> d(p);
    typename A::lobes r;
    typename A::real pdf = 0;
    typename A::vec3 wo;
    int lobe = 0;
    for (auto _ : state) {
        for (int i = 0; i < kPairs; ++i) {
            A::sample(d.m, d.wi[size_t(i)], d.u[size_t(i)], wo, r, pdf, lobe);
            benchmark::DoNotOptimize(wo);
            benchmark::DoNotOptimize(r);
            benchmark::DoNotOptimize(pdf);
        }
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kPairs);
}

// A baseline in its own precision (float here, as the node's tiers), on the same pairs.
template <class B>
void bm_baseline(benchmark::State& state, B model) {
    using vec3 = typename B::vec3;
    std::vector<vec3> wi, wo;
    for (const Pair& q : pairs()) {
        wi.push_back(vec3(q.wi));
        wo.push_back(vec3(q.wo));
    }
    vec3 f(0);
    for (auto _ : state) {
        for (int i = 0; i < kPairs; ++i) {
            f = model.f(wi[size_t(i)], wo[size_t(i)]);
            benchmark::DoNotOptimize(f);
        }
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kPairs);
}

// The direction pairs and the random numbers for sample of the scalar float rows (Prepared), as
// structure-of-arrays batches.
struct BatchPairs {
    std::vector<float> a[9];    // wi, wo, u
    std::vector<float> out[14]; // 9 lobe channels, pdf, sampled direction (3)
    std::vector<int> lobe;
    BatchPairs() {
        const Prepared<Float> scalar{Params()};
        for (size_t i = 0; i < scalar.wi.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                a[c].push_back(scalar.wi[i][c]);
                a[3 + c].push_back(scalar.wo[i][c]);
                a[6 + c].push_back(scalar.u[i][c]);
            }
        for (auto& v : out)
            v.assign(pairs().size(), 0.0f);
        lobe.assign(pairs().size(), 0);
    }
    BatchDirections in(int k) const { return {a[k].data(), a[k + 1].data(), a[k + 2].data()}; }
    BatchColors rgb(int k) { return {out[k].data(), out[k + 1].data(), out[k + 2].data()}; }
    BatchLobes lobes() { return {rgb(0), rgb(3), rgb(6)}; }
};

// The node over one batch of the pairs (nodes/batch.h), one thread: f alone, f + pdf, or sample.
enum class BatchCall { F, FPdf, Sample };
void bm_batch(benchmark::State& state, Params p, BatchCall call, SimdLevel level) {
    const BatchEvaluator batch(p);
    BatchPairs d;
    const BatchSamples samples{d.out[10].data(), d.out[11].data(), d.out[12].data(),
                               d.lobes(),        d.out[9].data(),  d.lobe.data()};
    BatchOptions opt;
    opt.level = level;
    for (auto _ : state) {
        if (call == BatchCall::Sample)
            batch.sample(kPairs, d.in(0), d.in(6), samples, opt);
        else
            batch.eval(kPairs, d.in(0), d.in(3), d.lobes(),
                       call == BatchCall::FPdf ? d.out[9].data() : nullptr, opt);
        benchmark::DoNotOptimize(d.out[4].data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kPairs);
}

// The MaterialX-style GGX over one batch by the same means (bench/batch_baseline.h).
void bm_mrm_batch(benchmark::State& state, baselines::RetroreflectiveGGXT<float> model) {
    BatchPairs d;
    for (auto _ : state) {
        mrm_batch_f(model, kPairs, d.in(0), d.in(3), d.rgb(0));
        benchmark::DoNotOptimize(d.out[0].data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * kPairs);
}

// The batch evaluator for material p at instruction set `level`, one query at a time, as a
// LocalEval (its errors).
LocalEval batch_eval(const Params& p, SimdLevel level) {
    const auto batch = std::make_shared<const BatchEvaluator>(p);
    return [batch, level](const glm::dvec3& wi, const glm::dvec3& wo, glm::dvec3 f[3]) {
        const float in[6] = {float(wi.x), float(wi.y), float(wi.z),
                             float(wo.x), float(wo.y), float(wo.z)};
        float out[9];
        BatchOptions opt;
        opt.level = level;
        batch->eval(
            1, {&in[0], &in[1], &in[2]}, {&in[3], &in[4], &in[5]},
            {{&out[0], &out[1], &out[2]}, {&out[3], &out[4], &out[5]}, {&out[6], &out[7], &out[8]}},
            nullptr, opt);
        for (int k = 0; k < 3; ++k)
            f[k] = glm::dvec3(out[3 * k], out[3 * k + 1], out[3 * k + 2]);
    };
}

// A prepared for material p, as a LocalEval.
template <class A>
LocalEval local_eval(const Params& p) {
    const auto d = std::make_shared<const Prepared<A>>(p);
    return [d](const glm::dvec3& wi, const glm::dvec3& wo, glm::dvec3 f[3]) {
        using vec3 = typename A::vec3;
        typename A::lobes r;
        A::eval_f(d->m, vec3(wi), vec3(wo), r);
        f[0] = glm::dvec3(r.surface);
        f[1] = glm::dvec3(r.retro);
        f[2] = glm::dvec3(r.diffuse);
    };
}

Params material(int prism, int fidelity, double specular = 1.0) {
    Params p;
    p.prism_reflection = prism;
    p.fidelity = fidelity;
    p.specular = specular;
    p.diffuse_color = {0.8, 0.8, 0.8};
    return p;
}

template <class A>
Row node_row(const std::string& name, const std::string& tier, const std::string& lobes,
             const std::string& config, const Params& p, const Params& ref, int mask) {
    benchmark::RegisterBenchmark(("eval/" + name).c_str(), bm_eval<A>, p);
    benchmark::RegisterBenchmark(("eval_pdf/" + name).c_str(), bm_eval_pdf<A>, p);
    benchmark::RegisterBenchmark(("sample_pdf/" + name).c_str(), bm_sample<A>, p);
    Row r;
    r.name = name;
    r.tier = tier;
    r.lobes = lobes;
    r.config = config;
    r.has_sample = true;
    r.mask = mask;
    r.material = p;
    r.reference = ref;
    r.make_eval = local_eval<A>;
    return r;
}

Row batch_row(const std::string& name, const std::string& tier, const Params& p, const Params& ref,
              SimdLevel level = simd_level_supported()) {
    benchmark::RegisterBenchmark(("eval/" + name).c_str(), bm_batch, p, BatchCall::F, level);
    benchmark::RegisterBenchmark(("eval_pdf/" + name).c_str(), bm_batch, p, BatchCall::FPdf, level);
    benchmark::RegisterBenchmark(("sample_pdf/" + name).c_str(), bm_batch, p, BatchCall::Sample,
                                 level);
    Row r;
    r.name = name;
    r.tier = tier;
    r.lobes = "surface+retro+diffuse";
    r.config = std::string("ideal prisms, one batch of ") + std::to_string(kPairs) +
               " pairs (nodes/batch.h), " + simd_level_name(level) + " kernels, one thread";
    r.has_sample = true;
    r.mask = 7;
    r.material = p;
    r.reference = ref;
    r.make_eval = [level](const Params& q) { return batch_eval(q, level); };
    return r;
}

// A PairedRow of material p: benchmark bm registered as "<prefix><name>" (bm(p, false)) and
// "<prefix><name><suffix>" (bm(p, true)).
PairedRow paired_row(void (*bm)(benchmark::State&, Params, bool), const std::string& prefix,
                     const std::string& suffix, const std::string& name, const std::string& config,
                     const Params& p) {
    PairedRow r{name, config, prefix + name, prefix + name + suffix};
    benchmark::RegisterBenchmark(r.first.c_str(), bm, p, false);
    benchmark::RegisterBenchmark(r.second.c_str(), bm, p, true);
    return r;
}

template <class B>
Row baseline_row(const std::string& name, const std::string& config, B model) {
    benchmark::RegisterBenchmark(("eval/" + name).c_str(), bm_baseline<B>, model);
    Row r;
    r.name = name;
    r.tier = "baseline";
    r.lobes = name;
    r.config = config;
    r.baseline = true;
    return r;
}

} // namespace

const std::vector<Row>& rows() {
    static const std::vector<Row> all = [] {
        const std::string all3 = "surface+retro+diffuse";
        const Params ideal = material(0, 0), idealFast = material(0, 1);
        const Params tir = material(1, 0), tirFast = material(1, 1);
        const Params noSurface = material(0, 0, 0.0);
        std::vector<Row> out;
        out.push_back(node_row<Double>("reference", "reference", all3, "ideal prisms, double",
                                       ideal, ideal, 7));
        out.push_back(node_row<Float>("exact", "exact", all3, "ideal prisms, modes at run time",
                                      ideal, ideal, 7));
        out.push_back(node_row<AveragedIdealF32>("exact_fixed", "exact", all3,
                                                 "ideal prisms, averaged ERA fixed at compile time",
                                                 ideal, ideal, 7));
        out.push_back(node_row<Float>("exact_specular_off", "exact", "retro+diffuse",
                                      "surface lobe off at run time (specular 0)", noSurface,
                                      noSurface, 6));
        out.push_back(node_row<RetroDiffuseF32>("exact_retro_diffuse", "exact", "retro+diffuse",
                                                "surface lobe left out at compile time", ideal,
                                                ideal, 6));
        out.push_back(node_row<RetroF32>("exact_retro", "exact", "retro",
                                         "surface and diffuse lobes left out at compile time",
                                         ideal, ideal, 2));
        out.push_back(node_row<Float>("fast", "fast", all3, "ideal prisms, modes at run time",
                                      idealFast, ideal, 7));
        out.push_back(node_row<AveragedIdealFastF32>(
            "fast_fixed", "fast", all3, "ideal prisms, averaged ERA fixed at compile time",
            idealFast, ideal, 7));
        out.push_back(node_row<Double>("reference_tir", "reference", all3,
                                       "uncoated (tir) prisms, double", tir, tir, 7));
        out.push_back(node_row<Float>("exact_tir", "exact", all3,
                                      "uncoated prisms, modes at run time", tir, tir, 7));
        out.push_back(node_row<Float>("fast_tir", "fast", all3,
                                      "uncoated prisms, modes at run time", tirFast, tir, 7));
        out.push_back(node_row<AveragedTirF32>(
            "exact_tir_fixed", "exact", all3, "uncoated prisms, averaged ERA fixed at compile time",
            tir, tir, 7));
        out.push_back(node_row<AveragedTirFastF32>(
            "fast_tir_fixed", "fast", all3, "uncoated prisms, averaged ERA fixed at compile time",
            tirFast, tir, 7));
        // Canted cube corners (cant_angle 10 deg): what the runtime cant costs when it is used.
        Params canted = ideal, tirCanted = tir;
        canted.cant_angle = 10.0;
        tirCanted.cant_angle = 10.0;
        out.push_back(node_row<Float>("exact_canted", "exact", all3,
                                      "ideal prisms canted 10 deg, modes at run time", canted,
                                      canted, 7));
        out.push_back(node_row<Float>("exact_tir_canted", "exact", all3,
                                      "uncoated prisms canted 10 deg, modes at run time", tirCanted,
                                      tirCanted, 7));
        // Dihedral errors (5 arcmin, a ring of spots about the retro direction): what the
        // runtime ring costs when it is used; at 0 the fixed rows above leave its code out.
        Params dihedral = ideal;
        dihedral.dihedral_error = 5.0;
        out.push_back(node_row<Float>("exact_dihedral", "exact", all3,
                                      "ideal prisms, dihedral error 5 arcmin, modes at run time",
                                      dihedral, dihedral, 7));
        // Diffraction at the prisms (prism_pitch 160 um, docs/diffraction.md): at one wavelength
        // (one pattern), per colour channel (three) and in the fast tier (9 tail scales instead
        // of 17); at pitch 0 the fixed rows above leave its code out.
        Params diffraction = ideal, diffractionRgb = ideal, diffractionFast = idealFast;
        diffraction.prism_pitch = diffractionRgb.prism_pitch = diffractionFast.prism_pitch = 160.0;
        diffraction.wavelength = diffractionFast.wavelength = 550.0;
        out.push_back(node_row<Float>("exact_diffraction", "exact", all3,
                                      "ideal prisms, pitch 160 um at 550 nm, modes at run time",
                                      diffraction, diffraction, 7));
        out.push_back(node_row<Float>("exact_diffraction_rgb", "exact", all3,
                                      "ideal prisms, pitch 160 um per colour channel",
                                      diffractionRgb, diffractionRgb, 7));
        out.push_back(node_row<Float>("fast_diffraction", "fast", all3,
                                      "ideal prisms, pitch 160 um at 550 nm, fast tier",
                                      diffractionFast, diffraction, 7));
        // A smooth top surface (roughness 5e-4), whose geometric lobe is narrow against the
        // pattern's rings: the exact tier evaluates the pattern itself (rp_diffraction_pattern).
        Params pattern = diffraction;
        pattern.roughness = 5e-4;
        pattern.wavelength = 905.0;
        out.push_back(node_row<Float>("exact_diffraction_pattern", "exact", all3,
                                      "ideal prisms, pitch 160 um at 905 nm, roughness 5e-4: the "
                                      "pattern itself",
                                      pattern, pattern, 7));
        Params tirPattern = pattern;
        tirPattern.prism_reflection = f64::RP_PRISM_TIR;
        out.push_back(node_row<Float>("exact_tir_diffraction_pattern", "exact", all3,
                                      "uncoated prisms, pitch 160 um at 905 nm, roughness 5e-4: "
                                      "the face orders' pattern",
                                      tirPattern, tirPattern, 7));
        baselines::LambertT<float> lambert;
        baselines::BeckmannCookTorranceT<float> ct;
        ct.roughness = 0.05f;
        ct.ior = 1.49f;
        baselines::RetroreflectiveGGXT<float> mrm;
        mrm.roughness = 0.05f;
        mrm.ior = 1.49f;
        out.push_back(baseline_row("lambert", "Lambert, float", lambert));
        out.push_back(baseline_row("beckmann_ct", "Beckmann Cook-Torrance, float", ct));
        out.push_back(
            baseline_row("mrm_ggx", "MaterialX-style retroreflective GGX + Lambert, float", mrm));
        out.push_back(batch_row("batch_exact", "exact", ideal, ideal));
        out.push_back(batch_row("batch_fast", "fast", idealFast, ideal));
        // The fast batch at every lower instruction set (each is supported where a higher one
        // is): what the vector width buys.
        for (int level = int(simd_level_supported()) - 1; level >= 0; --level)
            out.push_back(batch_row(std::string("batch_fast_") + simd_level_name(SimdLevel(level)),
                                    "fast", idealFast, ideal, SimdLevel(level)));
        benchmark::RegisterBenchmark("eval/mrm_ggx_batch", bm_mrm_batch, mrm);
        Row mrmBatch;
        mrmBatch.name = "mrm_ggx_batch";
        mrmBatch.tier = "baseline";
        mrmBatch.lobes = "mrm_ggx";
        mrmBatch.config = std::string("mrm_ggx over one batch by the batch rows' means "
                                      "(bench/batch_baseline.h), ") +
                          simd_level_name(simd_level_supported()) + " kernels, one thread";
        mrmBatch.baseline = true;
        out.push_back(mrmBatch);
        construction_rows();
        shading_rows();
        return out;
    }();
    return all;
}

const std::vector<PairedRow>& construction_rows() {
    static const std::vector<PairedRow> all = [] {
        std::vector<PairedRow> out;
        auto add = [&](const std::string& name, const std::string& config, const Params& p) {
            out.push_back(paired_row(bm_construct, "construct/", "_kept", name, config, p));
        };
        Params tir;
        tir.prism_reflection = f64::RP_PRISM_TIR;
        tir.fidelity = f64::RP_FIDELITY_EXACT;
        add("exact_tir", "the paper's cube, uncoated prisms, exact tier, ior 1.49", tir);
        Params canted = tir;
        canted.cant_angle = -11.0;
        add("canted_tir", "cant -11 deg, uncoated prisms, ior 1.49", canted);
        Params metal = canted;
        metal.prism_reflection = f64::RP_PRISM_METALLIZED;
        add("canted_metal", "cant -11 deg, metallised prisms (ERA and face hits), ior 1.49", metal);
        return out;
    }();
    return all;
}

const std::vector<PairedRow>& shading_rows() {
    static const std::vector<PairedRow> all = [] {
        std::vector<PairedRow> out;
        auto add = [&](const std::string& name, const std::string& config, const Params& p) {
            out.push_back(paired_row(bm_shading, "shading/", "_state", name, config, p));
        };
        const Params ideal = material(0, 0), tir = material(1, 0);
        add("exact", "ideal prisms, exact tier", ideal);
        add("exact_tir", "uncoated prisms, exact tier", tir);
        Params diffraction = ideal, tirDiffraction = tir;
        diffraction.prism_pitch = tirDiffraction.prism_pitch = 160.0;
        add("exact_diffraction_rgb", "ideal prisms, pitch 160 um per colour channel", diffraction);
        add("exact_tir_diffraction_rgb", "uncoated prisms, pitch 160 um per colour channel",
            tirDiffraction);
        diffraction.wavelength = 905.0;
        add("exact_diffraction_905", "ideal prisms, pitch 160 um at 905 nm", diffraction);
        diffraction.roughness = 5e-4;
        add("exact_pattern_905", "ideal prisms, pitch 160 um at 905 nm, roughness 5e-4",
            diffraction);
        tirDiffraction.wavelength = 905.0;
        tirDiffraction.roughness = 5e-4;
        add("exact_tir_pattern_905", "uncoated prisms, pitch 160 um at 905 nm, roughness 5e-4",
            tirDiffraction);
        return out;
    }();
    return all;
}

} // namespace retroprism::bench
