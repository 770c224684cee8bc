// [osl] The node as an Open Shading Language closure (osl/), run through liboslexec: the
// generated shader osl/shaders/retroprism_bsdf.osl compiled by oslc and liboslcomp, its closure
// registered by register_retroprism_closure and read back from the closure tree, against the
// C++ node; every input changing it; the node made once per material; a direct-lighting render's
// R_A against the C++ R_A table; the OSL that real MaterialX generates with the opt-in library
// materialx/rp_pbrlib_closure for every bundled document, compiled, and rendered against the
// same table (the node's chain) or run over its texture (a graph). Built where OSL is found
// (tests/CMakeLists.txt); docs/osl.md quotes the figures.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "color.h"
#include "mtlx_reader.h"
#include "osl_gen.h"
#include "photometry.h"
#include "ra_render.h"
#include "retroprism_closure.h"
#include "shading.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace retroprism;
using glm::dvec3;

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// eval's pdf at a sampled light against the sample's pdf: the light is returned in world space
// as floats, and projected again it moves by a few 2^-24 radians, which moves the pdf of the
// narrowest lobes (roughness 1e-4: about 2e-4 radians wide, 1e7 per steradian) by up to 3%
// (measured); the pdf of the other side (the light as the incident direction) differs by far
// more for the diffuse lobe and the mixture's weights.
constexpr double kPdfTolerance = 0.05;

const fs::path kShaders = fs::path(RP_SOURCE_DIR) / "osl" / "shaders";

// OSL's oslc compiles `file` (#include searched in `includes`); its messages when it fails.
bool oslc(const fs::path& file, const fs::path& includes) {
    const fs::path oso =
        fs::temp_directory_path() / ("retroprism_test_osl_" + std::to_string(::getpid()) + ".oso");
    const rptest::CommandRun run =
        rptest::run_command(std::string(RP_OSLC_PATH) + " -q -I" + includes.string() + " " +
                            file.string() + " -o " + oso.string());
    fs::remove(oso);
    INFO("oslc " << file.string() << ": " << run.output);
    CHECK(run.status == 0);
    return run.status == 0;
}

// One shading system for the binary, with the generated shader loaded.
osl::ShaderRunner& runner() {
    static osl::ShaderRunner r;
    static bool loaded = false;
    if (!loaded) {
        r.compile("retroprism_bsdf", read_text(kShaders / "retroprism_bsdf.osl"),
                  {kShaders.string()});
        loaded = true;
    }
    return r;
}

// p with its floats and colours rounded to float: the values a shader parameter holds.
Params rounded(Params p) {
    for_each_input(p, [](const ParamInfo&, auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>) v = double(float(v));
        if constexpr (std::is_same_v<T, Color3>)
            for (double& c : v)
                c = double(float(c));
    });
    return p;
}

// The shader parameters of every input but the vectors (the shading point's N and dPdu).
std::vector<osl::ParamValue> shader_params(const Params& p) {
    std::vector<osl::ParamValue> out;
    for_each_input(p, [&](const ParamInfo& info, const auto& v) {
        using T = std::decay_t<decltype(v)>;
        osl::ParamValue pv;
        pv.name = glsl::osl_name(info.name);
        if constexpr (std::is_same_v<T, double>) {
            pv.type = OSL::TypeDesc::TypeFloat;
            pv.floats = {float(v)};
        } else if constexpr (std::is_same_v<T, Color3>) {
            if (info.type == ParamType::Vector) return;
            pv.type = OSL::TypeDesc::TypeColor;
            pv.floats = {float(v[0]), float(v[1]), float(v[2])};
        } else {
            pv.type = OSL::TypeDesc::TypeInt;
            pv.integer = int(v);
        }
        out.push_back(pv);
    });
    return out;
}

// The retroprism_bsdf components of a closure.
std::vector<osl::Component> retroprism_components(const std::vector<osl::Component>& closure) {
    std::vector<osl::Component> out;
    for (const osl::Component& c : closure)
        if (c.id == osl::kRetroprismClosureId) out.push_back(c);
    return out;
}

