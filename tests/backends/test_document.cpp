// [document]: MaterialX documents beyond the node's chain (layers, mixes, textures) rendered
// through the GLSL real MaterialX 1.39.4 generates (backends/mx_night.h), in the night scene of
// the reference renderer: the regions an image mask separates differ as the document's inputs
// say; on a document the reference renderer reads, MaterialX's path and the C++ path agree per
// pixel; bad documents give errors naming the element and the file. Each shader is compiled
// once (about 30 s on llvmpipe) and shared by the test cases.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <map>
#include <sstream>

#include <unistd.h>

#include "check.h"
#include "color.h"
#include "error.h"
#include "mtlx_reader.h"
#include "mx_night.h"
#include "night_scene.h"
#include "paths.h"
#include "test_support.h"

using namespace retroprism;
namespace fs = std::filesystem;

namespace {

const fs::path kRoot = RP_SOURCE_DIR;
const fs::path kLayered = kRoot / "tests" / "data" / "documents" / "layered_mask.mtlx";
const fs::path kWhite = kRoot / "examples" / "documents" / "white_sign.mtlx";

// A small frame: the sign covers about 1,500 fully covered pixels.
NightSettings small_settings() {
    NightSettings s;
    s.width = 192;
    s.height = 108;
    s.spp = 2;
    return s;
}

// One renderer per document for the whole binary: each compiles its shader once.
gl::MxNightRenderer& renderer(const fs::path& doc) {
    static std::map<std::string, std::unique_ptr<gl::MxNightRenderer>> cache;
    auto& r = cache[doc.string()];
    if (!r)
        r = std::make_unique<gl::MxNightRenderer>(
            gl::generate_mx_material(RP_SOURCE_DIR, doc.string(), ""));
    return *r;
}

// The pixels whose centre ray hits the sign, fully covered, with the sign's texture
// coordinate v at the centre (0 at the bottom corner, 1 at the top).
struct SignPixel {
    size_t index;
    double v;
    double irradianceCos; // I cos(theta_i) / d^2 of the headlight at the centre's hit
};
std::vector<SignPixel> sign_pixels(const NightImage& img, const NightSettings& st) {
    const NightScene scene = build_night_scene(st);
    std::vector<SignPixel> out;
    for (int y = 0; y < st.height; ++y)
        for (int x = 0; x < st.width; ++x) {
            const size_t i = size_t(y) * size_t(st.width) + size_t(x);
            if (img.alpha[i] < 1.0f) continue;
            NightHit h;
            const glm::dvec3 d = scene.ray((x + 0.5) / st.width, (y + 0.5) / st.height);
            if (!scene.trace(scene.eye, d, h) || h.object != kNightSign) continue;
            const double b = glm::dot(h.p - scene.sign.c, scene.sign.v);
            const glm::dvec3 toL = scene.lights[0].position - h.p;
            const double d2 = glm::dot(toL, toL);
            const double cosI = glm::dot(toL, scene.sign.n) / std::sqrt(d2);
            out.push_back({i, 0.5 * (b / scene.sign.halfDiagonal + 1),
                           scene.lights[0].intensity * cosI / d2});
        }
    return out;
}

double luminance(const std::vector<std::vector<float>*>& layers, size_t i) {
    double y = 0;
    const double w[3] = {0.2126, 0.7152, 0.0722};
    for (const std::vector<float>* l : layers)
        if (!l->empty())
            for (size_t c = 0; c < 3; ++c)
                y += w[c] * (*l)[3 * i + c];
    return y;
}

std::vector<std::vector<float>*> all_layers(NightImage& img) {
    return {&img.surface, &img.retro, &img.diffuse, &img.other};
}

} // namespace

