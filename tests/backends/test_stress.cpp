// [stress]: reliability.
//  - A bounded version of the adversarial sweep of `retroprism check --stress`, through the
//    library's API (backends/stress.h, linked from retroprism_backends) and printed by the
//    command's printer (report/stress_table.h): the same generator over every enum/boolean
//    combination and every single-input hard value, on every seventh direction pair (every
//    13th for materialx), then random hard materials, through every backend (1e6, 1e6, 5e5 and
//    9e4 evaluations). Required: no NaN, Inf or negative value, no guard violation, no
//    sample/pdf inconsistency. These sweeps are tagged [ci]: the ctest entry stress_ci (label
//    ci), which .ci/run runs after the README's test command.
//  - The generator itself (stress::material, stress::stress_pairs): it reaches the hard values
//    and is deterministic.
//  - The checked-in fuzz corpus (fuzz/corpus/<target>/) replayed through the fuzz targets'
//    checks (fuzz/fuzz_checks.h, header-only), and the inputs the fuzzing and the sweep found,
//    as regression tests.
//  - The error paths of the sweep's command.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../../fuzz/fuzz_checks.h"
#include "backend.h"
#include "stress.h"
#include "stress_table.h"
#include "test_support.h"

using namespace retroprism;
namespace fs = std::filesystem;

namespace {

using Run = rptest::CommandRun;
using rptest::contains;
using rptest::run_cli;

std::vector<std::uint8_t> read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// Runs the bounded sweep of one backend and reports it as the command does.
stress::Tally bounded_sweep(const std::string& backend) {
    // Every combination and single-input hard value (the hard materials) on every seventh pair,
    // then random hard materials: 1e6 evaluations for the C++ backends, 5e5 for glsl; materialx
    // on every 13th pair of the hard materials alone.
    stress::Options opt = stress::quick_options(backend);
    // Instrumented (scripts/sanitize.sh), materialx takes every third of its pairs (every 39th
    // of each hard material's): the pairs reach MaterialX's shader only as uniforms, one draw
    // each, through the same runner code; every hard material still goes through all of it.
    // Its 420,000 draws (140,000 pairs, three lobes) took 160 s there, 23 s in the release
    // build. The release suite's stress_ci keeps every 13th pair.
    if (rptest::kInstrumented && backend == "materialx")
        opt = stress::quick_options(backend, 3 * opt.pair_stride);
    const stress::Tally t = stress::sweep_backend(backend, opt);
    StressTable table(stress::coverage(), stdout);
    table.add(t);
    table.finish();
    std::printf("MEASURED: stress %s: %ld materials, %ld evaluations, %ld samples, %ld albedos, "
                "%ld values: %ld NaN, %ld Inf, %ld negative, %ld guard violations, %ld "
                "inconsistent samples (%ld round-trip differences), %.1f s\n",
                backend.c_str(), t.materials, t.evaluations, t.samples, t.albedos, t.values, t.nan,
                t.inf, t.negative, t.guard, t.inconsistent, t.round_trip, t.seconds);
    return t;
}

void require_clean(const stress::Tally& t) {
    // Every enum/boolean combination and every single-input hard value went through.
    CHECK(t.materials >= stress::hard_material_count());
    CHECK(t.nonzero > t.evaluations / 4);
    CHECK(t.nan == 0);
    CHECK(t.inf == 0);
    CHECK(t.negative == 0);
    CHECK(t.guard == 0);
    CHECK(t.inconsistent == 0);
    CHECK(t.oob_bad == 0);
    CHECK(t.passed());
}

} // namespace

TEST_CASE("bounded adversarial sweep: cpp-double", "[stress][ci]") {
    const stress::Tally t = bounded_sweep("cpp-double");
    CHECK(t.samples > 0);
    CHECK(t.albedos > 0);
    require_clean(t);
}

TEST_CASE("bounded adversarial sweep: cpp-float", "[stress][ci]") {
    const stress::Tally t = bounded_sweep("cpp-float");
    CHECK(t.samples > 0);
    require_clean(t);
}

TEST_CASE("bounded adversarial sweep: cpp-batch", "[stress][ci]") {
    const stress::Tally t = bounded_sweep("cpp-batch");
    CHECK(t.evaluations > 0);
    require_clean(t);
}

