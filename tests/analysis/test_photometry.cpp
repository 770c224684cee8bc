// [photometry]: the R_A table against direct evaluation and its angle conventions; the
// MaterialX reader (exact parameters, every error naming the element and its line); the ALTA
// reader (errors naming file:line, files without #PARAM_OUT); the fitter recovering known
// parameters of both models from synthetic data, the sheeting geometry (cant_angle,
// dihedral_error) included, never fitting worse than with the paper's geometry, and
// deterministic; the R_A table reader (every error naming
// file:line and the expected form) and the R_A fit recovering the fittable inputs; `retroprism
// ra`, `fit --json`, `fit --ra` and `render` end to end (no output on a bad input); a sign's
// luminance on approach.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "alta_reader.h"
#include "approach.h"
#include "baselines.h"
#include "fitting.h"
#include "mtlx_reader.h"
#include "night_render.h"
#include "photometry.h"
#include "photopic.h"
#include "query.h"
#include "ra_fit.h"
#include "ra_table.h"
#include "standards.h"
#include "test_support.h"

using namespace retroprism;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = M_PI / 180.0;

using Run = rptest::CommandRun;
using rptest::contains;
const auto& run = rptest::run_command;
const auto& cli = rptest::run_cli;

// A fresh empty folder under the temporary directory.
fs::path temp_dir(const std::string& name) {
    const fs::path d =
        fs::temp_directory_path() / ("retroprism_photometry_" + name + std::to_string(getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string source(const std::string& rel) {
    return std::string(RP_SOURCE_DIR) + "/" + rel;
}

// ---------------------------------------------------------------------------------------------
// MaterialX documents built line by line, so that the expected line numbers are known.

struct Doc {
    std::vector<std::string> lines;
    std::string text() const {
        std::string t;
        for (const std::string& l : lines)
            t += l + "\n";
        return t;
    }
    // 1-based line of the first line containing `marker`.
    int line_of(const std::string& marker) const {
        for (size_t i = 0; i < lines.size(); ++i)
            if (contains(lines[i], marker)) return int(i) + 1;
        FAIL("marker not in the document: " << marker);
        return 0;
    }
    void replace(const std::string& from, const std::string& to) {
        for (std::string& l : lines) {
            const size_t at = l.find(from);
            if (at != std::string::npos) {
                l.replace(at, from.size(), to);
                return;
            }
        }
        FAIL("not in the document: " << from);
    }
    void insert_after(const std::string& marker, const std::string& line) {
        const int at = line_of(marker);
        lines.insert(lines.begin() + at, line);
    }
};

Doc valid_doc() {
    return Doc{{
        R"(<?xml version="1.0"?>)",
        R"(<materialx version="1.39">)",
        R"(  <rp_prismatic_retroreflector_bsdf name="sheet_bsdf" type="BSDF">)",
        R"(    <input name="roughness" type="float" value="0.07"/>)",
        R"(    <input name="ior" type="float" value="1.586"/>)",
        R"(    <input name="diffuse_color" type="color3" value="0.8, 0.6, 0.05"/>)",
        R"(    <input name="retro_color" type="color3" value="1, 0.75,0.08" colorspace="srgb_texture"/>)",
        R"(    <input name="specular" type="float" value="0.5"/>)",
        R"(    <input name="prism_reflection" type="integer" value="2"/>)",
        R"(    <input name="metal_reflectance" type="float" value="0.9"/>)",
        // An enum as its name (type="string"): the form of documents written before the
        // node's enums were integer enums, still read.
        R"(    <input name="era_mode" type="string" value="oriented"/>)",
        R"(    <input name="orientation" type="float" value="30"/>)",
        R"(    <input name="cant_angle" type="float" value="-12.5"/>)",
        R"(    <input name="retro_lobe" type="integer" value="1"/>)",
        R"(    <input name="reciprocal" type="boolean" value="true"/>)",
        R"(    <input name="weight" type="float" value="0.75"/>)",
        R"(    <input name="normal" type="vector3" value="0, 0, 1"/>)",
        R"(  </rp_prismatic_retroreflector_bsdf>)",
        R"(  <surface name="sheet_surface" type="surfaceshader">)",
        R"(    <input name="bsdf" type="BSDF" nodename="sheet_bsdf"/>)",
        R"(  </surface>)",
        R"(  <surfacematerial name="yellow_sign" type="material">)",
        R"(    <input name="surfaceshader" type="surfaceshader" nodename="sheet_surface"/>)",
        R"(  </surfacematerial>)",
        R"(</materialx>)",
    }};
}

std::string parse_error(const Doc& d) {
    try {
        parse_mtlx(d.text(), "doc.mtlx");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

// ---------------------------------------------------------------------------------------------
// Synthetic measurements.

// theta_l 15, 30, 60 degrees; in-plane every 2.5 degrees, 0.25 degrees within 3 degrees of the
// retro and mirror directions, and five off-plane azimuths every 5 degrees of theta_v.
FitData synthetic_geometry() {
    FitData d;
    d.file = "synthetic";
    for (double tl : {15.0, 30.0, 60.0}) {
        auto add = [&](double thetaV, double phi) {
            const double t = thetaV * kDeg, p = phi * kDeg;
            add_sample(
                d, tl * kDeg,
                glm::dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)), 0.0);
        };
        for (double s = -85.0; s <= 85.0; s += 2.5)
            add(std::abs(s), s < 0 ? 180.0 : 0.0);
        for (double peak : {tl, -tl})
            for (double s = peak - 3.0; s <= peak + 3.0; s += 0.25)
                add(std::abs(s), s < 0 ? 180.0 : 0.0);
        for (double phi : {30.0, 60.0, 90.0, 120.0, 150.0})
            for (double tv = 5.0; tv <= 85.0; tv += 5.0)
                add(tv, phi);
    }
    return d;
}

// The node's fit inputs of the synthetic fits: uncoated prisms (tir), ior 1.55, specular 0.7,
// retro_color 0.6, diffuse_color 0.5, the paper's geometry, and `roughness`.
NodeFitParams synthetic_truth(double roughness) {
    return {roughness, 1.55, 0.7, 0.6, 0.5, 1};
}

// A fit to synthetic_fit_data(truth) recovers truth. Tolerances (no noise): 1% on roughness and
// ior; 0.3 degrees of cant and 0.3 arcminutes of dihedral error (1% of their RP_FIT ranges); 0.01
// on the weights and colours.
void check_recovered(const NodeFit& f, const NodeFitParams& truth) {
    CHECK(f.params.prism_reflection == truth.prism_reflection);
    CHECK(f.params.roughness == Approx(truth.roughness).epsilon(0.01));
    CHECK(f.params.ior == Approx(truth.ior).epsilon(0.01));
    CHECK(f.params.cant_angle == Approx(truth.cant_angle).margin(0.3));
    CHECK(f.params.dihedral_error == Approx(truth.dihedral_error).margin(0.3));
    CHECK(f.params.specular == Approx(truth.specular).margin(0.01));
    CHECK(f.params.retro == Approx(truth.retro).margin(0.01));
    CHECK(f.params.diffuse == Approx(truth.diffuse).margin(0.01));
    CHECK(f.report.log_rms < 1e-3);
}

// The fit f of d with o is deterministic, whatever the number of threads: the same bits again
// with one thread.
void check_deterministic(const NodeFit& f, const FitData& d, const FitOptions& o) {
    FitOptions one = o;
    one.threads = 1;
    const NodeFit g = fit_node(d, one);
    CHECK(g.params.roughness == f.params.roughness);
    CHECK(g.params.ior == f.params.ior);
    CHECK(g.params.cant_angle == f.params.cant_angle);
    CHECK(g.params.dihedral_error == f.params.dihedral_error);
    CHECK(g.params.specular == f.params.specular);
    CHECK(g.params.retro == f.params.retro);
    CHECK(g.params.diffuse == f.params.diffuse);
    CHECK(g.report.objective == f.report.objective);
}

// synthetic_geometry()'s samples with the values of `truth` (blurred as `o` says).
FitData synthetic_fit_data(const NodeFitParams& truth, const FitOptions& o) {
    FitData d = synthetic_geometry();
    const std::vector<double> v = node_values(truth, d, o);
    for (size_t i = 0; i < v.size(); ++i)
        d.samples[i].value = v[i];
    return d;
}

} // namespace

// =============================================================================================
// R_A

TEST_CASE("R_A table: f cos(theta_i) cos(theta_o) at the standard angles", "[photometry]") {
    REQUIRE(ra_observation_angles() == std::vector<double>{0.2, 0.33, 0.5, 1.0, 1.5});
    REQUIRE(ra_entrance_angles() == std::vector<double>{-4, 15, 30, 40, 45});
    Params p;
    p.prism_reflection = 1; // tir
    p.diffuse_color = {0.8, 0.6, 0.05};
    p.retro_color = {1.0, 0.75, 0.08};
    const RaTable t = ra_table(p, 0.0);
    // The node as ra_table makes it (integrating its azimuth averages: a table's few dozen
    // directions do not pay for the series, whose values agree within 1e-6 relative).
    const PrismaticRetroreflector<double> node(
        p, PrismaticRetroreflector<double>::Averages::Integrated);
    for (size_t r = 0; r < t.observation.size(); ++r)
        for (size_t c = 0; c < t.entrance.size(); ++c) {
            const double a = t.observation[r], b = t.entrance[c];
            // Independently: the light in the x-z plane at beta, the observer alpha closer to
            // the normal (beta > 0) or farther from it (beta < 0).
            const glm::dvec3 wi(std::sin(b * kDeg), 0, std::cos(b * kDeg));
            const glm::dvec3 wo(std::sin((b - a) * kDeg), 0, std::cos((b - a) * kDeg));
            const glm::dvec3 expect = node.eval(wi, wo).f.total() * wi.z * wo.z;
            for (int k = 0; k < 3; ++k)
                CHECK(t.rgb[r][c][k] == Approx(expect[k]).epsilon(1e-12));
            // The geometry: observation angle alpha between the two, entrance |beta|.
            glm::dvec3 dwi, dwo;
            ra_directions(b, a, 0.0, dwi, dwo);
            CHECK(std::acos(std::clamp(glm::dot(dwi, dwo), -1.0, 1.0)) / kDeg ==
                  Approx(a).epsilon(1e-6));
            CHECK(std::acos(dwi.z) / kDeg == Approx(std::abs(b)).epsilon(1e-9));
        }
    // Luminance: Rec. 709 weights.
    CHECK(luminance_709({1, 0, 0}) == 0.2126);
    CHECK(luminance_709({0, 1, 0}) == 0.7152);
    CHECK(luminance_709({0, 0, 1}) == 0.0722);
    // Retroreflection dominates: R_A falls with observation and (tir) entrance angle.
    for (size_t c = 0; c < t.entrance.size(); ++c)
        for (size_t r = 1; r < t.observation.size(); ++r)
            CHECK(luminance_709(t.rgb[r][c]) < luminance_709(t.rgb[r - 1][c]));
    CHECK(luminance_709(t.rgb[0][4]) < 0.3 * luminance_709(t.rgb[0][1]));
}

TEST_CASE("R_A: -4 and +4 degrees agree for the isotropic modes; rotation matters when "
          "oriented",
          "[photometry]") {
    // averaged: the retro lobe is symmetric about wi, so -4 and +4 degrees agree. The observer's
    // side differs (theta_o = 3.8 vs 4.2 degrees at alpha = 0.2): the surface lobe sees it (at
    // -4 degrees the observer is farther from the mirror direction, which is why specifications
    // use -4), and T(cos theta_o) and G1(wo) barely do.
    double worstRetro = 0, worstTotal = 0;
    for (int mode : {0, 1, 2}) {
        Params p;
        p.prism_reflection = mode;
        const PrismaticRetroreflector<double> node(ra_params(p));
        for (double a : ra_observation_angles()) {
            glm::dvec3 wiM, woM, wiP, woP;
            ra_directions(-4.0, a, 0.0, wiM, woM);
            ra_directions(4.0, a, 0.0, wiP, woP);
            const auto eM = node.eval(wiM, woM).f, eP = node.eval(wiP, woP).f;
            const double retroRel =
                std::abs(eM.retro.x * wiM.z * woM.z / (eP.retro.x * wiP.z * woP.z) - 1.0);
            const double totalRel = std::abs(luminance_709(ra_value(node, -4.0, a, 0.0)) /
                                                 luminance_709(ra_value(node, 4.0, a, 0.0)) -
                                             1.0);
            worstRetro = std::max(worstRetro, retroRel);
            worstTotal = std::max(worstTotal, totalRel);
            CHECK(retroRel < 1e-5);
            CHECK(totalRel < 5e-3);
            // The rotation does not matter to the averaged mode.
            CHECK(luminance_709(ra_value(node, 45.0, a, 47.0)) ==
                  Approx(luminance_709(ra_value(node, 45.0, a, 0.0))).epsilon(1e-12));
        }
    }
    std::printf("MEASURED: R_A(-4) vs R_A(+4), averaged era_mode: retro lobe %.2e, total %.2e "
                "(relative)\n",
                worstRetro, worstTotal);

    // oriented: period 120 degrees in epsilon, and a real dependence on it once the refracted
    // ray is steeper than 19.47 degrees (beta = 45: theta_t = 28.3 degrees for eta = 1.49).
    Params o;
    o.era_mode = 2;
    const PrismaticRetroreflector<double> oriented(ra_params(o));
    double lo = 1e300, hi = 0;
    for (double e = 0; e < 120; e += 5) {
        const double v = luminance_709(ra_value(oriented, 45.0, 0.2, e));
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        CHECK(v == Approx(luminance_709(ra_value(oriented, 45.0, 0.2, e + 120.0))).epsilon(1e-9));
    }
    CHECK(hi > 1.15 * lo);
    std::printf("MEASURED: oriented prisms, beta = 45, alpha = 0.2 deg: R_A from %.2f to %.2f "
                "over epsilon\n",
                lo, hi);
    // matched pair: period 180 degrees, and epsilon is the same as turning the prisms.
    Params m;
    m.era_mode = 1;
    const PrismaticRetroreflector<double> pair(ra_params(m));
    Params turned = m;
    turned.orientation = 25.0;
    const PrismaticRetroreflector<double> pairTurned(ra_params(turned));
    CHECK(luminance_709(ra_value(pair, 45.0, 0.5, 25.0)) ==
          Approx(luminance_709(ra_value(pair, 45.0, 0.5, 205.0))).epsilon(1e-9));
    CHECK(luminance_709(ra_value(pair, 45.0, 0.5, 25.0)) ==
          Approx(luminance_709(ra_value(pairTurned, 45.0, 0.5, 0.0))).epsilon(1e-9));
    CHECK(luminance_709(ra_value(pair, 45.0, 0.5, 25.0)) !=
          Approx(luminance_709(ra_value(pair, 45.0, 0.5, 55.0))).epsilon(1e-3));
    // The material's own normal and tangent are not used for R_A.
    Params tilted = o;
    tilted.normal = {0.0, 1.0, 0.0};
    CHECK(ra_table(tilted, 10.0).rgb == ra_table(o, 10.0).rgb);
}

TEST_CASE("retroprism ra: text and CSV answer the library's table", "[photometry]") {
    Run r =
        cli("ra --csv --rotation 10 --material " + source("examples/materials/white_sign.json"));
    REQUIRE(r.status == 0);
    const Params p = params_from_json(read_json(source("examples/materials/white_sign.json")), "");
    const RaTable t = ra_table(p, 10.0);
    std::istringstream in(r.output);
    std::string line;
    std::getline(in, line);
    CHECK(line == "observation_deg,entrance_deg,rotation_deg,R_A_Y,R_A_R,R_A_G,R_A_B");
    int rows = 0;
    for (size_t i = 0; i < t.observation.size(); ++i)
        for (size_t j = 0; j < t.entrance.size(); ++j) {
            REQUIRE(std::getline(in, line));
            double v[7];
            char comma;
            std::istringstream ls(line);
            ls >> v[0];
            for (int k = 1; k < 7; ++k)
                ls >> comma >> v[k];
            CHECK(v[0] == t.observation[i]);
            CHECK(v[1] == t.entrance[j]);
            CHECK(v[2] == 10.0);
            CHECK(v[3] == Approx(luminance_709(t.rgb[i][j])).epsilon(1e-8));
            for (int k = 0; k < 3; ++k)
                CHECK(v[4 + k] == Approx(t.rgb[i][j][k]).epsilon(1e-8));
            ++rows;
        }
    CHECK(rows == 25);
    // The bundled document holds the same inputs as the JSON material: the same table.
    Run doc =
        cli("ra --csv --rotation 10 --document " + source("examples/documents/white_sign.mtlx"));
    REQUIRE(doc.status == 0);
    CHECK(doc.output == r.output);
    Run text = cli("ra --document " + source("examples/documents/white_sign.mtlx"));
    REQUIRE(text.status == 0);
    CHECK(contains(text.output, "R_A [cd lx^-1 m^-2] of material \"white_sign\""));
    CHECK(contains(text.output, "alpha \\ beta"));

    Run both = cli("ra --material a.json --document b.mtlx");
    CHECK(both.status != 0);
    CHECK(contains(both.output, "either --material FILE.json or --document DOC.mtlx"));
    Run rot = cli("ra --rotation ten");
    CHECK(rot.status != 0);
    CHECK(contains(rot.output, "--rotation ten: expected a finite number"));
}

TEST_CASE("Photopic R_A: illuminant A x V(lambda) over the band", "[photometry]") {
    // R_A as a photometer under illuminant A sees it (RaSpectrum::Photopic): without a pitch or
    // dispersion nothing in the node depends on the wavelength, so it is the channels' luminance
    // (to rounding), a coloured retro_color included; with a pitch and acrylic's dispersion it is
    // the weighted sum of R_A at each of the 15 wavelengths, made apart here with the material's
    // own `wavelength` input (not at_wavelength), and lies between their least and largest; the
    // table form and the standards' judgement take it; `ra --photopic` prints it and refuses
    // --wavelength and --rgb.
    const RaMeasurements t = read_ra_table(source("examples/standards/iso-20471.csv"));
    Params grey;
    grey.retro_color = {0.8, 0.6, 0.05};
    grey.roughness = 0.01;
    const std::vector<double> channels = ra_node_values(grey, t.entries);
    const std::vector<double> flat = ra_node_values(grey, t.entries, RaSpectrum::Photopic);
    double worstFlat = 0;
    for (size_t i = 0; i < t.entries.size(); ++i)
        worstFlat = std::max(worstFlat, std::abs(flat[i] / channels[i] - 1));
    Params pitch;
    pitch.prism_reflection = 1;
    pitch.abbe_number = 57;
    pitch.prism_pitch = 120;
    pitch.roughness = 0.001;
    const std::vector<double> photopic = ra_node_values(pitch, t.entries, RaSpectrum::Photopic);
    std::vector<double> sum(t.entries.size(), 0.0), lo(t.entries.size(), 1e300),
        hi(t.entries.size(), 0.0);
    for (size_t k = 0; k < photopic_weights().size(); ++k) {
        Params at = pitch;
        at.wavelength = photopic_wavelengths_nm()[k];
        const std::vector<double> v = ra_node_values(at, t.entries);
        for (size_t i = 0; i < v.size(); ++i) {
            sum[i] += photopic_weights()[k] * v[i];
            lo[i] = std::min(lo[i], v[i]);
            hi[i] = std::max(hi[i], v[i]);
        }
    }
    double worstSum = 0, spread = 0;
    const std::vector<double> rgb = ra_node_values(pitch, t.entries);
    for (size_t i = 0; i < t.entries.size(); ++i) {
        worstSum = std::max(worstSum, std::abs(photopic[i] / sum[i] - 1));
        CHECK(photopic[i] >= lo[i]);
        CHECK(photopic[i] <= hi[i]);
        spread = std::max(spread, std::abs(photopic[i] / rgb[i] - 1));
    }
    std::printf("MEASURED: photopic R_A: without a pitch the channels' luminance within %.1e; with "
                "a pitch the weighted sum within %.1e, and up to %.1f%% from the channels' "
                "luminance (ISO 20471's entries, 120 um, roughness 0.001)\n",
                worstFlat, worstSum, 100 * spread);
    // Rounding of the two sums (15 terms against 3, relative 1e-16 each).
    CHECK(worstFlat < 1e-12);
    CHECK(worstSum < 1e-12);

    // The table and the judgement take the same values.
    const RaTable table = ra_table(pitch, 0.0, {0.2, 1.0}, {-4.0, 30.0}, RaSpectrum::Photopic);
    RaEntry e;
    e.observation_deg = 1.0;
    e.entrance_deg = 30.0;
    e.rotation_deg = 0.0;
    e.ra = 1.0;
    const double one = ra_node_values(pitch, {e}, RaSpectrum::Photopic)[0];
    CHECK(table.rgb[1][1].x == Approx(one).epsilon(1e-12));
    CHECK(table.rgb[1][1].y == table.rgb[1][1].x);
    CHECK(table.rgb[1][1].z == table.rgb[1][1].x);
    const StandardJudgement j = judge_standard(t, pitch, "white", RaSpectrum::Photopic);
    REQUIRE(j.entries.size() == t.entries.size());
    CHECK(j.entries[0].material == Approx(photopic[0]).epsilon(1e-12));

    const fs::path dir = temp_dir("photopic");
    const std::string material = (dir / "photopic.json").string();
    {
        std::ofstream f(material);
        f << "{\"prism_reflection\": \"tir\", \"abbe_number\": 57, \"prism_pitch\": 120, "
             "\"roughness\": 0.001}";
    }
    Run r = cli("ra --csv --photopic --material " + material);
    REQUIRE(r.status == 0);
    const RaTable whole =
        ra_table(pitch, 0.0, ra_observation_angles(), ra_entrance_angles(), RaSpectrum::Photopic);
    std::istringstream in(r.output);
    std::string line;
    std::getline(in, line);
    REQUIRE(std::getline(in, line)); // 0.2 deg, -4 deg
    CHECK(contains(line, "0.2,-4,0,"));
    std::istringstream ls(line.substr(line.rfind(',') + 1));
    double blue = 0;
    ls >> blue;
    CHECK(blue == Approx(whole.rgb[0][0].z).epsilon(1e-8));
    Run both = cli("ra --photopic --wavelength 550 --material " + material);
    CHECK(both.status != 0);
    CHECK(contains(both.output, "give either --wavelength NM or --photopic, not both"));
    Run rgbOut = cli("ra --photopic --rgb --material " + material);
    CHECK(rgbOut.status != 0);
    CHECK(contains(rgbOut.output, "--rgb: the photopic R_A is one luminance"));
    fs::remove_all(dir);
}

TEST_CASE("ra --document: colours are converted from the document's colour space", "[photometry]") {
    // srgb_texture colours against the same colours decoded by the sRGB formula, linear.
    const fs::path dir = temp_dir("colour");
    const double enc[3] = {0.9, 0.5, 0.2};
    auto decode = [](double v) {
        return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    };
    Doc d = valid_doc();
    d.replace(R"(value="0.8, 0.6, 0.05")", R"(value="0.9, 0.5, 0.2" colorspace="srgb_texture")");
    d.replace(R"(value="1, 0.75,0.08" colorspace="srgb_texture")", R"(value="0.9, 0.5, 0.2")");
    d.replace(R"(<materialx version="1.39">)",
              R"(<materialx version="1.39" colorspace="srgb_texture">)");
    std::ofstream(dir / "srgb.mtlx") << d.text();
    MtlxDocument parsed = parse_mtlx(d.text(), "srgb.mtlx");
    Params lin = parsed.materials[0].params;
    lin.diffuse_color = {decode(enc[0]), decode(enc[1]), decode(enc[2])};
    lin.retro_color = lin.diffuse_color; // via the document's colorspace attribute
    std::ofstream(dir / "lin.json") << params_to_json(lin).dump();
    Run a = cli("ra --csv --document " + (dir / "srgb.mtlx").string());
    Run b = cli("ra --csv --material " + (dir / "lin.json").string());
    REQUIRE(a.status == 0);
    REQUIRE(b.status == 0);
    // OpenColorIO's CPU path works in float: agreement to ~1e-6 relative.
    std::istringstream sa(a.output), sb(b.output);
    std::string la, lb;
    std::getline(sa, la);
    std::getline(sb, lb);
    double worst = 0;
    while (std::getline(sa, la) && std::getline(sb, lb)) {
        std::replace(la.begin(), la.end(), ',', ' ');
        std::replace(lb.begin(), lb.end(), ',', ' ');
        std::istringstream xa(la), xb(lb);
        for (int k = 0; k < 7; ++k) {
            double va, vb;
            xa >> va;
            xb >> vb;
            worst = std::max(worst, std::abs(va - vb) / std::max(std::abs(vb), 1e-9));
        }
    }
    CHECK(worst < 2e-6);
    std::printf("MEASURED: srgb_texture via OpenColorIO vs the sRGB formula: R_A relative "
                "difference %.2e\n",
                worst);
    fs::remove_all(dir);
}

// =============================================================================================
// MaterialX reader

TEST_CASE("MaterialX reader: a valid document gives exactly its parameters", "[photometry]") {
    const Doc d = valid_doc();
    const MtlxDocument doc = parse_mtlx(d.text(), "doc.mtlx");
    REQUIRE(doc.materials.size() == 1);
    const MtlxMaterial& m = select_material(doc, "");
    CHECK(m.name == "yellow_sign");
    CHECK(m.surface == "sheet_surface");
    CHECK(m.bsdf == "sheet_bsdf");
    CHECK(m.line == d.line_of("<surfacematerial"));
    CHECK(m.bsdf_line == d.line_of("<rp_prismatic"));
    Params e; // expected
    e.roughness = 0.07;
    e.ior = 1.586;
    e.diffuse_color = {0.8, 0.6, 0.05};
    e.retro_color = {1.0, 0.75, 0.08}; // as written: not converted by the reader
    e.specular = 0.5;
    e.prism_reflection = 2;
    e.metal_reflectance = 0.9;
    e.era_mode = 2;
    e.orientation = 30.0;
    e.cant_angle = -12.5;
    e.retro_lobe = 1;
    e.reciprocal = true;
    e.weight = 0.75;
    e.normal = {0.0, 0.0, 1.0};
    CHECK(params_to_json(m.params) == params_to_json(e));
    CHECK(m.params.roughness == 0.07); // bit-exact, not just equal after JSON
    CHECK(m.params.diffuse_color == e.diffuse_color);
    REQUIRE(m.colors.size() == 2);
    CHECK(m.colors[0].input == "diffuse_color");
    CHECK(m.colors[0].colorspace == "lin_rec709");
    CHECK(m.colors[1].input == "retro_color");
    CHECK(m.colors[1].colorspace == "srgb_texture");
    CHECK(m.colors[1].line == d.line_of(R"(name="retro_color")"));
    // Conversion: only colours outside lin_rec709 go through the converter.
    int calls = 0;
    const Params w = to_working_space(doc, m, [&](const std::string& cs, const Color3& c) {
        ++calls;
        CHECK(cs == "srgb_texture");
        return Color3{c[0] * 0.5, c[1] * 0.5, c[2] * 0.5};
    });
    CHECK(calls == 1);
    CHECK(w.diffuse_color == e.diffuse_color);
    CHECK(w.retro_color == Color3{0.5, 0.375, 0.04});
    // A converted colour out of range is an error naming the input and its line.
    try {
        to_working_space(doc, m, [](const std::string&, const Color3&) {
            return Color3{1.7, -0.1, 0.0};
        });
        FAIL("no error");
    } catch (const InputError& err) {
        CHECK(contains(err.what(), "doc.mtlx:" + std::to_string(d.line_of("retro_color")) +
                                       ": <input name=\"retro_color\">"));
        CHECK(contains(err.what(), "outside the input's range [0, 1]"));
    }
    // Omitted inputs keep their defaults.
    Doc minimal = valid_doc();
    for (const char* in : {"roughness", "ior", "diffuse_color", "retro_color", "specular",
                           "prism_reflection", "metal_reflectance", "era_mode", "orientation",
                           "cant_angle", "retro_lobe", "reciprocal", "weight", "normal"}) {
        const int l = minimal.line_of(std::string("name=\"") + in + "\"");
        minimal.lines.erase(minimal.lines.begin() + (l - 1));
    }
    CHECK(params_to_json(parse_mtlx(minimal.text(), "m.mtlx").materials[0].params) ==
          params_to_json(Params()));
}

TEST_CASE("MaterialX reader: several materials, chosen by name", "[photometry]") {
    Doc d = valid_doc();
    d.insert_after("</surfacematerial>", R"(  <surfacematerial name="second" type="material">)");
    d.insert_after(R"(name="second")",
                   R"(    <input name="surfaceshader" type="surfaceshader" nodename="s2"/>)");
    d.insert_after(R"(nodename="s2")", R"(  </surfacematerial>)");
    d.insert_after(R"(<materialx)",
                   R"(  <rp_prismatic_retroreflector_bsdf name="b2" type="BSDF">)");
    d.insert_after(R"(name="b2")", R"(    <input name="roughness" type="float" value="0.3"/>)");
    d.insert_after(R"(value="0.3")", R"(  </rp_prismatic_retroreflector_bsdf>)");
    d.insert_after(R"(<materialx)", R"(  <surface name="s2" type="surfaceshader">)");
    d.insert_after(R"(name="s2")", R"(    <input name="bsdf" type="BSDF" nodename="b2"/>)");
    d.insert_after(R"(nodename="b2")", R"(  </surface>)");
    const MtlxDocument doc = parse_mtlx(d.text(), "two.mtlx");
    REQUIRE(doc.materials.size() == 2);
    CHECK(select_material(doc, "").name == "yellow_sign");
    CHECK(select_material(doc, "second").params.roughness == 0.3);
    CHECK(select_material(doc, "yellow_sign").params.roughness == 0.07);
    try {
        select_material(doc, "red_sign");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), "two.mtlx: no material named \"red_sign\" (materials: "
                                 "yellow_sign, second)"));
    }
}