TEST_CASE("a layered, mixed and textured document renders, its mask's regions as the inputs say",
          "[document]") {
    const NightSettings st = small_settings();
    gl::MxNightRenderer& r = renderer(kLayered);
    REQUIRE(r.lobes());
    NightImage img = r.render(st);
    REQUIRE(img.anomalies == 0);
    // The node alone, as the reference renders it: the layered document's sheeting inputs are
    // those of white_sign.mtlx.
    NightImage ref = render_night(document_params(kWhite.string(), ""), st);
    const std::vector<SignPixel> pixels = sign_pixels(img, st);
    double filmSum = 0, filmLambert = 0, coatedSum = 0, bareSum = 0, filmRetro = 0;
    double coatedRetro = 0;
    int film = 0, coated = 0;
    for (const SignPixel& p : pixels) {
        const double y = luminance(all_layers(img), p.index);
        // Texels are 1/64 wide and filtered linearly: 0.05 keeps a pixel's samples off the
        // edge between the mask's halves.
        if (p.v > 0.55) {
            ++film;
            filmSum += y;
            filmLambert += 0.04 / M_PI * p.irradianceCos;
            filmRetro += luminance({&img.retro}, p.index);
        } else if (p.v < 0.45) {
            ++coated;
            coatedSum += y;
            coatedRetro += luminance({&img.retro}, p.index);
            bareSum += luminance(all_layers(ref), p.index);
        }
    }
    INFO("film pixels " << film << ", coated pixels " << coated);
    REQUIRE(film > 300);
    REQUIRE(coated > 300);
    const double filmRatio = filmSum / filmLambert, coatRatio = coatedSum / bareSum;
    std::printf("MEASURED: layered_mask, sign: film region (mask 1) / Lambert 0.04/pi E cos = "
                "%.4f; coated region (mask 0) / the bare node (C++ reference) = %.4f; the film "
                "region's retro layer %.3g (the coated region's %.3g)\n",
                filmRatio, coatRatio, filmRetro, coatedRetro);
    // Where the mask is 1 the mix is the film alone: MaterialX's oren_nayar_diffuse_bsdf
    // (sigma = roughness 0.3: A = 0.893, B = 0.225) at this near-retro geometry is
    // A + B s / max(cos), s = L.V - cos_i cos_o = 0.04 to 0.10 over the sign (entrance 11 to
    // 19 degrees, observation 0.5): 0.902 to 0.916 of Lambert's 0.04 / pi; 0.01 either side
    // for the illuminance's variation within a pixel (Lambert's value is the pixel centre's).
    CHECK(filmRatio > 0.89);
    CHECK(filmRatio < 0.93);
    // There the node's retro lobe is mixed away: what remains is the GPU's mix() rounding
    // (bg + (fg - bg) m with m = 1 leaves a float ulp of bg, 2^-24 relative).
    CHECK(filmRetro < 1e-6 * coatedRetro);
    // Where the mask is 0 the node is under the coat: MaterialX's layer passes it times the
    // coat's throughput 1 - E(V), E the dielectric's directional albedo: Fresnel's
    // F0 = 0.04 for ior 1.5 (Schlick adds < 1e-5 at these view angles, under 25 degrees)
    // with GGX roughness 0.1's albedo near it: 0.96 +- 0.01; the coat's own reflection at the
    // retro direction (30 degrees from its mirror direction) is negligible.
    CHECK(coatRatio > 0.95);
    CHECK(coatRatio < 0.97);
}