TEST_CASE("bounded adversarial sweep: glsl", "[stress][ci]") {
    require_clean(bounded_sweep("glsl"));
}

TEST_CASE("bounded adversarial sweep: materialx", "[stress][ci]") {
    require_clean(bounded_sweep("materialx"));
}

TEST_CASE("the sweep's generator covers the hard places", "[stress]") {
    // Every enum value and out-of-range index, every float input at its range ends, NaN and
    // Inf, in the materials the bounded sweep runs.
    const long n = stress::hard_material_count();
    CHECK(n == stress::coverage().combinations + stress::coverage().single_mutations);
    bool nanRoughness = false, minAlpha = false, iorBelow1 = false, enumOut = false,
         nanNormal = false, negativeColor = false;
    for (long i = 0; i < n; ++i) {
        const Params p = stress::material(i, nullptr);
        nanRoughness = nanRoughness || std::isnan(p.roughness);
        minAlpha = minAlpha || p.roughness == 1e-4;
        iorBelow1 = iorBelow1 || p.ior < 1.0;
        enumOut = enumOut || p.prism_reflection < 0 || p.era_mode > 2;
        nanNormal = nanNormal || std::isnan(p.normal[0]);
        negativeColor = negativeColor || p.diffuse_color[0] < 0;
    }
    CHECK(nanRoughness);
    CHECK(minAlpha);
    CHECK(iorBelow1);
    CHECK(enumOut);
    CHECK(nanNormal);
    CHECK(negativeColor);
    // Labels name what each material is.
    std::string label;
    (void)stress::material(0, &label);
    CHECK(label == "combination 0");
    (void)stress::material(n, &label);
    CHECK(label == "random material 0");
    // Pairs: wo = wi exactly and one ulp away, float ulps for float backends.
    const std::vector<DirectionPair> d = stress::stress_pairs(Params(), false, 1);
    const std::vector<DirectionPair> f = stress::stress_pairs(Params(), true, 1);
    REQUIRE(d.size() == f.size());
    CHECK(d.size() == stress::coverage().pairs_per_material);
    CHECK(d[0].wi == d[0].wo);
    CHECK(f[1].wo[0] == double(std::nextafter(float(f[1].wi[0]), -INFINITY)));
    CHECK(d[1].wo[0] == std::nextafter(d[1].wi[0], -INFINITY));
    // The same generator gives the same pairs every time.
    CHECK(std::memcmp(stress::stress_pairs(Params(), true, 1).data(), f.data(),
                      f.size() * sizeof(DirectionPair)) == 0);
}

TEST_CASE("check --stress rejects an unknown backend", "[stress]") {
    const Run r = run_cli("check --stress --backend no-such-backend");
    CHECK(r.status != 0);
    CHECK(contains(r.output, "no-such-backend"));
    CHECK(contains(r.output, "unknown backend"));
    // The sweep itself names the backend and lists the known ones.
    try {
        (void)stress::sweep_backend("nope");
        FAIL("sweep_backend accepted an unknown backend");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), "nope"));
        for (const std::string& name : backend_names())
            CHECK(contains(e.what(), name));
    }
}

TEST_CASE("check --stress states its size and takes --evaluations and --quick", "[stress]") {
    // One material of the full generator (2746 pairs) through cpp-double.
    Run r = run_cli("check --stress --backend cpp-double --evaluations 2000");
    CHECK(r.status == 0);
    CHECK(contains(r.output, "size: at least 2000 evaluations per C++ backend, 200 per GL"));
    // One material: its pairs are the row's evaluations.
    CHECK(contains(r.output, " " + std::to_string(stress::coverage().pairs_per_material) + " "));
    CHECK(contains(r.output, "stress: pass (1 backend, "));
    for (const char* bad : {"0", "-5", "nan", "1e13"}) {
        r = run_cli(std::string("check --stress --backend cpp-double --evaluations ") + bad);
        CHECK(r.status != 0);
        CHECK(contains(r.output, "--evaluations"));
        CHECK(contains(r.output, "expected a whole number in [1, 1000000000000]"));
    }
    r = run_cli("check --stress --quick --evaluations 5000");
    CHECK(r.status != 0);
    CHECK(contains(r.output, "not with --quick"));
    // The bounded sweep's sizes.
    const stress::Options quick = stress::quick_options("cpp-float");
    CHECK(quick.pair_stride == 7);
    CHECK(quick.cpp_evaluations >= 1000000);
    CHECK(stress::quick_options("materialx").pair_stride == 13);
    CHECK(stress::sized_options(123).gl_evaluations == 12);
}