TEST_CASE("MaterialX reader: every unsupported construct names the element and its line",
          "[photometry]") {
    struct Case {
        const char* what;
        std::function<void(Doc&)> mutate;
        std::string marker;  // the line the message must name ("" = no line check)
        std::string element; // what the message must name after "doc.mtlx:LINE: "
        std::string expect;  // and what it must say
    };
    const std::string bsdf = R"(<rp_prismatic_retroreflector_bsdf name="sheet_bsdf">)";
    auto input = [&](const char* n) {
        return std::string("<input name=\"") + n + "\"> of " + bsdf;
    };
    const std::vector<Case> cases = {
        {"no material",
         [](Doc& d) {
             for (const char* m :
                  {"<surfacematerial", R"(name="surfaceshader")", "</surfacematerial>"})
                 d.lines.erase(d.lines.begin() + (d.line_of(m) - 1));
         },
         "<materialx", "<materialx>", "no <surfacematerial> in the document"},
        {"unknown node category",
         [](Doc& d) {
             d.insert_after("<materialx",
                            R"(  <standard_surface name="ss" type="surfaceshader"/>)");
         },
         "standard_surface", "<standard_surface name=\"ss\">", "unsupported element"},
        {"node graph", [](Doc& d) { d.insert_after("<materialx", R"(  <nodegraph name="ng"/>)"); },
         "nodegraph", "<nodegraph name=\"ng\">", "node graphs are not supported"},
        {"connected input",
         [](Doc& d) { d.replace(R"(value="0.07")", R"(nodename="sheet_surface")"); },
         R"(name="roughness")", input("roughness"),
         "connected inputs (nodename=\"sheet_surface\")"},
        {"out of range", [](Doc& d) { d.replace(R"(value="0.07")", R"(value="2")"); },
         R"(name="roughness")", input("roughness"), "value 2 is outside its range [0, 1]"},
        {"colour out of range",
         [](Doc& d) { d.replace(R"(value="0.8, 0.6, 0.05")", R"(value="0.8, 1.5, 0.05")"); },
         R"(name="diffuse_color")", input("diffuse_color"),
         "component 1 = 1.5 is outside its range [0, 1]"},
        {"bad type",
         [](Doc& d) { d.replace(R"("roughness" type="float")", R"("roughness" type="color3")"); },
         R"(name="roughness")", input("roughness"), "type \"color3\", expected \"float\""},
        {"bad enum name", [](Doc& d) { d.replace(R"(value="oriented")", R"(value="sideways")"); },
         R"(name="era_mode")", input("era_mode"),
         "value \"sideways\" is not one of averaged, matched_pair, oriented (or give "
         "type=\"integer\" with one of 0 (averaged), 1 (matched_pair), 2 (oriented))"},
        {"bad enum value",
         [](Doc& d) {
             d.replace(R"("prism_reflection" type="integer" value="2")",
                       R"("prism_reflection" type="integer" value="3")");
         },
         R"(name="prism_reflection")", input("prism_reflection"),
         "value \"3\" is not one of the integers 0 (ideal), 1 (tir), 2 (metallized)"},
        {"enum name as an integer",
         [](Doc& d) {
             d.replace(R"("prism_reflection" type="integer" value="2")",
                       R"("prism_reflection" type="integer" value="metallized")");
         },
         R"(name="prism_reflection")", input("prism_reflection"),
         "value \"metallized\" is not one of the integers 0 (ideal), 1 (tir), 2 (metallized)"},
        {"bad enum type",
         [](Doc& d) {
             d.replace(R"("retro_lobe" type="integer")", R"("retro_lobe" type="float")");
         },
         R"(name="retro_lobe")", input("retro_lobe"), "type \"float\", expected \"integer\""},
        {"bad boolean",
         [](Doc& d) { d.replace(R"(type="boolean" value="true")", R"(type="boolean" value="1")"); },
         R"(name="reciprocal")", input("reciprocal"), "is not a boolean"},
        {"not a number", [](Doc& d) { d.replace(R"(value="1.586")", R"(value="glass")"); },
         R"(name="ior")", input("ior"),
         "value \"glass\" is not a number; expected a float in [1, 3]"},
        {"malformed colour",
         [](Doc& d) { d.replace(R"(value="0.8, 0.6, 0.05")", R"(value="0.8, 0.6")"); },
         R"(name="diffuse_color")", input("diffuse_color"), "is not a color3"},
        {"unknown input", [](Doc& d) { d.replace(R"(name="specular")", R"(name="sheen")"); },
         R"(name="sheen")", input("sheen"), "unknown input of rp_prismatic_retroreflector_bsdf"},
        {"duplicate input",
         [](Doc& d) {
             d.insert_after(R"(name="ior")", R"(    <input name="ior" type="float" value="1.5"/>)");
         },
         R"(value="1.5")", input("ior"), "duplicate input (first at line 5)"},
        {"missing value", [](Doc& d) { d.replace(R"(value="0.5")", ""); }, R"(name="specular")",
         input("specular"), "needs a constant value"},
        {"unknown colour space", [](Doc& d) { d.replace("srgb_texture", "rec2020"); },
         R"(name="retro_color")", input("retro_color"), "colorspace \"rec2020\" is not supported"},
        {"missing bsdf connection",
         [](Doc& d) { d.lines.erase(d.lines.begin() + (d.line_of(R"(name="bsdf")") - 1)); },
         "<surface ", "<surface name=\"sheet_surface\">", "needs an input bsdf"},
        {"dangling nodename",
         [](Doc& d) { d.replace(R"(nodename="sheet_surface")", R"(nodename="nowhere")"); },
         R"(name="surfaceshader")",
         "<input name=\"surfaceshader\"> of <surfacematerial name=\"yellow_sign\">",
         "nodename=\"nowhere\": no node of that name"},
        {"material straight to the BSDF",
         [](Doc& d) { d.replace(R"(nodename="sheet_surface")", R"(nodename="sheet_bsdf")"); },
         R"(name="surfaceshader")",
         "<input name=\"surfaceshader\"> of <surfacematerial name=\"yellow_sign\">",
         "expected a <surface> node"},
        {"missing surfaceshader",
         [](Doc& d) {
             d.lines.erase(d.lines.begin() + (d.line_of(R"(name="surfaceshader")") - 1));
         },
         "<surfacematerial", "<surfacematerial name=\"yellow_sign\">",
         "needs an input surfaceshader"},
        {"displacement",
         [](Doc& d) {
             d.insert_after(
                 R"(name="surfaceshader")",
                 R"(    <input name="displacementshader" type="displacementshader" nodename="x"/>)");
         },
         "displacementshader",
         "<input name=\"displacementshader\"> of <surfacematerial name=\"yellow_sign\">",
         "not supported"},
        {"opacity",
         [](Doc& d) {
             d.insert_after(R"(name="bsdf")",
                            R"(    <input name="opacity" type="float" value="0.5"/>)");
         },
         R"(name="opacity")", "<input name=\"opacity\"> of <surface name=\"sheet_surface\">",
         "only opacity 1 is supported"},
        {"wrong node type",
         [](Doc& d) {
             d.replace(R"(name="sheet_bsdf" type="BSDF")", R"(name="sheet_bsdf" type="EDF")");
         },
         "<rp_prismatic", bsdf, "type \"EDF\", expected type=\"BSDF\""},
        {"duplicate node name",
         [](Doc& d) {
             d.replace(R"(<surface name="sheet_surface")", R"(<surface name="sheet_bsdf")");
         },
         "<surface ", "<surface name=\"sheet_bsdf\">",
         "duplicate name \"sheet_bsdf\" (first used at line 3)"},
        {"no version", [](Doc& d) { d.replace(R"( version="1.39")", ""); }, "<materialx",
         "<materialx>", "expected a MaterialX version 1.38 or later"},
        {"wrong root",
         [](Doc& d) {
             d.replace("<materialx", "<mtlx");
             d.replace("</materialx>", "</mtlx>");
         },
         "<mtlx", "<mtlx>", "expected the root element <materialx"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        Doc d = valid_doc();
        c.mutate(d);
        const std::string msg = parse_error(d);
        INFO(msg);
        const std::string where = "doc.mtlx:" + std::to_string(d.line_of(c.marker)) + ": ";
        CHECK(contains(msg, where + c.element + ": "));
        CHECK(contains(msg, c.expect));
    }
    // Malformed XML: file, line and column of the parser's position.
    Doc bad = valid_doc();
    bad.replace(R"(<input name="specular" type="float" value="0.5"/>)",
                R"(<input name="specular" type="float" value="0.5">)");
    const std::string msg = parse_error(bad);
    INFO(msg);
    CHECK(contains(msg, "doc.mtlx:"));
    CHECK(contains(msg, ": malformed XML: "));
    // pugixml stops at the closing tag that does not match (the BSDF node's end).
    CHECK(contains(msg, "doc.mtlx:" + std::to_string(bad.line_of("</rp_prismatic")) + ":"));
    // A file that cannot be opened.
    try {
        read_mtlx("/nonexistent/doc.mtlx");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), "/nonexistent/doc.mtlx: cannot open file"));
    }
}