namespace {

// Per-value relative errors |x - r| / max(|r|, 1e-6 peak) (the contract's floor) of MaterialX's
// layers against the reference's, over the fully covered pixels whose centre ray hits
// `object`, sorted.
std::vector<double> layer_errors(const NightImage& mx, const NightImage& ref,
                                 const NightSettings& st, int object) {
    const NightScene scene = build_night_scene(st);
    const std::vector<float>* mxLayers[3] = {&mx.surface, &mx.retro, &mx.diffuse};
    const std::vector<float>* refLayers[3] = {&ref.surface, &ref.retro, &ref.diffuse};
    std::vector<double> errs;
    for (int l = 0; l < 3; ++l) {
        const double peak = *std::max_element(refLayers[l]->begin(), refLayers[l]->end());
        for (int y = 0; y < st.height; ++y)
            for (int x = 0; x < st.width; ++x) {
                const size_t i = size_t(y) * size_t(st.width) + size_t(x);
                NightHit h;
                if (mx.alpha[i] < 1 || ref.alpha[i] < 1 ||
                    !scene.trace(scene.eye, scene.ray((x + 0.5) / st.width, (y + 0.5) / st.height),
                                 h) ||
                    h.object != object)
                    continue;
                for (size_t c = 0; c < 3; ++c) {
                    const double a = (*mxLayers[l])[3 * i + c], b = (*refLayers[l])[3 * i + c];
                    errs.push_back(std::abs(a - b) / std::max(std::abs(b), 1e-6 * peak));
                }
            }
    }
    std::sort(errs.begin(), errs.end());
    return errs;
}

double quantile(const std::vector<double>& sorted, double q) {
    return sorted[std::min(sorted.size() - 1, size_t(q * double(sorted.size())))];
}

} // namespace

TEST_CASE("on a document the reference reads, MaterialX's path and the C++ path agree per pixel",
          "[document]") {
    const NightSettings st = small_settings();
    gl::MxNightRenderer& r = renderer(kWhite);
    REQUIRE(r.lobes());
    const NightImage mx = r.render(st);
    const NightImage ref = render_night(document_params(kWhite.string(), ""), st);
    REQUIRE(mx.anomalies == 0);
    // The node's chain alone: no rest of a graph.
    REQUIRE(mx.other.empty());
    // Both sample each pixel at the same spp x spp points (the render target's pixel centres
    // are the reference's stratified rays), so the same samples hit.
    CHECK(mx.alpha == ref.alpha);
    const std::vector<double> sign = layer_errors(mx, ref, st, kNightSign);
    const std::vector<double> sphere = layer_errors(mx, ref, st, kNightSphere);
    REQUIRE(sign.size() > 3000);
    REQUIRE(sphere.size() > 3000);
    std::printf("MEASURED: MaterialX's path vs the reference, white_sign, %dx%d, %d samples per "
                "pixel: sign %zu values, median %.2e, max %.2e; sphere %zu values, median "
                "%.2e, 99%% %.2e, max %.2e\n",
                st.width, st.height, st.spp * st.spp, sign.size(), quantile(sign, 0.5), sign.back(),
                sphere.size(), quantile(sphere, 0.5), quantile(sphere, 0.99), sphere.back());
    // The sign is flat and drawn exactly: its samples see the same directions to float
    // rounding, and the tolerance contract (backends/check.h) holds per value of a pixel.
    const ToleranceContract contract;
    const long signOver =
        long(sign.end() - std::upper_bound(sign.begin(), sign.end(), contract.per_sample));
    CHECK(double(signOver) <= contract.allowed_fraction * double(sign.size()));
    CHECK(sign.back() <= contract.hard_max);
    // The sphere is a 512 x 256 mesh: its interpolated normals and tangents, and its flat
    // triangles' points (up to 9.4e-6 m inside the sphere, more along a grazing ray), are not
    // the sphere's, and the matched-pair ERA's pattern on it has sharp edges (where a prism
    // face's total internal reflection starts) that a small shift moves across a pixel. The
    // image tolerance: the median value within the contract's per-value 1e-4, 99% within its
    // hard maximum 1e-2, none beyond 5% (halving the mesh's step divided these by 3.5 to 4:
    // they are the mesh's).
    CHECK(quantile(sphere, 0.5) <= contract.per_sample);
    CHECK(quantile(sphere, 0.99) <= contract.hard_max);
    CHECK(sphere.back() <= 0.05);
}