OSL::Vec3 to_osl(const dvec3& v) {
    return OSL::Vec3(float(v.x), float(v.y), float(v.z));
}
dvec3 from_osl(const OSL::Vec3& v) {
    return dvec3(v.x, v.y, v.z);
}

// |a - b| relative to |b| (0 when both are 0), the largest over the channels.
double rel_diff(const dvec3& a, const dvec3& b) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double d = std::abs(a[c] - b[c]);
        if (d > 0.0) worst = std::max(worst, d / std::max(std::abs(b[c]), 1e-300));
    }
    return worst;
}

// The sweep's shading frame: a tilted normal and a tangent not orthogonal to it (the closure
// makes the frame as the node does).
const dvec3 kNormal = glm::normalize(dvec3(0.2, -0.3, 1.0));
const dvec3 kTangent = dvec3(1.0, 0.4, 0.0);

struct Frame {
    dvec3 n, t, b;
};
Frame sweep_frame() {
    Frame f;
    f.n = kNormal;
    f.t = glm::normalize(kTangent - glm::dot(kTangent, f.n) * f.n);
    f.b = glm::cross(f.n, f.t);
    return f;
}
dvec3 to_world(const Frame& f, const dvec3& l) {
    return l.x * f.t + l.y * f.b + l.z * f.n;
}

// The sweep's views (local polar angles 0-85 degrees at three azimuths) and, per view, lights
// at observation angles 0.2, 1 and 4 degrees from it, its mirror direction, and two fixed
// directions, all in the local frame.
struct DirectionPair {
    dvec3 view, light;
};
std::vector<DirectionPair> sweep_pairs() {
    std::vector<DirectionPair> out;
    for (double thetaV : {0.0, 15.0, 40.0, 65.0, 85.0})
        for (double phiV : {0.0, 70.0, 200.0}) {
            const dvec3 v = rptest::dir_deg(thetaV, phiV);
            const dvec3 side = glm::normalize(glm::cross(v, dvec3(0.3, 0.5, 0.2)));
            for (double obs : {0.2, 1.0, 4.0}) {
                const double a = glm::radians(obs);
                out.push_back({v, std::cos(a) * v + std::sin(a) * side});
            }
            out.push_back({v, dvec3(-v.x, -v.y, v.z)});
            out.push_back({v, rptest::dir_deg(30.0, 120.0)});
            out.push_back({v, rptest::dir_deg(75.0, 300.0)});
        }
    return out;
}

// The closure of `p` through liboslexec at the sweep's frame (N and dPdu of the shading point).
struct ShadedClosure {
    osl::ShaderRunner::Group group;
    std::vector<osl::Component> components;
};
ShadedClosure shade(const Params& p) {
    ShadedClosure s{runner().group("retroprism_bsdf", shader_params(p)), {}};
    osl::ShadingPoint point;
    point.N = to_osl(kNormal);
    point.dPdu = to_osl(kTangent);
    s.components = runner().shade(s.group, point);
    return s;
}

} // namespace

TEST_CASE("oslc compiles the generated shader", "[osl]") {
    CHECK(oslc(kShaders / "retroprism_bsdf.osl", kShaders));
}