// =============================================================================================
// ALTA reader

TEST_CASE("ALTA reader: the 3M measurement and its conventions", "[photometry]") {
    const AltaData a = read_alta(source("tests/data/belcour2014/retro-3M-jaune.dat"));
    CHECK(a.samples.size() == 7397);
    CHECK(a.param_in == "ISOTROPIC_TL_TV_PROJ_DPHI");
    CHECK(a.param_out == "INV_STERADIAN_COSINE_FACTOR");
    CHECK(a.cosine_factor);
    CHECK(a.header_value("SAMPLE") == "3M Yellow");
    CHECK(a.samples.front().line == 8);
    CHECK(a.samples.front().value == Approx(0.000501744));
    // Directions: light at azimuth 0, view (x, y) = theta_v (cos dphi, sin dphi).
    AltaSample s;
    s.theta_l = 30 * kDeg;
    s.x = -30 * kDeg; // the mirror direction
    s.y = 0.0;
    CHECK(s.wi().x == Approx(0.5));
    CHECK(s.wo().x == Approx(-0.5));
    CHECK(s.wo().z == Approx(std::cos(30 * kDeg)));
    s.x = 0.0;
    s.y = 20 * kDeg;
    CHECK(s.wo().y == Approx(std::sin(20 * kDeg)));
    s.y = 0.0;
    CHECK(s.wo() == glm::dvec3(0, 0, 1));
    // INV_STERADIAN: the value is the BRDF, multiplied by cos(theta_v) for the fit.
    const AltaData b =
        parse_alta("#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n#PARAM_OUT INV_STERADIAN\n"
                   "0.5 1.0471975511965976 0 2.0\n",
                   "b.dat");
    CHECK_FALSE(b.cosine_factor);
    CHECK(b.samples[0].value_cos(b.cosine_factor) == Approx(1.0));
}