namespace {

// layered_mask.mtlx with `from` replaced by `to`, written as NAME.mtlx into a temporary folder
// (beside nothing: its texture is not found there unless the test copies it).
fs::path variant(const std::string& name, const std::string& from, const std::string& to) {
    std::ifstream in(kLayered);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const size_t at = text.find(from);
    if (at == std::string::npos) throw std::logic_error("variant: no " + from);
    text.replace(at, from.size(), to);
    const fs::path dir =
        fs::temp_directory_path() / ("retroprism_document_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path f = dir / (name + ".mtlx");
    std::ofstream(f) << text;
    return f;
}

// The InputError generate_mx_material (then load_mx_textures) throws for `doc`; "" when none.
std::string document_error(const fs::path& doc) {
    try {
        const gl::MxMaterial m = gl::generate_mx_material(RP_SOURCE_DIR, doc.string(), "");
        (void)gl::load_mx_textures(m);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("bad documents: MaterialX's errors name the element and the file", "[document]") {
    SECTION("a missing texture file") {
        const fs::path doc = variant("missing", "value=\"mask.png\"", "value=\"no_such_mask.png\"");
        const std::string e = document_error(doc);
        INFO(e);
        CHECK(rptest::contains(e, doc.string()));
        CHECK(rptest::contains(e, "<image name=\"legend_mask\"> input file: no_such_mask.png"));
        CHECK(rptest::contains(e, "no such file"));
    }
    SECTION("an unknown node") {
        const fs::path doc =
            variant("unknown", "<oren_nayar_diffuse_bsdf name=\"film\" type=\"BSDF\">",
                    "<oren_nayar_bsdf name=\"film\" type=\"BSDF\">");
        // The closing tag must match for the XML to be well-formed.
        std::ifstream in(doc);
        std::stringstream ss;
        ss << in.rdbuf();
        std::string text = ss.str();
        text.replace(text.find("</oren_nayar_diffuse_bsdf>"), 26, "</oren_nayar_bsdf>");
        std::ofstream(doc) << text;
        const std::string e = document_error(doc);
        INFO(e);
        CHECK(rptest::contains(e, doc.string() + ": error: <oren_nayar_bsdf name=\"film\">: "
                                                 "unknown node category 'oren_nayar_bsdf'"));
    }
    SECTION("a cycle") {
        const fs::path doc = variant("cycle", "nodename=\"sheeting\"", "nodename=\"legend\"");
        const std::string e = document_error(doc);
        INFO(e);
        CHECK(rptest::contains(e, doc.string()));
        CHECK(rptest::contains(e, "Encountered cycle at element: <mix name=\"legend\""));
    }
    SECTION("a type mismatch") {
        const fs::path doc = variant("mismatch", "<input name=\"mix\" type=\"float\"",
                                     "<input name=\"mix\" type=\"color3\"");
        const std::string e = document_error(doc);
        INFO(e);
        CHECK(rptest::contains(
            e, doc.string() + ": error: <mix name=\"legend\">: no nodedef of 'mix' matches"));
        CHECK(rptest::contains(e, "Mismatched types in port connection: <input name=\"mix\" "
                                  "type=\"color3\" nodename=\"legend_mask\">"));
    }
    SECTION("render and ra --document name the problem; nothing is written") {
        const fs::path doc =
            variant("missing_cli", "value=\"mask.png\"", "value=\"no_such_mask.png\"");
        const fs::path out = doc.parent_path() / "out.exr";
        const rptest::CommandRun render =
            rptest::run_cli("render " + doc.string() + " -o " + out.string());
        INFO(render.output);
        CHECK(render.status != 0);
        CHECK(rptest::contains(render.output,
                               "<image name=\"legend_mask\"> input file: no_such_mask.png"));
        CHECK_FALSE(fs::exists(out));
        CHECK_FALSE(fs::exists(doc.parent_path() / "out.png"));
        const rptest::CommandRun ra = rptest::run_cli("ra --document " + kLayered.string());
        INFO(ra.output);
        CHECK(ra.status != 0);
        CHECK(rptest::contains(ra.output, kLayered.string() +
                                              ": a MaterialX graph (nodes image, dielectric_bsdf, "
                                              "layer, oren_nayar_diffuse_bsdf, mix)"));
    }
    std::error_code ec;
    fs::remove_all(
        fs::temp_directory_path() / ("retroprism_document_" + std::to_string(::getpid())), ec);
}