TEST_CASE("the closure through liboslexec equals the C++ node: eval, pdf and sample over the "
          "parameter corners",
          "[osl]") {
    const Frame frame = sweep_frame();
    const std::vector<DirectionPair> pairs = sweep_pairs();
    rptest::Rng rng(39);
    double worstF = 0, worstPdf = 0, worstSample = 0, worstDouble = 0, worstConsistency = 0;
    long evals = 0, samples = 0, otherSide = 0;
    for (const rptest::Corner& corner : rptest::parameter_corners()) {
        INFO(corner.name);
        const ShadedClosure s = shade(corner.params);
        const auto comps = retroprism_components(s.components);
        REQUIRE(comps.size() == 1);
        CHECK(from_osl(comps[0].weight) == dvec3(1.0));
        const osl::RetroprismBsdf bsdf(*static_cast<const osl::ClosureParams*>(comps[0].params));
        // The C++ node of the same inputs: the shader's float values, the shading point's frame.
        Params ref = rounded(corner.params);
        ref.normal = {float(kNormal.x), float(kNormal.y), float(kNormal.z)};
        ref.tangent = {float(kTangent.x), float(kTangent.y), float(kTangent.z)};
        const PrismaticRetroreflector<float> node(ref);
        const PrismaticRetroreflector<double> nodeDouble(ref);
        for (const DirectionPair& d : pairs) {
            const dvec3 view = to_world(frame, d.view), light = to_world(frame, d.light);
            const auto e = bsdf.eval(to_osl(view), to_osl(light));
            const glm::vec3 vf(view), lf(light);
            const dvec3 f(node.f(lf, vf).total());
            worstF = std::max(worstF, rel_diff(from_osl(e.f), f));
            const double pdf = node.pdf(vf, lf);
            worstPdf = std::max(worstPdf, rel_diff(dvec3(e.pdf), dvec3(pdf)));
            // Against the double node, where f is not negligible (float rounding of the lobes).
            const dvec3 fd = nodeDouble.f(light, view).total();
            if (std::max({fd.x, fd.y, fd.z}) > 1e-3)
                worstDouble = std::max(worstDouble, rel_diff(from_osl(e.f), fd));
            ++evals;
        }
        for (const DirectionPair& d : pairs) {
            const glm::vec3 view(to_world(frame, d.view));
            for (int k = 0; k < 2; ++k) {
                const glm::vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
                const auto got =
                    bsdf.sample(OSL::Vec3(view.x, view.y, view.z), OSL::Vec3(u.x, u.y, u.z));
                const auto want = node.sample(view, u);
                REQUIRE(got.has_value() == want.has_value());
                ++samples;
                if (!got) continue;
                CHECK(got->lobe == want->lobe);
                const double dir = glm::length(from_osl(got->light) - dvec3(want->wo));
                const dvec3 fWant(node.f(want->wo, view).total());
                worstSample = std::max({worstSample, dir, rel_diff(from_osl(got->f), fWant),
                                        rel_diff(dvec3(got->pdf), dvec3(want->pdf))});
                // The view side's eval at the sampled light gives the sample's pdf; the pdf of
                // the other side (the light as the node's incident direction) would not.
                const OSL::Vec3 v(view.x, view.y, view.z);
                const double pdfEval = bsdf.eval(v, got->light).pdf;
                const double pdfOtherSide = bsdf.eval(got->light, v).pdf;
                worstConsistency =
                    std::max(worstConsistency, rel_diff(dvec3(pdfEval), dvec3(got->pdf)));
                if (rel_diff(dvec3(pdfOtherSide), dvec3(got->pdf)) > kPdfTolerance) ++otherSide;
            }
        }
    }
    std::printf("MEASURED: retroprism_bsdf through liboslexec (OSL %s) vs the C++ float node: "
                "%zu corners, %ld eval/pdf pairs, %ld samples; worst relative f %.3g, pdf %.3g, "
                "sample (direction, f, pdf) %.3g; vs the double node where f > 1e-3: %.3g; "
                "eval's pdf at the sampled light vs the sample's: worst relative %.3g (the other "
                "side's pdf differs by more than %g for %ld samples)\n",
                OSL_LIBRARY_VERSION_STRING, rptest::parameter_corners().size(), evals, samples,
                worstF, worstPdf, worstSample, worstDouble, worstConsistency, kPdfTolerance,
                otherSide);
    // The closure runs the node's float core on the same material and frame (the shader's float
    // values, rp_make_frame in double rounded as the node rounds it): equal to an ulp or two.
    CHECK(worstF <= 1e-6);
    CHECK(worstPdf <= 1e-6);
    CHECK(worstSample <= 1e-6);
    CHECK(worstConsistency <= kPdfTolerance);
    CHECK(otherSide > samples / 10);
}