TEST_CASE("ALTA reader: errors name file:line and what is expected", "[photometry]") {
    const std::string head = "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n"
                             "#PARAM_OUT INV_STERADIAN_COSINE_FACTOR\n";
    struct Case {
        std::string text, expect;
    };
    const std::vector<Case> cases = {
        {"#DIM 3 3\n", "d.dat:1: #DIM 3 3: expected \"#DIM 3 1\""},
        {"#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n", "d.dat:2: #PARAM_IN RUSIN_TH_TD_PD: unsupported"},
        {"#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n#PARAM_OUT RGB_COLOR\n",
         "d.dat:3: #PARAM_OUT RGB_COLOR: unsupported output"},
        {"#SAMPLE x\n0.1 0 0 1\n", "d.dat:2: data line before the header is complete"},
        {head + "0.1 0 0 1\n\n0.1 0 1\n",
         "d.dat:6: expected 4 numbers (theta_l x y value), found 3"},
        {head + "0.1 0 0 abc\n", "d.dat:4: value \"abc\" is not a finite number"},
        {head + "0.1 0 nan 1\n", "d.dat:4: y \"nan\" is not a finite number"},
        {head + "0.1 0 0 -0.5\n", "d.dat:4: value -0.5 is negative"},
        {head + "1.6 0 0 1\n", "d.dat:4: theta_l = 1.6 rad is outside [0, pi/2)"},
        {head + "0.1 1.2 1.2 1\n", "d.dat:4: theta_v = |(x, y)| = "},
        {head, "d.dat:3: no data lines"},
    };
    for (const Case& c : cases) {
        INFO(c.text);
        try {
            parse_alta(c.text, "d.dat");
            FAIL("no error");
        } catch (const InputError& e) {
            CHECK(contains(e.what(), c.expect));
        }
    }
    try {
        read_alta("/nonexistent/d.dat");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), "/nonexistent/d.dat: cannot open file"));
    }
}

// =============================================================================================
// Fitting

TEST_CASE("Fit: the forward models are the library's", "[photometry]") {
    FitData d = synthetic_geometry();
    FitOptions sharp;
    sharp.resolution_fwhm_deg = 0.0;
    NodeFitParams p;
    p.roughness = 0.08;
    p.ior = 1.55;
    p.specular = 0.7;
    p.retro = 0.6;
    p.diffuse = 0.5;
    p.prism_reflection = 1;
    // Without blur, node_values is the node's f cos(theta_o) (colours grey), to rounding.
    // The fitter's core materials integrate their azimuth averages; so does this node.
    const std::vector<double> v = node_values(p, d, sharp);
    const PrismaticRetroreflector<double> node(
        node_params(p), PrismaticRetroreflector<double>::Averages::Integrated);
    double worst = 0;
    for (size_t i = 0; i < d.samples.size(); ++i) {
        const FitSample& s = d.samples[i];
        const double ref = node.eval(s.wi, s.wo).f.total().x * s.wo.z;
        worst = std::max(worst, std::abs(v[i] - ref) / std::max(ref, 1e-300));
    }
    CHECK(worst < 1e-12);
    // The baseline likewise.
    baselines::RetroreflectiveGGX m;
    m.roughness = 0.12;
    m.ior = 1.6;
    m.specular = 0.8;
    m.color = glm::dvec3(0.4);
    const std::vector<double> mv = mrm_values(m, d, sharp);
    for (size_t i = 0; i < d.samples.size(); ++i)
        CHECK(mv[i] ==
              Approx(m.f(d.samples[i].wi, d.samples[i].wo).x * d.samples[i].wo.z).epsilon(1e-12));
    // The blur keeps each lobe's peak finite and lowers it.
    FitOptions blur;
    const std::vector<double> vb = node_values(p, d, blur);
    double peakSharp = 0, peakBlur = 0;
    for (size_t i = 0; i < v.size(); ++i) {
        peakSharp = std::max(peakSharp, v[i]);
        peakBlur = std::max(peakBlur, vb[i]);
    }
    CHECK(peakBlur < peakSharp);
    CHECK(peakBlur > 0.2 * peakSharp);
}

TEST_CASE("Fit: known parameters are recovered from synthetic data", "[photometry][threads]") {
    FitOptions o; // with the default blur, in the data and in the fit
    const NodeFitParams truth = synthetic_truth(0.08);
    FitData d = synthetic_fit_data(truth, o);
    const auto t0 = std::chrono::steady_clock::now();
    const NodeFit f = fit_node(d, o);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    check_recovered(f, truth);
    std::printf("MEASURED: node fit on %zu synthetic samples: roughness %.5f (0.08), ior %.5f "
                "(1.55), specular %.4f, retro %.4f, diffuse %.4f, log_rms %.2e, %.1f s\n",
                d.samples.size(), f.params.roughness, f.params.ior, f.params.specular,
                f.params.retro, f.params.diffuse, f.report.log_rms, secs);
    check_deterministic(f, d, o);

    // The baseline from its own synthetic data.
    baselines::RetroreflectiveGGX m;
    m.roughness = 0.12;
    m.ior = 1.6;
    m.specular = 0.8;
    m.color = glm::dvec3(0.4);
    const std::vector<double> mv = mrm_values(m, d, o);
    for (size_t i = 0; i < mv.size(); ++i)
        d.samples[i].value = mv[i];
    const MrmFit mf = fit_mrm(d, o);
    CHECK(mf.model.roughness == Approx(0.12).epsilon(0.01));
    CHECK(mf.model.ior == Approx(1.6).epsilon(0.01));
    CHECK(mf.model.specular == Approx(0.8).margin(0.01));
    CHECK(mf.model.color.x == Approx(0.4).margin(0.01));
    CHECK(mf.report.log_rms < 1e-3);
    std::printf("MEASURED: baseline fit: roughness %.5f (0.12), ior %.5f (1.6), specular %.4f, "
                "color %.4f, log_rms %.2e\n",
                mf.model.roughness, mf.model.ior, mf.model.specular, mf.model.color.x,
                mf.report.log_rms);
}

TEST_CASE("Fit: the sheeting geometry is recovered from synthetic data; the paper's geometry "
          "never fits better; deterministic",
          "[photometry]") {
    FitOptions o;
    NodeFitParams truth = synthetic_truth(0.04);
    truth.cant_angle = 12.0;
    truth.dihedral_error = 8.0;
    const FitData d = synthetic_fit_data(truth, o);
    const NodeFit f = fit_node(d, o);
    check_recovered(f, truth);
    for (int mode = 0; mode < 3; ++mode)
        CHECK(f.mode_objective[mode] <= f.paper_objective[mode]);
    // Held at the paper's geometry: the old fit, worse on these data.
    FitOptions paper = o;
    paper.paper_geometry = true;
    const NodeFit p = fit_node(d, paper);
    CHECK(p.params.cant_angle == 0.0);
    CHECK(p.params.dihedral_error == 0.0);
    CHECK(p.report.objective > 100.0 * f.report.objective);
    for (int mode = 0; mode < 3; ++mode) {
        CHECK(p.mode_objective[mode] == p.paper_objective[mode]);
        CHECK(p.paper_objective[mode] == f.paper_objective[mode]);
    }
    std::printf("MEASURED: geometry fit on %zu synthetic samples: cant %.4f (12), dihedral %.4f "
                "(8), roughness %.5f (0.04), ior %.5f (1.55), log_rms %.2e; paper geometry "
                "log_rms %.3f; %d + %d evaluations\n",
                d.samples.size(), f.params.cant_angle, f.params.dihedral_error, f.params.roughness,
                f.params.ior, f.report.log_rms, p.report.log_rms, f.evaluations, p.evaluations);
    check_deterministic(f, d, o);
}