TEST_CASE("the fuzz corpus replays cleanly", "[stress]") {
    const fs::path corpus = fs::path(RP_SOURCE_DIR) / "fuzz" / "corpus";
    struct Target {
        const char* name;
        void (*check)(const std::uint8_t*, size_t);
    };
    const Target targets[] = {{"closure", rpfuzz::check_closure},   {"query", rpfuzz::check_query},
                              {"mtlx", rpfuzz::check_mtlx},         {"alta", rpfuzz::check_alta},
                              {"ra_table", rpfuzz::check_ra_table}, {"study", rpfuzz::check_study}};
    for (const Target& t : targets) {
        int files = 0;
        for (const auto& entry : fs::directory_iterator(corpus / t.name)) {
            const std::vector<std::uint8_t> bytes = read_bytes(entry.path());
            INFO(entry.path().string());
            CHECK_NOTHROW(t.check(bytes.data(), bytes.size()));
            ++files;
        }
        std::printf("MEASURED: fuzz corpus %s: %d inputs replayed\n", t.name, files);
        CHECK(files >= 5);
    }
}

// ---- Regressions: what the fuzzing and the sweep found ----------------------------------

TEST_CASE("regression: a number beyond double's range is an error naming the file", "[stress]") {
    // Found by fuzz_query: nlohmann's parser throws out_of_range (406), not parse_error, for
    // 1e400; read_json passed it on without the file's name.
    const fs::path p = fs::temp_directory_path() / "retroprism_stress_overflow.json";
    std::ofstream(p) << "{\"material\": {\"ior\": 1e400}, \"samples\": []}";
    try {
        (void)read_json(p.string());
        FAIL("read_json accepted 1e400");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), p.string()));
    } catch (const std::exception& e) {
        FAIL(std::string("read_json threw a non-InputError: ") + e.what());
    }
    const Run r = run_cli("eval " + p.string());
    CHECK(r.status != 0);
    CHECK(contains(r.output, p.string()));
    fs::remove(p);
}

TEST_CASE("regression: the frame is orthonormal for a tangent nearly along the normal",
          "[stress]") {
    // Found by the sweep: one Gram-Schmidt pass leaves t.n ~ eps / |t - (t.n) n|, so sample()'s
    // to_world and eval()'s to_local stop being inverses (sample vs eval(wi, s.wo): 3e-7 in
    // double for the normal below).
    const std::vector<std::pair<Vec3d, Vec3d>> frames = {{{0.999, 0.0, 0.04}, {1.0, 0.0, 0.0}},
                                                         {{0.2, -0.1, 1.0}, {0.201, -0.1, 1.0}},
                                                         {{0.2, -0.1, 1.0}, {0.200002, -0.1, 1.0}}};
    for (const auto& [n, t] : frames) {
        Params p;
        p.normal = n;
        p.tangent = t;
        const Params s = sanitize(p);
        const glm::dvec3 N(s.normal[0], s.normal[1], s.normal[2]);
        const glm::dvec3 T(s.tangent[0], s.tangent[1], s.tangent[2]);
        INFO("normal (" << n[0] << ", " << n[1] << ", " << n[2] << "), tangent (" << t[0] << ", "
                        << t[1] << ", " << t[2] << "): t.n = " << glm::dot(N, T));
        CHECK(std::abs(glm::dot(N, T)) <= 8 * std::numeric_limits<double>::epsilon());
    }
}

TEST_CASE("regression: a tiny direction is unit in the local frame, or none", "[stress]") {
    // Found by the sweep: a direction whose squared length is subnormal (|w| < 1e-19 in float,
    // < 1e-154 in double) was divided by the square root of a number with few significant bits,
    // and its local direction was off unit by up to 1e-5: sample() and eval(wi, s.wo) then
    // disagreed (9e-5 in float, 1.7e-4 in double). Such a direction must come out unit, or be
    // rejected as a zero direction.
    {
        const PrismaticRetroreflector<float> node{Params()};
        const glm::vec3 w(6.208851201256054e-21f, 1.6636567076292983e-21f, 7.6604445280518633e-21f);
        glm::vec3 local;
        if (node.to_local(w, local)) CHECK(std::abs(glm::length(glm::dvec3(local)) - 1.0) <= 4e-7);
    }
    {
        const PrismaticRetroreflector<double> node{Params()};
        const glm::dvec3 w(6.2088515301484567e-161, 1.6636567534280191e-161,
                           7.6604444311897799e-161);
        glm::dvec3 local;
        if (node.to_local(w, local)) CHECK(std::abs(glm::length(local) - 1.0) <= 1e-15);
    }
}