TEST_CASE("the closure's node is made once per material, whatever the shading frame", "[osl]") {
    // Closure parameters as a shader passes them: the sweep's corners through liboslexec.
    const std::vector<rptest::Corner> corners = rptest::parameter_corners();
    auto closure_of = [](const Params& p) {
        const ShadedClosure s = shade(p);
        const auto comps = retroprism_components(s.components);
        REQUIRE(comps.size() == 1);
        return *static_cast<const osl::ClosureParams*>(comps[0].params);
    };
    const osl::ClosureParams a = closure_of(corners[5].params);
    const osl::ClosureParams b = closure_of(corners[17].params);
    const auto nodeA = osl::material_node(a);
    CHECK(nodeA != osl::material_node(b));
    // Another frame, the same material: the same node, from the thread's last lookup and from
    // the shared table.
    osl::ClosureParams turned = a;
    turned.normal = OSL::Vec3(0.3f, 0.1f, 0.9f);
    turned.tangent = OSL::Vec3(0.0f, 1.0f, 0.0f);
    CHECK(osl::material_node(turned) == nodeA);
    CHECK(osl::material_node(b) != nodeA);
    CHECK(osl::material_node(turned) == nodeA);
    // Its values: the node of the material, in the shading point's frame.
    const osl::RetroprismBsdf bsdf(turned);
    CHECK(&bsdf.node() == nodeA.get());
    CHECK(bsdf.node().params().normal == Params().normal);
}

TEST_CASE("every input of the closure changes its value through liboslexec", "[osl]") {
    // A base where every input matters: metallised prisms in one orientation, with dihedral
    // errors, a cant, and diffraction at one wavelength with dispersion (the wavelength and the
    // Abbe number act only together or with a pitch); each input moved alone to another value.
    Params base;
    base.prism_reflection = 2;
    base.era_mode = 2;
    base.dihedral_error = 4.0;
    base.cant_angle = 5.0;
    base.prism_pitch = 100.0;
    base.abbe_number = 57.0;
    base.wavelength = 550.0;
    const Frame frame = sweep_frame();
    const std::vector<DirectionPair> pairs = sweep_pairs();
    auto values = [&](const Params& p) {
        const ShadedClosure s = shade(p);
        const auto comps = retroprism_components(s.components);
        REQUIRE(comps.size() == 1);
        const osl::RetroprismBsdf bsdf(*static_cast<const osl::ClosureParams*>(comps[0].params));
        std::vector<float> out;
        for (const DirectionPair& d : pairs) {
            const auto e =
                bsdf.eval(to_osl(to_world(frame, d.view)), to_osl(to_world(frame, d.light)));
            out.insert(out.end(), {e.f.x, e.f.y, e.f.z, e.pdf});
        }
        return out;
    };
    const std::vector<float> baseValues = values(base);
    int inputs = 0;
    for (const ParamInfo& info : param_table()) {
        if (info.type == ParamType::Vector) continue; // the frame: the sweep's own
        INFO(info.name);
        Params p = base;
        for_each_input(p, [&](const ParamInfo& i, auto& v) {
            if (std::string(i.name) != info.name) return;
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, double>)
                v = v == i.min_value + 0.37 * (i.max_value - i.min_value)
                        ? i.max_value
                        : i.min_value + 0.37 * (i.max_value - i.min_value);
            if constexpr (std::is_same_v<T, Color3>) v = {0.3, 0.5, 0.7};
            if constexpr (std::is_same_v<T, int>) v = (v + 1) % int(enum_values(i).size());
            if constexpr (std::is_same_v<T, bool>) v = !v;
        });
        CHECK(values(p) != baseValues);
        ++inputs;
    }
    std::printf("MEASURED: each of %d inputs (the frame aside) moved alone changes the closure's "
                "f or pdf through liboslexec\n",
                inputs);
}