TEST_CASE("Fit: the 3M measurement, node against the MaterialX-style baseline", "[photometry]") {
    const FitData d = fit_data(read_alta(source("tests/data/belcour2014/retro-3M-jaune.dat")));
    FitOptions o;
    const NodeFit nf = fit_node(d, o);
    const MrmFit mf = fit_mrm(d, o);
    std::printf(
        "MEASURED: 3M yellow: node log_rms %.4f rel_rms %.4f (%s, roughness %.4f, ior "
        "%.4f); baseline log_rms %.4f rel_rms %.4f\n",
        nf.report.log_rms, nf.report.rel_rms,
        enum_values(*find_param("prism_reflection"))[size_t(nf.params.prism_reflection)].c_str(),
        nf.params.roughness, nf.params.ior, mf.report.log_rms, mf.report.rel_rms);
    // The node's three lobes (retro peak, mirror peak, floor) fit the data better in log space
    // than one retroreflective GGX lobe over Lambert (no mirror peak).
    CHECK(nf.report.log_rms < mf.report.log_rms);
    for (const GroupReport& g : nf.report.groups) {
        CHECK(g.retro_measured > 5.0);
        CHECK(g.mirror_measured > 5.0);
    }
}

TEST_CASE("retroprism fit --json: exactly the documented keys; --plot writes a PNG",
          "[photometry]") {
    const fs::path dir = temp_dir("fit");
    FitData d = synthetic_geometry();
    NodeFitParams truth;
    truth.roughness = 0.1;
    truth.ior = 1.5;
    truth.specular = 0.9;
    truth.retro = 0.8;
    truth.diffuse = 0.6;
    truth.prism_reflection = 0;
    const std::vector<double> v = node_values(truth, d, FitOptions());
    {
        std::ofstream f(dir / "synthetic.dat");
        f << "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n"
             "#PARAM_OUT INV_STERADIAN_COSINE_FACTOR\n";
        char buf[256];
        for (size_t i = 0; i < d.samples.size(); ++i) {
            const FitSample& s = d.samples[i];
            const double thetaV = std::acos(std::clamp(s.wo.z, -1.0, 1.0));
            const double r = std::hypot(s.wo.x, s.wo.y);
            const double x = r > 0 ? thetaV * s.wo.x / r : 0.0,
                         y = r > 0 ? thetaV * s.wo.y / r : 0.0;
            std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g\n",
                          d.group_theta[size_t(s.group)], x, y, v[i]);
            f << buf;
        }
    }
    Run r = cli("fit --json --plot " + (dir / "fit.png").string() + " " +
                (dir / "synthetic.dat").string());
    REQUIRE(r.status == 0);
    const json j = json::parse(r.output);
    std::vector<std::string> keys;
    for (auto it = j.begin(); it != j.end(); ++it)
        keys.push_back(it.key());
    CHECK(keys == std::vector<std::string>{"log_rms", "mrm", "params", "rel_rms"});
    std::vector<std::string> mrmKeys;
    for (auto it = j["mrm"].begin(); it != j["mrm"].end(); ++it)
        mrmKeys.push_back(it.key());
    CHECK(mrmKeys == std::vector<std::string>{"log_rms", "params", "rel_rms"});
    // `params` is a material the other commands read.
    const Params p = params_from_json(j["params"], "fit.params");
    CHECK(p.roughness == Approx(0.1).epsilon(0.01));
    CHECK(p.prism_reflection == 0);
    CHECK(j["log_rms"].get<double>() < 1e-3);
    CHECK(j["mrm"]["log_rms"].get<double>() > j["log_rms"].get<double>());
    CHECK(j["mrm"]["params"].contains("roughness"));
    CHECK(j["mrm"]["params"].contains("color"));
    std::ifstream png(dir / "fit.png", std::ios::binary);
    char magic[4] = {0, 0, 0, 0};
    png.read(magic, 4);
    CHECK(std::string(magic + 1, 3) == "PNG");
    // A bad data file: an error naming file:line, no output.
    std::ofstream(dir / "bad.dat") << "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n"
                                      "#PARAM_OUT INV_STERADIAN_COSINE_FACTOR\n0.1 0 0\n";
    Run bad = cli("fit --plot " + (dir / "bad.png").string() + " " + (dir / "bad.dat").string());
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "bad.dat:4: expected 4 numbers"));
    CHECK_FALSE(fs::exists(dir / "bad.png"));
    fs::remove_all(dir);
}

// =============================================================================================
// Render

TEST_CASE("retroprism render: finite non-negative EXR layers and a PNG; nothing on error",
          "[photometry]") {
    const fs::path dir = temp_dir("render");
    const std::string doc = source("examples/documents/white_sign.mtlx");
    Run r = cli("render " + doc + " -o " + (dir / "tiny.exr").string() +
                " --width 48 --height 27 --samples 2 --fill");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(contains(r.output, "R_A [cd lx^-1 m^-2] of material \"white_sign\""));
    REQUIRE(fs::exists(dir / "tiny.exr"));
    REQUIRE(fs::exists(dir / "tiny.png"));
    std::ifstream png(dir / "tiny.png", std::ios::binary);
    char magic[4] = {0, 0, 0, 0};
    png.read(magic, 4);
    CHECK(std::string(magic + 1, 3) == "PNG");
    // The EXR through oiiotool (openimageio-tools, a set-up package).
    Run stats = run("oiiotool --stats " + (dir / "tiny.exr").string());
    INFO(stats.output);
    REQUIRE(stats.status == 0);
    CHECK(contains(stats.output, "13 channel, float openexr"));
    auto numbers = [&](const std::string& key) {
        std::vector<double> v;
        const size_t at = stats.output.find(key);
        if (at == std::string::npos) return v;
        std::istringstream ls(
            stats.output.substr(at + key.size(), stats.output.find('\n', at) - at - key.size()));
        double x;
        while (ls >> x)
            v.push_back(x);
        return v;
    };
    const std::vector<double> mins = numbers("Stats Min:"), maxs = numbers("Stats Max:");
    REQUIRE(mins.size() == 13);
    for (double m : mins)
        CHECK(m >= 0.0);
    for (double c : numbers("Stats NanCount:"))
        CHECK(c == 0);
    for (double c : numbers("Stats InfCount:"))
        CHECK(c == 0);
    CHECK(*std::max_element(maxs.begin(), maxs.end()) > 1.0); // the glow is there
    Run info = run("oiiotool --info -v " + (dir / "tiny.exr").string());
    for (const char* ch : {"R", "G", "B", "A", "surface.R", "retro.G", "diffuse.B"})
        CHECK(contains(info.output, std::string(" ") + ch + ","));

    // A bad document: an error naming the element and line; no EXR, PNG or temporary file.
    const fs::path badDir = temp_dir("render_bad");
    Doc d = valid_doc();
    d.replace(R"(value="0.07")", R"(value="-1")");
    std::ofstream(badDir / "bad.mtlx") << d.text();
    Run bad = cli("render " + (badDir / "bad.mtlx").string() + " -o " +
                  (badDir / "out.exr").string() + " --width 16 --height 16");
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "bad.mtlx:" + std::to_string(d.line_of("roughness")) +
                                   ": <input name=\"roughness\">"));
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(badDir)) {
        (void)e;
        ++files;
    }
    CHECK(files == 1); // bad.mtlx alone
    Run noOut = cli("render " + doc + " -o " + (badDir / "out.png").string());
    CHECK(noOut.status != 0);
    CHECK(contains(noOut.output, "must be an OpenEXR file ending in .exr"));
    fs::remove_all(dir);
    fs::remove_all(badDir);
}

// =============================================================================================
// R_A tables (fit --ra)

namespace {

RaMeasurements table_of(const std::string& text, const std::string& name = "t.csv") {
    std::istringstream in(text);
    return parse_ra_table(in, name);
}

// Each case's text (`.text`) read as a table fails with an error containing `.expect`.
template <class Case>
void check_table_errors(const std::vector<Case>& cases) {
    for (const Case& c : cases) {
        INFO(c.text);
        try {
            table_of(c.text);
            FAIL("no error");
        } catch (const InputError& e) {
            CHECK(contains(e.what(), c.expect));
        }
    }
}

// R_A of `truth` at observation x entrance angles (rows without rotation: the mean over 0 and
// 90 degrees), as a table.
RaMeasurements synthetic_table(const Params& truth, const std::vector<double>& observation,
                               const std::vector<double>& entrance) {
    RaMeasurements t;
    t.file = "synthetic.csv";
    for (double a : observation)
        for (double b : entrance) {
            RaEntry e;
            e.observation_deg = a;
            e.entrance_deg = b;
            e.line = int(t.entries.size()) + 2;
            t.entries.push_back(e);
        }
    const std::vector<double> v = ra_node_values(truth, t.entries);
    for (size_t i = 0; i < v.size(); ++i)
        t.entries[i].ra = v[i];
    return t;
}

} // namespace

TEST_CASE("R_A table reader: the DG983 preset, every column, comments", "[photometry]") {
    const RaMeasurements dg = read_ra_table(source("examples/sheeting/dg983_white.csv"));
    REQUIRE(dg.entries.size() == 6);
    CHECK(contains(dg.comments.front(), "3M Diamond Grade"));
    CHECK(dg.entries[0].observation_deg == 0.2);
    CHECK(dg.entries[0].entrance_deg == -4);
    CHECK(dg.entries[0].ra == 800);
    CHECK_FALSE(dg.entries[0].rotation_deg.has_value());
    CHECK(dg.entries[0].presentation_deg == 0);
    CHECK(dg.entries[5].ra == 85);
    // Columns in any order, blanks around fields, CRLF, an empty rotation field (the mean).
    const RaMeasurements t = table_of("# a comment\r\n\r\n entrance_deg , ra,observation_deg,"
                                      "rotation_deg,presentation_deg\r\n-4,800,0.2,0,0\r\n"
                                      "  # another\n-4,760,0.2,90,5\n30,1e2,0.5,,-10\n");
    REQUIRE(t.entries.size() == 3);
    CHECK(t.comments == std::vector<std::string>{"a comment", "another"});
    CHECK(t.entries[0].line == 4);
    CHECK(t.entries[1].rotation_deg == 90.0);
    CHECK(t.entries[1].presentation_deg == 5.0);
    CHECK(t.entries[2].line == 7);
    CHECK(t.entries[2].ra == 100.0);
    CHECK_FALSE(t.entries[2].rotation_deg.has_value());
}

TEST_CASE("R_A table reader: errors name file:line, the column and the expected form",
          "[photometry]") {
    const std::string head = "observation_deg,entrance_deg,ra\n";
    struct Case {
        std::string text, expect;
    };
    const std::vector<Case> cases = {
        {"observation,entrance_deg,ra\n0.2,-4,800\n",
         "t.csv:1, column 1: unknown column \"observation\"; expected a header row "
         "observation_deg,entrance_deg,ra[,rotation_deg][,presentation_deg]"},
        {"observation_deg,ra,ra\n", "t.csv:1, column 3: column \"ra\" appears twice"},
        {"# c\nobservation_deg,ra\n0.2,5\n",
         "t.csv:2: the header row has no column entrance_deg; expected observation_deg,"},
        {head + "0.2,-4\n", "t.csv:2: 2 fields, but the header row has 3 columns"},
        {head + "0.2,-4,abc\n",
         "t.csv:2, column 3 (ra): \"abc\" is not a number; expected an R_A in cd lx^-1 m^-2 "
         "greater than 0"},
        {head + "0.2,-4,\n", "t.csv:2, column 3 (ra): \"\" is not a number"},
        {head + "0.2,-4,nan\n", "t.csv:2, column 3 (ra): \"nan\" is not a number"},
        {head + "0.2,-4,0\n", "t.csv:2, column 3 (ra): 0 is out of range; expected an R_A"},
        {head + "0.2,-4,-5\n", "t.csv:2, column 3 (ra): -5 is out of range"},
        {head + "0,-4,5\n",
         "t.csv:2, column 1 (observation_deg): 0 is out of range; expected an observation angle "
         "in (0, 5] degrees"},
        {head + "5.5,-4,5\n", "t.csv:2, column 1 (observation_deg): 5.5 is out of range"},
        {head + "0.2,90,5\n",
         "t.csv:2, column 2 (entrance_deg): 90 is out of range; expected an entrance angle in "
         "(-90, 90) degrees"},
        {head + "0.2,-90,5\n", "t.csv:2, column 2 (entrance_deg): -90 is out of range"},
        {"observation_deg,entrance_deg,ra,rotation_deg\n0.2,-4,5,400\n",
         "t.csv:2, column 4 (rotation_deg): 400 is out of range; expected a rotation angle in "
         "[-360, 360] degrees"},
        {head + "0.2,-4,800\n\n0.2,-4.0,790\n",
         "t.csv:4: a second row for observation 0.2, entrance -4, rotation mean of 0 and 90, "
         "presentation 0 (the first is line 2); expected one measurement per row"},
        {"# only comments\n", "t.csv:1: no header row; expected a header row"},
        {head, "t.csv:1: no rows; expected one row per measurement"},
    };
    check_table_errors(cases);
    // Rows at the same angles but another rotation are different measurements.
    CHECK(table_of("observation_deg,entrance_deg,ra,rotation_deg\n0.2,-4,8,0\n0.2,-4,7,90\n"
                   "0.2,-4,7.5,\n")
              .entries.size() == 3);
    try {
        read_ra_table("/nonexistent/t.csv");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), "/nonexistent/t.csv: cannot open file"));
    }
}