TEST_CASE("regression: materialx gives zero, not NaN, for a non-finite view direction",
          "[stress]") {
    // Found by the sweep: these five pairs (the first material's degenerate block) rendered
    // together give NaN in every lobe at the last one (wo = (0, 0, inf)): the environment
    // closure of the node's MaterialX implementation evaluates MaterialX's environment lookups
    // with the NaN view direction (times u_envLightIntensity = 0, still NaN).
    const double inf = std::numeric_limits<double>::infinity();
    const Vec3d wi = {-0.62088513374328613, -0.16636566817760468, 0.76604443788528442};
    Query q;
    q.samples = {{wi, {inf, 0, 0}},
                 {{0, 0, inf}, {0, 0, inf}},
                 {{0, 0, inf}, wi},
                 {{0, 0, inf}, {0.34202015399932861, 0, 0.93969261646270752}},
                 {wi, {0, 0, inf}}};
    const nlohmann::json a = answer_query(q, "materialx");
    for (const nlohmann::json& r : a.at("results")) {
        INFO(r.dump());
        for (const char* key : {"surface", "retro", "diffuse"})
            for (const nlohmann::json& v : r.at(key))
                CHECK((v.is_number() && v.get<double>() == 0.0));
    }
}

TEST_CASE("regression: diffraction at a vanishing wavelength and near the horizon of wi",
          "[stress]") {
    // Found by the sweep: (1) a wavelength of 1e-300 nm (or a denormal) made the dispersion
    // law's 1 / lambda^2 infinite, and with ior 1 (b = 0) the index 0 * inf = NaN: the diffuse
    // lobe was NaN; and lambda / pitch underflowed to 0, a zero-width pattern: the retro lobe 0.
    // Wavelengths below RP_MIN_WAVELENGTH_NM (1 nm) are taken as it: the node at 1e-300 nm is
    // the node at 1 nm. (2) In float, wo 90 degrees from wi (cos 1e-8) gave 1 / cos^3 = inf times
    // the pattern's zero: NaN in the retro lobe and the pdf.
    Params p;
    p.ior = 1.0;
    p.abbe_number = 57.3;
    p.prism_pitch = 1e-3;
    p.cant_angle = 30.0;
    p.dihedral_error = 48.0;
    Params at1 = p;
    at1.wavelength = 1.0;
    const glm::dvec3 n(0, 0, 1), w1(-4.9406564584124654e-324, 0, 1);
    for (double tiny : {4.9406564584124654e-324, 1e-300, 1e-10, 0.5}) {
        Params q = p;
        q.wavelength = tiny;
        INFO("wavelength " << tiny);
        const auto a = PrismaticRetroreflector<double>(q).eval(n, w1);
        const auto b = PrismaticRetroreflector<double>(at1).eval(n, w1);
        CHECK(a.f.diffuse.x == b.f.diffuse.x);
        CHECK(a.f.retro.x == b.f.retro.x);
        CHECK(a.pdf == b.pdf);
        CHECK(a.f.retro.x > 0);
    }
    Params g;
    g.roughness = 0.78;
    g.cant_angle = 24.26;
    g.dihedral_error = 38.0;
    g.dihedral_spread = 59.9;
    g.prism_pitch = 1632.0;
    g.wavelength = 1871.0;
    g.retro_lobe = 1;
    const PrismaticRetroreflector<float> node(g);
    const glm::vec3 wi(-5.6892428546007068e-08f, 8.2238990728455974e-08f, 1.0f);
    const glm::vec3 wo(0.56892430782318115f, -0.82238990068435669f, 1.0000000116860974e-07f);
    const auto e = node.eval(wi, wo);
    CHECK(e.f.retro.x == 0.0f);
    CHECK(std::isfinite(e.pdf));
    CHECK(e.pdf >= 0.0f);
}