namespace {

// The R_A of a group's closure rendered against the C++ R_A table of `material`, per channel
// at each entrance and observation angle: the worst relative difference.
double render_against_table(const osl::ShaderRunner::Group& group, const Params& material,
                            const std::vector<double>& observation,
                            const std::vector<double>& entrance, const std::string& label) {
    const RaTable table = ra_table(material, 0.0, observation, entrance);
    double worst = 0.0;
    for (size_t r = 0; r < observation.size(); ++r)
        for (size_t c = 0; c < entrance.size(); ++c) {
            const dvec3 rendered = osl::render_ra(runner(), group, entrance[c], observation[r]);
            const double d = rel_diff(rendered, table.rgb[r][c]);
            INFO(label << " entrance " << entrance[c] << " observation " << observation[r]
                       << ": rendered " << rendered.y << ", table " << table.rgb[r][c].y);
            CHECK(d <= 0.005);
            worst = std::max(worst, d);
        }
    return worst;
}

const std::vector<double> kObservation = {0.2, 0.33, 0.5, 1.0, 1.5, 2.0, 4.0};
const std::vector<double> kEntrance = {-4.0, 30.0};

} // namespace

TEST_CASE("a direct-lighting render of retroprism_bsdf.osl gives the C++ R_A table", "[osl]") {
    // The white material with dihedral errors of 6', and uncoated prisms in matched pairs with a
    // cant, random dihedral errors and the anisotropic lobe.
    Params white;
    white.dihedral_error = 6.0;
    Params tir;
    tir.prism_reflection = 1;
    tir.era_mode = 1;
    tir.cant_angle = 8.0;
    tir.dihedral_spread = 3.0;
    tir.retro_lobe = 1;
    // And the white material's prisms with a pitch of 150 um (diffraction at the colour
    // channels' wavelengths) in acrylic's dispersion.
    Params diffracting = white;
    diffracting.prism_pitch = 150.0;
    diffracting.abbe_number = 57.0;
    double worst = 0.0;
    for (const auto& [name, p] : {std::pair{"white", white}, std::pair{"tir", tir},
                                  std::pair{"diffracting", diffracting}}) {
        const osl::ShaderRunner::Group group = runner().group("retroprism_bsdf", shader_params(p));
        worst = std::max(worst, render_against_table(group, p, kObservation, kEntrance, name));
    }
    // Tolerance 0.5% (the issue's): the render differs from the table by the float closure and
    // by the scene's finite distance (observation varies by ~1e-3 of itself over the image).
    std::printf("MEASURED: R_A of a direct-lighting render through liboslexec vs the C++ R_A "
                "table: 3 materials, entrance -4 and 30 deg, observation 0.2-4 deg: worst "
                "relative difference %.3g\n",
                worst);
}

namespace {

// A graph document's shader (legend_sign.mtlx: the white sheeting and an Oren-Nayar film mixed
// through a texture, under a dielectric layer) run over a 16 x 16 grid of texture coordinates:
// at every point a layer of a dielectric over the film and the sheeting, whose weights sum to 1;
// the sheeting alone at some points, the film alone at others; the sheeting's closure that of
// white_sign.mtlx's inputs (the legend sign's sheeting, as its comment says) wherever it shows.
// No R_A: there is no C++ table of the layered sign. 1 when it ran.
int run_graph_document(const std::string& name, const fs::path& doc) {
    const osl::ShaderRunner::Group group = runner().group(name, {}, "out");
    const fs::path white = doc.parent_path() / "white_sign.mtlx";
    const MtlxDocument whiteDoc = read_mtlx(white.string());
    const Params sheet = rounded(whiteDoc.materials.front().params);
    const PrismaticRetroreflector<float> node(sheet);
    int sheetOnly = 0, filmOnly = 0;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
            osl::ShadingPoint point;
            point.u = (i + 0.5f) / 16.0f;
            point.v = (j + 0.5f) / 16.0f;
            double sheetWeight = 0.0, filmWeight = 0.0;
            int layers = 0, dielectrics = 0;
            for (const osl::Component& c : runner().shade(group, point)) {
                layers += c.id == osl::kLayerClosureId;
                dielectrics += c.id == osl::kDielectricClosureId;
                if (c.id == osl::kOrenNayarClosureId) filmWeight += c.weight.y;
                if (c.id != osl::kRetroprismClosureId) continue;
                sheetWeight += c.weight.y;
                const osl::RetroprismBsdf bsdf(*static_cast<const osl::ClosureParams*>(c.params));
                const glm::vec3 view = rptest::dir_deg(30.0, 0.0),
                                light = rptest::dir_deg(30.5, 0.0);
                const auto e = bsdf.eval(OSL::Vec3(view.x, view.y, view.z),
                                         OSL::Vec3(light.x, light.y, light.z));
                CHECK(rel_diff(from_osl(e.f), dvec3(node.f(light, view).total())) <= 1e-6);
            }
            CHECK(layers == 1);
            CHECK(dielectrics == 1);
            CHECK(std::abs(sheetWeight + filmWeight - 1.0) <= 1e-6);
            sheetOnly += sheetWeight == 1.0;
            filmOnly += filmWeight == 1.0;
        }
    std::printf("MEASURED: %s through liboslexec over 256 texture coordinates: the sheeting alone "
                "at %d, the film alone at %d, weights summing to 1 at all\n",
                doc.filename().string().c_str(), sheetOnly, filmOnly);
    CHECK(sheetOnly > 0);
    CHECK(filmOnly > 0);
    return 1;
}

} // namespace