TEST_CASE("R_A of an entry: presentation turns the observer about the source; no rotation is "
          "the mean of 0 and 90 degrees",
          "[photometry]") {
    glm::dvec3 wi, wo, wi0, wo0;
    ra_directions(30.0, 0.5, 20.0, wi0, wo0);
    ra_directions(30.0, 0.5, 20.0, wi, wo, 0.0);
    CHECK(wo == wo0);
    ra_directions(30.0, 0.5, 20.0, wi, wo, 90.0);
    CHECK(wi == wi0);
    CHECK(std::acos(glm::dot(wi, wo)) / kDeg == Approx(0.5).epsilon(1e-6));
    CHECK(glm::length(wo - wo0) > 0.5 * 0.5 * kDeg);
    ra_directions(30.0, 0.5, 20.0, wi, wo, 180.0);
    // Turned by 180 degrees about wi: the observer on the far side (theta_o = 30.5 degrees).
    CHECK(std::acos(wo.z) / kDeg == Approx(30.5).epsilon(1e-6));
    // Rotation-sensitive prisms: a row without rotation is the mean over 0 and 90 degrees.
    Params o;
    o.era_mode = 2; // oriented
    const PrismaticRetroreflector<double> node(ra_params(o));
    RaEntry e;
    e.observation_deg = 0.2;
    e.entrance_deg = 45;
    RaEntry r0 = e, r90 = e;
    r0.rotation_deg = 0.0;
    r90.rotation_deg = 90.0;
    const double a = ra_at_entry(node, r0), b = ra_at_entry(node, r90);
    CHECK(a != Approx(b).epsilon(0.05));
    CHECK(ra_at_entry(node, e) == Approx(0.5 * (a + b)).epsilon(1e-12));
    CHECK(a == Approx(luminance_709(ra_value(node, 45.0, 0.2, 0.0))).epsilon(1e-12));
}

TEST_CASE("fit --ra: the fittable inputs of the parameter table are recovered from a synthetic "
          "table",
          "[photometry]") {
    // The fitted inputs are the table's RP_FIT lines, but prism_pitch for a base without one.
    std::vector<std::string> names;
    for (const FitInfo& f : fit_table())
        if (std::string(f.param->name) != "prism_pitch") names.push_back(f.param->name);
    for (const char* n : {"retro_color", "roughness", "ior", "prism_reflection"})
        CHECK(std::count(names.begin(), names.end(), n) == 1);
    Params truth;
    truth.roughness = 0.02;
    truth.ior = 1.58;
    truth.retro_color = {0.7, 0.7, 0.7};
    truth.prism_reflection = 1; // tir
    const RaMeasurements t =
        synthetic_table(truth, {0.1, 0.2, 0.33, 0.5, 1.0}, {-4.0, 15.0, 30.0, 40.0});
    const auto t0 = std::chrono::steady_clock::now();
    const RaNodeFit f = fit_ra_node(t);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    CHECK(f.fitted == names);
    CHECK(f.params.prism_reflection == 1);
    CHECK(f.params.roughness == Approx(0.02).epsilon(1e-3));
    CHECK(f.params.ior == Approx(1.58).epsilon(1e-3));
    CHECK(f.params.retro_color[0] == Approx(0.7).epsilon(1e-3));
    CHECK(f.params.retro_color[2] == f.params.retro_color[0]);
    // Not fitted: the base's.
    CHECK(f.params.diffuse_color == Params().diffuse_color);
    CHECK(f.report.max_error < 1e-3);
    std::printf("MEASURED: fit --ra on %zu synthetic entries: roughness %.6g (0.02), ior %.6g "
                "(1.58), retro_color %.6g (0.7), max error %.2e, %d evaluations, %.1f s\n",
                t.entries.size(), f.params.roughness, f.params.ior, f.params.retro_color[0],
                f.report.max_error, f.evaluations, secs);
    // The baseline's GGX lobe is the same at every entrance angle: it cannot follow the fall-off.
    const RaMrmFit m = fit_ra_mrm(t);
    CHECK(m.report.log_rms > 5 * f.report.log_rms);
    // The document's values give what the report says: the fitted values are rounded.
    const std::vector<double> again = ra_node_values(f.params, t.entries);
    CHECK(again == f.report.model);
    // Fewer rows than fitted inputs.
    RaMeasurements few = t;
    few.entries.resize(names.size() - 1);
    std::string list;
    for (const std::string& n : names)
        list += (list.empty() ? "" : ", ") + n;
    try {
        fit_ra_node(few);
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), "synthetic.csv: " + std::to_string(names.size() - 1) +
                                     " rows, fewer than the " + std::to_string(names.size()) +
                                     " inputs fitted (" + list + "); give at least " +
                                     std::to_string(names.size()) + " rows"));
    }
    // Held inputs keep the base's value and do not count: two held, the same rows suffice.
    Params base;
    base.cant_angle = 0.0;
    base.dihedral_spread = 0.0;
    const RaNodeFit held = fit_ra_node(few, base, {"cant_angle", "dihedral_spread"});
    CHECK(held.params.cant_angle == 0.0);
    CHECK(held.params.dihedral_spread == 0.0);
    CHECK(held.fitted.size() == names.size() - 2);
    CHECK(std::find(held.fitted.begin(), held.fitted.end(), "cant_angle") == held.fitted.end());
    // The message names every fittable input, prism_pitch too.
    std::string fittable;
    for (const FitInfo& fi : fit_table())
        fittable += (fittable.empty() ? "" : ", ") + std::string(fi.param->name);
    try {
        fit_ra_node(t, base, {"weight"});
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(contains(e.what(),
                       "--hold weight: not a fitted input (the fitted inputs: " + fittable + ")"));
    }
}

TEST_CASE("fit --ra: the prism pitch is recovered when the base has one", "[photometry]") {
    // Uncoated prisms of pitch 150 um: a wide table (0.1-1.5 deg) from them; the fit starts from
    // a base of 100 um with the geometry's inputs held.
    Params truth;
    truth.roughness = 0.02;
    truth.ior = 1.58;
    truth.retro_color = {0.7, 0.7, 0.7};
    truth.prism_reflection = 1; // tir
    truth.prism_pitch = 150;
    const RaMeasurements t =
        synthetic_table(truth, {0.1, 0.2, 0.33, 0.5, 1.0, 1.5}, {-4.0, 15.0, 30.0});
    Params base;
    base.prism_reflection = 1;
    base.prism_pitch = 100;
    const RaNodeFit f = fit_ra_node(
        t, base, {"prism_reflection", "cant_angle", "dihedral_error", "dihedral_spread"});
    CHECK(std::count(f.fitted.begin(), f.fitted.end(), "prism_pitch") == 1);
    std::printf("MEASURED: fit --ra with a pitch: prism_pitch %.6g (150), roughness %.6g (0.02), "
                "ior %.6g (1.58), max error %.2e, %d evaluations\n",
                f.params.prism_pitch, f.params.roughness, f.params.ior, f.report.max_error,
                f.evaluations);
    // The optimiser's stopping rule (1e-9 relative in the objective) leaves the inputs within
    // about 1e-4; 1e-3 is the bound of the other synthetic fits.
    CHECK(f.params.prism_pitch == Approx(150).epsilon(1e-3));
    CHECK(f.params.roughness == Approx(0.02).epsilon(1e-3));
    CHECK(f.report.max_error < 1e-3);
}

namespace {

// The largest |ln(model / measured)| of a fit's report over the table t.
double largest_log_error(const RaMeasurements& t, const RaFitReport& r) {
    double worst = 0;
    for (size_t i = 0; i < r.model.size(); ++i)
        worst = std::max(worst, std::abs(std::log(r.model[i] / t.entries[i].ra)));
    return worst;
}

} // namespace

TEST_CASE("fit --ra --objective max: the largest error is the minimax one", "[photometry]") {
    // The DG983 table with the preset's base (uncoated prisms of 100 um, acrylic's dispersion,
    // the fast tier): the minimax fit's largest error is at most the least-squares fit's, and
    // its largest squared log error is what it minimised (no other fit of the same inputs found
    // lower: the least-squares one is not); the names are checked.
    const RaMeasurements t = read_ra_table(source("examples/sheeting/dg983_white.csv"));
    Params base;
    base.prism_reflection = 1;
    base.abbe_number = 57;
    base.prism_pitch = 100;
    base.fidelity = 1;
    const std::vector<std::string> held = {"prism_reflection", "dihedral_spread"};
    const RaNodeFit rms = fit_ra_node(t, base, held, RaObjective::Rms);
    const RaNodeFit max = fit_ra_node(t, base, held, RaObjective::Max);
    std::printf("MEASURED: DG983 table, largest error: rms fit %.1f%%, max fit %.1f%%; log RMS "
                "%.4f and %.4f\n",
                100 * rms.report.max_error, 100 * max.report.max_error, rms.report.log_rms,
                max.report.log_rms);
    CHECK(largest_log_error(t, max.report) < largest_log_error(t, rms.report));
    CHECK(max.report.log_rms >= rms.report.log_rms * (1 - 1e-6));
    CHECK(ra_objective("rms") == RaObjective::Rms);
    CHECK(ra_objective("max") == RaObjective::Max);
    CHECK(std::string(ra_objective_name(RaObjective::Max)) == "max");
    CHECK_THROWS_WITH(ra_objective("minimax"),
                      "--objective minimax: not one of rms, max, relative");
}

TEST_CASE("fit --ra --objective relative: the largest error is the minimax one", "[photometry]") {
    // ISO 20471's table with geometric optics (uncoated prisms, no pitch: quick to evaluate)
    // and the GGX baseline: each minimax fit ends at or below the other fits' largest error in
    // its own measure (both start from the least-squares optimum and keep it unless they find
    // lower), and a free scale (the node's retro_color, below its bound; the baseline's
    // specular weight) leaves the relative fit's largest errors above and below the table
    // equal: were they not, scaling would lower the larger. The equality holds to the 6 digits
    // the fitted values are rounded to; 1e-3 of slack for the simplex's stopping rule (1e-9
    // relative in the objective, about 3e-5 in the error).
    const RaMeasurements t = read_ra_table(source("examples/standards/iso-20471.csv"));
    Params base;
    base.prism_reflection = 1;
    base.abbe_number = 57;
    const std::vector<std::string> held = {"prism_reflection", "dihedral_spread"};
    auto balance = [](const RaFitReport& r) {
        const auto [lo, hi] = std::minmax_element(r.error.begin(), r.error.end());
        return *hi + *lo; // 0 when the largest errors above and below are equal
    };
    std::array<RaNodeFit, 3> node;
    std::array<RaMrmFit, 3> mrm;
    for (int o = 0; o < 3; ++o) {
        node[size_t(o)] = fit_ra_node(t, base, held, RaObjective(o));
        mrm[size_t(o)] = fit_ra_mrm(t, RaObjective(o));
    }
    std::printf("MEASURED: ISO 20471, geometric optics, largest error: rms %.1f%%, max %.1f%%, "
                "relative %.1f%% (balance %.1e); baseline %.1f%%, %.1f%%, %.1f%% (%.1e)\n",
                100 * node[0].report.max_error, 100 * node[1].report.max_error,
                100 * node[2].report.max_error, balance(node[2].report),
                100 * mrm[0].report.max_error, 100 * mrm[1].report.max_error,
                100 * mrm[2].report.max_error, balance(mrm[2].report));
    for (const RaFitReport* r : {&node[2].report, &mrm[2].report}) {
        CHECK(std::abs(balance(*r)) < 1e-3);
    }
    CHECK(node[2].params.retro_color[0] < 1);
    CHECK(node[2].report.max_error <= node[0].report.max_error);
    CHECK(node[2].report.max_error <= node[1].report.max_error);
    CHECK(largest_log_error(t, node[1].report) <= largest_log_error(t, node[0].report));
    CHECK(largest_log_error(t, node[1].report) <= largest_log_error(t, node[2].report));
    CHECK(mrm[2].report.max_error <= mrm[0].report.max_error);
    CHECK(mrm[2].report.max_error <= mrm[1].report.max_error);
    CHECK(largest_log_error(t, mrm[1].report) <= largest_log_error(t, mrm[0].report));
    CHECK(ra_objective("relative") == RaObjective::Relative);
    CHECK(std::string(ra_objective_name(RaObjective::Relative)) == "relative");
    CHECK(std::string(ra_objective_name(RaObjective::Rms)) == "rms");

    // A coloured table: each colour's scale makes its largest errors above and below equal.
    const RaMeasurements at = read_ra_table(source("examples/standards/at-stvzvo-1998-type2.csv"));
    const RaColoredFit colored = fit_ra_colors(at, base, held, "", RaObjective::Relative);
    REQUIRE(colored.colors.size() > 1);
    for (const RaColorFit& c : colored.colors) {
        INFO(c.color);
        // Off where a channel reaches retro_color's range [0.01, 1] (a grey scale: all three).
        if (c.retro_color[0] > 0.01 && c.retro_color[0] < 1)
            CHECK(std::abs(balance(c.report)) < 1e-3);
    }
}

TEST_CASE("Every bundled table reaching observation 1 degree is fitted within 30%",
          "[photometry][ci]") {
    // The standards' tables with entries at 1 degree or wider, fitted as docs/standards.md does
    // (uncoated prisms of 100 um with acrylic's dispersion, the exact tier; prism_reflection and
    // dihedral_spread held) with --objective relative: the largest |model - measured| / measured
    // over the rows of the table's reference colour (white, or the whole table without colours)
    // within 30%. The other colours keep that geometry with a scale of retro_color: printed,
    // not asserted (a colour's minimums need not follow white's over the angles, and the base's
    // white substrate sets a floor under a dark colour's minimums at 2 degrees).
    Params base;
    base.prism_reflection = 1;
    base.abbe_number = 57;
    base.prism_pitch = 100;
    const std::vector<std::string> held = {"prism_reflection", "dihedral_spread"};
    int wide = 0;
    for (const std::string& name : standard_names()) {
        const RaMeasurements t = read_standard(name);
        if (std::none_of(t.entries.begin(), t.entries.end(),
                         [](const RaEntry& e) { return e.observation_deg >= 1; }))
            continue;
        ++wide;
        const RaColoredFit f = fit_ra_colors(t, base, held, "", RaObjective::Relative);
        std::printf("MEASURED: %s: largest error %.1f%% over %zu rows (pitch %.4g um, cant %.3g "
                    "deg, roughness %.3g)\n",
                    name.c_str(), 100 * f.fit.report.max_error, f.rows.entries.size(),
                    f.fit.params.prism_pitch, f.fit.params.cant_angle, f.fit.params.roughness);
        for (const RaColorFit& c : f.colors)
            std::printf("  colour %-7s retro_color %.4g: largest error %.1f%%\n", c.color.c_str(),
                        c.retro_color[0], 100 * c.report.max_error);
        INFO(name);
        CHECK(f.fit.report.max_error <= 0.30);
    }
    CHECK(wide >= 3); // ISO 20471 and the Austrian types 1 and 2
}

TEST_CASE("The DG983 preset with diffraction: the table within 25%, light kept at 1 degree",
          "[photometry]") {
    // examples/sheeting/dg983_white_tir.mtlx: uncoated prisms, their pitch fitted with the rest
    // to the datasheet's six rows (each the mean of rotations 0 and 90 degrees), minimax.
    const MtlxDocument d = read_mtlx(source("examples/sheeting/dg983_white_tir.mtlx"));
    REQUIRE(d.materials.size() == 1);
    const Params& p = d.materials[0].params;
    CHECK(p.prism_pitch > 50.0);
    CHECK(p.prism_pitch < 200.0);
    CHECK(p.prism_reflection == 1); // tir
    const RaMeasurements dg = read_ra_table(source("examples/sheeting/dg983_white.csv"));
    const std::vector<double> v = ra_node_values(p, dg.entries);
    double worst = 0;
    for (size_t i = 0; i < v.size(); ++i)
        worst = std::max(worst, std::abs(v[i] / dg.entries[i].ra - 1.0));
    // Beyond the table, entrance -4 degrees, the datasheet's mean of rotations 0 and 90.
    std::vector<RaEntry> wide(3);
    const double obs[3] = {0.2, 1.0, 1.5};
    for (int k = 0; k < 3; ++k) {
        wide[size_t(k)].observation_deg = obs[k];
        wide[size_t(k)].entrance_deg = -4;
    }
    const std::vector<double> w = ra_node_values(p, wide);
    std::printf("MEASURED: DG983 preset with diffraction: largest error %.1f%% over %zu rows; "
                "R_A at entrance -4 deg %.1f / %.2f / %.2f at observation 0.2 / 1.0 / 1.5 deg "
                "(%.1f%% and %.2f%% of the 0.2-deg value)\n",
                100 * worst, v.size(), w[0], w[1], w[2], 100 * w[1] / w[0], 100 * w[2] / w[0]);
    // Measured 13.8% (docs/datasheet.md); the bound the preset is made to meet.
    CHECK(worst <= 0.25);
    // Geometric optics keeps about 0.1% at 1 degree (the geometric preset at rotation 0: 0.93
    // of 972): the diffraction tail keeps 5-25% at 1 degree, as microprismatic sheeting does
    // (measured 13.3%), and more than 1% at 1.5 (2.7%).
    CHECK(w[1] / w[0] > 0.05);
    CHECK(w[1] / w[0] < 0.25);
    CHECK(w[2] / w[0] > 0.01);
}

TEST_CASE("fit --ra on the DG983 preset: JSON, plot and a document that ra --document "
          "reproduces",
          "[photometry]") {
    const fs::path dir = temp_dir("fit_ra");
    const std::string table = source("examples/sheeting/dg983_white.csv");
    const fs::path doc = dir / "dg983.mtlx", png = dir / "dg983.png";
    // Six rows: dihedral_spread held at 0, as the preset's command does (examples/sheeting).
    Run r = cli("fit --ra " + table + " --hold dihedral_spread --json --mtlx " + doc.string() +
                " --name dg983_white --plot " + png.string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    const json j = json::parse(r.output.substr(r.output.find('{')));
    REQUIRE(j["entries"].size() == 6);
    const MtlxDocument d = read_mtlx(doc.string());
    REQUIRE(d.materials.size() == 1);
    CHECK(d.materials[0].name == "dg983_white");
    // The document is the JSON's material.
    CHECK(params_to_json(d.materials[0].params) == j["params"]);
    // Its R_A at the table's entries is the fit's, to the digits printed.
    Run ra = cli("ra --document " + doc.string() + " --table " + table);
    INFO(ra.output);
    REQUIRE(ra.status == 0);
    const std::vector<double> v =
        ra_node_values(d.materials[0].params, read_ra_table(table).entries);
    for (size_t i = 0; i < v.size(); ++i) {
        CHECK(v[i] == j["entries"][i]["node"].get<double>());
        char buf[32];
        std::snprintf(buf, sizeof buf, "%10.4g", v[i]);
        CHECK(contains(ra.output, buf));
    }
    // The document names its source and its errors.
    std::ifstream f(doc);
    const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    CHECK(contains(text, "3M Product Bulletin 983 (2009)"));
    CHECK(contains(text, "largest error"));
    std::ifstream p(png, std::ios::binary);
    char magic[4] = {0, 0, 0, 0};
    p.read(magic, 4);
    CHECK(std::string(magic + 1, 3) == "PNG");
    // A bad table: an error naming file:line, nothing written.
    std::ofstream(dir / "bad.csv") << "observation_deg,entrance_deg,ra\n0.2,-4,800\n9,-4,1\n";
    Run bad =
        cli("fit --ra " + (dir / "bad.csv").string() + " --mtlx " + (dir / "bad.mtlx").string());
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "bad.csv:3, column 1 (observation_deg): 9 is out of range"));
    CHECK_FALSE(fs::exists(dir / "bad.mtlx"));
    fs::remove_all(dir);
}

TEST_CASE("R_A table reader: colours and the kind of table", "[photometry]") {
    const RaMeasurements t = table_of("# kind: minimum\nobservation_deg,entrance_deg,color,ra\n"
                                      "0.2,-4,white,70\n0.2,-4,yellow,50\n0.5,30,yellow,13\n");
    CHECK(t.kind == RaKind::Minimum);
    REQUIRE(t.entries.size() == 3);
    CHECK(t.entries[0].color == "white");
    CHECK(t.entries[1].color == "yellow");
    CHECK(ra_table_colors(t) == std::vector<std::string>{"white", "yellow"});
    const RaMeasurements yellow = ra_color_rows(t, "yellow");
    REQUIRE(yellow.entries.size() == 2);
    CHECK(yellow.entries[1].line == 5);
    CHECK(yellow.kind == RaKind::Minimum);
    // Every existing table reads as before: measured, no colour.
    const RaMeasurements dg = read_ra_table(source("examples/sheeting/dg983_white.csv"));
    CHECK(dg.kind == RaKind::Measured);
    CHECK(ra_table_colors(dg).empty());
    CHECK(table_of("# kind: measured\nobservation_deg,entrance_deg,ra\n0.2,-4,8\n").kind ==
          RaKind::Measured);
    const std::string head = "observation_deg,entrance_deg,color,ra\n";
    const std::string allowed = "expected one of " + [] {
        std::string s;
        for (const std::string& c : ra_colors())
            s += (s.empty() ? "" : ", ") + c;
        return s;
    }();
    struct Case {
        std::string text, expect;
    };
    const std::vector<Case> cases = {
        {head + "0.2,-4,purple,5\n",
         "t.csv:2, column 3 (color): \"purple\" is not a sheeting colour; " + allowed},
        {head + "0.2,-4,,5\n", "t.csv:2, column 3 (color): \"\" is not a sheeting colour"},
        {head + "0.2,-4,White,5\n", "t.csv:2, column 3 (color): \"White\" is not a sheeting"},
        {head + "0.2,-4,red,5\n0.2,-4,red,6\n",
         "t.csv:3: a second row for colour red, observation 0.2, entrance -4"},
        {"# kind: typical\n" + head,
         "t.csv:1: \"# kind: typical\" is not a kind of table; expected measured or minimum"},
        {"# kind: minimum\n# kind: minimum\n" + head,
         "t.csv:2: a second \"# kind:\" line; expected at most one per file"},
        {"observation_deg,entrance_deg,color,ra,color\n",
         "t.csv:1, column 5: column \"color\" appears twice"},
    };
    check_table_errors(cases);
    try {
        ra_color_rows(t, "red");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(
            contains(e.what(), "t.csv: no rows of colour red; the table's colours: white, yellow"));
    }
}