TEST_CASE("MaterialX's OSL with the opt-in closure library compiles and renders the bundled "
          "documents as the C++ R_A table",
          "[osl]") {
    const fs::path root = RP_SOURCE_DIR;
    const fs::path out =
        fs::temp_directory_path() / ("retroprism_test_osl_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const fs::path includes = out / "include";
    const std::string mx = "node " + (root / "materialx" / "tools" / "mx.cjs").string();
    const rptest::CommandRun inc = rptest::run_command(mx + " osl-includes " + includes.string());
    INFO(inc.output);
    REQUIRE(inc.status == 0);
    const ColorConverter convert = ocio_color_converter();
    int documents = 0, compiled = 0, rendered = 0, graphs = 0;
    double worst = 0.0;
    for (const char* folder : {"examples/documents", "materialx/examples"}) {
        std::string list;
        std::vector<fs::path> docs;
        for (const auto& e : fs::directory_iterator(root / folder))
            if (e.path().extension() == ".mtlx") docs.push_back(e.path());
        std::sort(docs.begin(), docs.end());
        for (const fs::path& doc : docs)
            list += " " + doc.string();
        // One run per folder (MaterialX names the files after the materials, unique in each).
        const fs::path dir = out / fs::path(folder).filename();
        const rptest::CommandRun gen = rptest::run_command(
            mx + " generate --osl-closure --targets osl" + list + " " + dir.string());
        INFO(gen.output);
        REQUIRE(gen.status == 0);
        for (const fs::path& doc : docs) {
            ++documents;
            const MtlxOutline outline = outline_mtlx(doc.string());
            for (const std::string& material : outline.materials) {
                INFO(doc.string() << ": " << material);
                const std::string name = dir.filename().string() + "_" + material;
                const std::string source = read_text(dir / (material + ".osl"));
                // MaterialX names the shader after the material; loaded under a name of its own.
                REQUIRE_NOTHROW(runner().compile(name, source, {includes.string()}));
                CHECK(oslc(dir / (material + ".osl"), includes));
                ++compiled;
                if (outline.graph()) {
                    runner().set_texture_searchpath(doc.parent_path().string());
                    graphs += run_graph_document(name, doc);
                    continue;
                }
                const MtlxDocument d = read_mtlx(doc.string());
                const Params p = to_working_space(d, select_material(d, material), convert);
                const osl::ShaderRunner::Group group = runner().group(name, {}, "out");
                const std::vector<double> obs = {0.5, 1.0, 1.5, 2.0, 4.0};
                worst = std::max(worst, render_against_table(group, p, obs, kEntrance, name));
                ++rendered;
            }
        }
    }
    fs::remove_all(out);
    std::printf(
        "MEASURED: MaterialX 1.39.4's OSL with rp_pbrlib_closure: %d materials of %d "
        "documents compiled by oslc and liboslcomp (OSL %s); %d rendered vs the C++ R_A table at "
        "entrance -4 and 30 deg, observation 0.5-4 deg: worst relative difference %.3g; "
        "%d graph run over its texture\n",
        compiled, documents, OSL_LIBRARY_VERSION_STRING, rendered, worst, graphs);
    CHECK(rendered > 0);
    CHECK(graphs > 0);
}