TEST_CASE("ra --standard: the bundled tables, a material judged per entry of its colour",
          "[photometry]") {
    const std::vector<std::string> names = standard_names();
    for (const char* n : {"astm-d4956-i", "astm-d4956-ii", "iso-20471", "ansi-isea-107-level2",
                          "at-stvzvo-1998-type1", "at-stvzvo-1998-type2"})
        CHECK(std::count(names.begin(), names.end(), n) == 1);
    // Every bundled table is a table of minimums that cites its source.
    for (const std::string& n : names) {
        INFO(n);
        const RaMeasurements t = read_standard(n);
        CHECK(t.kind == RaKind::Minimum);
        std::string comments;
        for (const std::string& c : t.comments)
            comments += c + "\n";
        CHECK(contains(comments, "Source"));
        CHECK(contains(comments, "http"));
    }
    const RaMeasurements astm = read_standard("astm-d4956-i");
    const Params dg = read_mtlx(source("examples/sheeting/dg983_white.mtlx")).materials[0].params;
    const StandardJudgement white = judge_standard(astm, dg);
    CHECK(white.color == "white");
    REQUIRE(white.entries.size() == 4);
    // The material's values are ra_node_values' at the rows, each against its minimum.
    std::vector<RaEntry> rows;
    for (const StandardEntry& s : white.entries)
        rows.push_back(s.entry);
    const std::vector<double> v = ra_node_values(dg, rows);
    for (size_t i = 0; i < v.size(); ++i) {
        CHECK(white.entries[i].material == v[i]);
        CHECK(white.entries[i].pass == (v[i] >= rows[i].ra));
        CHECK(rows[i].color == "white");
    }
    CHECK(white.entries[0].entry.ra == 70.0);
    CHECK(white.pass);
    // The same material judged as brown (lower minimums) passes; a dim one fails.
    CHECK(judge_standard(astm, dg, "brown").entries.front().entry.ra == 1.0);
    Params dim = dg;
    dim.retro_color = {0.01, 0.01, 0.01};
    const StandardJudgement fail = judge_standard(astm, dim);
    CHECK_FALSE(fail.pass);
    CHECK(std::any_of(fail.entries.begin(), fail.entries.end(),
                      [](const StandardEntry& s) { return !s.pass; }));
    // A table without a colour column holds for every colour.
    const RaMeasurements iso = read_standard("iso-20471");
    CHECK(judge_standard(iso, dg, "yellow").entries.size() == iso.entries.size());
    struct Case {
        std::string name, color, expect;
    };
    const std::vector<Case> errors = {
        {"astm-d4956-xi", "white",
         "--standard astm-d4956-xi: no such standard table; the "
         "bundled ones: ansi-isea-107-level1, "},
        {"astm-d4956-i", "purple",
         "--color purple: not a sheeting colour; expected one of white, "},
        {"astm-d4956-i", "grey",
         "astm-d4956-i.csv: no rows of colour grey; the table's colours: "
         "white, yellow, orange, green, red, blue, brown"},
    };
    for (const Case& c : errors) {
        INFO(c.name << " " << c.color);
        try {
            judge_standard(read_standard(c.name), dg, c.color);
            FAIL("no error");
        } catch (const InputError& e) {
            CHECK(contains(e.what(), c.expect));
        }
    }
    // The command prints the same judgement.
    Run r = cli("ra --document " + source("examples/sheeting/dg983_white.mtlx") +
                " --standard astm-d4956-i --color yellow");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(contains(r.output, "astm-d4956-i, colour yellow: pass (4 of 4 entries at or above"));
    Run list = cli("ra --standard list");
    CHECK(contains(list.output, "iso-20471"));
    Run bad = cli("ra --color red");
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "--color goes with --standard NAME"));
}

TEST_CASE("fit --ra on a coloured table: the geometry from the white rows, each colour's "
          "retro_color from its rows with the base's hue",
          "[photometry]") {
    Params truth;
    truth.roughness = 0.02;
    truth.ior = 1.58;
    truth.prism_reflection = 1; // tir
    truth.retro_color = {0.7, 0.7, 0.7};
    Params yellow = truth;
    yellow.retro_color = {0.8, 0.6, 0.05};
    const std::vector<double> obs = {0.2, 0.33, 0.5, 1.0}, ent = {-4.0, 15.0, 30.0, 40.0};
    RaMeasurements t = synthetic_table(truth, obs, ent);
    for (RaEntry& e : t.entries)
        e.color = "white";
    for (RaEntry e : synthetic_table(yellow, obs, ent).entries) {
        e.color = "yellow";
        e.line += int(obs.size() * ent.size());
        t.entries.push_back(e);
    }
    // The hue from the base: the truth's yellow at another brightness.
    Params base;
    base.retro_color = {0.4, 0.3, 0.025};
    const RaColoredFit f = fit_ra_colors(t, base, {}, "yellow");
    REQUIRE(f.colors.size() == 2);
    CHECK(f.colors[0].color == "white");
    CHECK(f.rows.entries.size() == obs.size() * ent.size());
    CHECK(f.rows.entries.front().color == "yellow");
    // The geometry is recovered from the white rows as by the uncoloured fit (its 1e-3), and
    // the yellow retro_color, a scale of the base's hue fitted on exact values, with it.
    CHECK(f.fit.params.prism_reflection == 1);
    CHECK(f.fit.params.roughness == Approx(0.02).epsilon(1e-3));
    CHECK(f.colors[0].retro_color[0] == Approx(0.7).epsilon(1e-3));
    for (size_t c = 0; c < 3; ++c)
        CHECK(f.fit.params.retro_color[c] == Approx(yellow.retro_color[c]).epsilon(1e-3));
    CHECK(f.colors[1].retro_color == f.fit.params.retro_color);
    CHECK(f.fit.report.max_error < 1e-3);
    std::printf("MEASURED: fit --ra on %zu white and %zu yellow synthetic rows: yellow "
                "retro_color (%.6g, %.6g, %.6g) for (0.8, 0.6, 0.05), largest error %.2e\n",
                obs.size() * ent.size(), obs.size() * ent.size(), f.fit.params.retro_color[0],
                f.fit.params.retro_color[1], f.fit.params.retro_color[2], f.fit.report.max_error);
    // A grey base cannot give the hue: the luminance matches, the colour is grey.
    const RaColoredFit grey = fit_ra_colors(t, Params(), {}, "yellow");
    CHECK(grey.fit.params.retro_color[0] == grey.fit.params.retro_color[2]);
    CHECK(luminance_709(glm::dvec3(grey.fit.params.retro_color[0], grey.fit.params.retro_color[1],
                                   grey.fit.params.retro_color[2])) ==
          Approx(luminance_709(glm::dvec3(0.8, 0.6, 0.05))).epsilon(1e-3));
    try {
        fit_ra_colors(t, base, {}, "red");
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(contains(e.what(), "synthetic.csv: no rows of colour red; the table's colours: "
                                 "white, yellow"));
    }
    // The command: the chosen colour's rows and material, every colour's retro_color.
    const std::string astm = source("examples/standards/astm-d4956-ii.csv");
    Run r =
        cli("fit --ra " + astm + " --material " + source("examples/materials/yellow_sign.json") +
            " --color yellow --hold cant_angle,dihedral_error,dihedral_spread --json");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const json j = json::parse(r.output.substr(r.output.find('{')));
    CHECK(j["entries"].size() == 4);
    CHECK(j["colors"].size() == 7);
    CHECK(j["params"]["retro_color"] == j["colors"]["yellow"]["retro_color"]);
    Run bad = cli("fit --ra " + astm + " --color purple");
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "astm-d4956-ii.csv: no rows of colour purple; the table's "
                               "colours: white, yellow, orange"));
}

TEST_CASE("ALTA file without #PARAM_OUT: read as BRDF x cos(theta_v) with a warning, or as "
          "--param-out says",
          "[photometry]") {
    const std::string text = "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n"
                             "0.5 1.0471975511965976 0 2.0\n";
    const AltaData a = parse_alta(text, "n.dat");
    CHECK(a.cosine_factor);
    CHECK(a.param_out == "INV_STERADIAN_COSINE_FACTOR");
    CHECK(contains(a.warning, "n.dat: no #PARAM_OUT before the data (line 3); the values are "
                              "taken as BRDF x cos(theta_v) (INV_STERADIAN_COSINE_FACTOR"));
    CHECK(a.samples[0].value_cos(a.cosine_factor) == 2.0);
    const AltaData b = parse_alta(text, "n.dat", "INV_STERADIAN");
    CHECK_FALSE(b.cosine_factor);
    CHECK(b.warning.empty());
    CHECK(b.samples[0].value_cos(b.cosine_factor) == Approx(1.0));
    // A file that has #PARAM_OUT: no warning; a contradicting --param-out is an error.
    const std::string declared = "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n"
                                 "#PARAM_OUT INV_STERADIAN_COSINE_FACTOR\n0.5 0 0 1\n";
    CHECK(parse_alta(declared, "d.dat").warning.empty());
    for (const auto& [file, paramOut, expect] :
         std::vector<std::tuple<std::string, std::string, std::string>>{
             {declared, "INV_STERADIAN",
              "d.dat:3: #PARAM_OUT INV_STERADIAN_COSINE_FACTOR "
              "contradicts --param-out INV_STERADIAN"},
             {text, "RGB", "--param-out RGB: expected INV_STERADIAN_COSINE_FACTOR"},
             {text + "#PARAM_OUT INV_STERADIAN\n", "", "d.dat:4: #PARAM_OUT after data lines"}}) {
        try {
            parse_alta(file, "d.dat", paramOut);
            FAIL("no error");
        } catch (const InputError& e) {
            CHECK(contains(e.what(), expect));
        }
    }
    // retroprism fit prints the warning and fits: the 3M file without its #PARAM_OUT line, every
    // eighth measurement of it and the paper's geometry at a fixed ior (the reading is what is
    // tested here; "Fit: the 3M measurement" fits the whole file).
    const fs::path dir = temp_dir("alta_no_param_out");
    {
        std::ifstream in(source("tests/data/belcour2014/retro-3M-jaune.dat"));
        std::ofstream out(dir / "no_param_out.dat");
        std::string line;
        long data = 0;
        while (std::getline(in, line)) {
            if (line.rfind("#PARAM_OUT", 0) == 0) continue;
            if (line.rfind("#", 0) == 0 || ++data % 8 == 0) out << line << "\n";
        }
    }
    Run r = cli("fit --json --paper-geometry --ior 1.49 " + (dir / "no_param_out.dat").string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(contains(r.output, "warning: " + (dir / "no_param_out.dat").string() +
                                 ": no #PARAM_OUT before the data"));
    fs::remove_all(dir);
}

TEST_CASE("A sign's luminance on approach: the driver's geometry and L = R_A E / cos(theta_o)",
          "[photometry]") {
    Params p;
    p.roughness = 0.01;
    ApproachSettings s;
    const std::vector<ApproachPoint> a = approach_luminance(node_lobes(p), s);
    REQUIRE(a.size() == size_t(s.steps));
    CHECK(a.front().distance == s.far_m);
    CHECK(a.back().distance == s.near_m);
    // The 30 m geometry of ASTM E1710: observation angle 1.05 degrees (the sign's offset from
    // the road's axis changes it by a few thousandths).
    CHECK(a.back().observation_deg == Approx(1.05).margin(0.02));
    CHECK(a.front().observation_deg == Approx(std::atan(0.55 / 300.0) / kDeg).epsilon(0.02));
    for (const ApproachPoint& q : a) {
        const double r2 =
            q.distance * q.distance + s.sign_right * s.sign_right + s.sign_up * s.sign_up;
        // cos(theta_o) of the eye is that of the lamp to within the observation angle.
        const double cosO = std::cos(q.entrance_deg * kDeg);
        CHECK(q.luminance == Approx(q.ra * s.lamp_cd / r2 / cosO).epsilon(2e-3));
    }
    // The luminance scales with the lamp; the R_A does not.
    ApproachSettings bright = s;
    bright.lamp_cd = 2 * s.lamp_cd;
    const std::vector<ApproachPoint> b = approach_luminance(node_lobes(p), bright);
    CHECK(b[10].luminance == Approx(2 * a[10].luminance).epsilon(1e-12));
    CHECK(b[10].ra == a[10].ra);
    // The baseline's lobes: its f.
    baselines::RetroreflectiveGGX m;
    const LobeBrdf lobes = mrm_lobes(m);
    const glm::dvec3 wi(0.3, 0.1, std::sqrt(0.9)), wo(0.2, 0.0, std::sqrt(0.96));
    glm::dvec3 l[3];
    lobes(wi, wo, l);
    CHECK(luminance_709(l[0] + l[1] + l[2]) == Approx(luminance_709(m.f(wi, wo))).epsilon(1e-12));
}

TEST_CASE("render_night: rows on every core give the same image twice and no anomaly",
          "[photometry][threads]") {
    // The preview renders its rows on every core (parallel_for); a small image twice must give
    // the same pixels (rows are computed alone) and no anomaly; under ThreadSanitizer
    // (scripts/tsan.sh) no race either.
    NightSettings s;
    s.width = 48;
    s.height = 27;
    s.spp = 1;
    const NightImage a = render_night(Params(), s);
    const NightImage b = render_night(Params(), s);
    CHECK(a.anomalies == 0);
    CHECK(a.retro == b.retro);
    CHECK(a.diffuse == b.diffuse);
    double sum = 0;
    for (float v : a.retro)
        sum += v;
    CHECK(sum > 0);
}
