// [cli]: the command-line tool: the JSON query interface answers what the library computes,
// and every bad input is rejected with a message naming what was wrong, a non-zero status
// and no output file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "backend.h"
#include "glsl_gen.h"
#include "photometry.h"
#include "query.h"
#include "ra_fit.h"
#include "ra_table.h"
#include "test_support.h"
#include "wave_node.h"

using namespace retroprism;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

using Run = rptest::CommandRun;
using rptest::contains;

// A temporary path named with the process id: test runs of other checkouts share the folder.
fs::path temp_path(const std::string& name) {
    return fs::temp_directory_path() /
           ("retroprism_test_" + std::to_string(::getpid()) + "_" + name);
}

// The command with `args`, its standard input from stdinText when that is not empty.
Run run(const std::string& args, const std::string& stdinText = "") {
    if (stdinText.empty()) return rptest::run_cli(args);
    const fs::path in = temp_path("stdin.json");
    std::ofstream(in) << stdinText;
    return rptest::run_cli(args + " < " + in.string());
}

fs::path write_temp(const std::string& name, const std::string& text) {
    fs::path p = temp_path(name);
    std::ofstream(p) << text;
    return p;
}

} // namespace

TEST_CASE("eval answers the library's values, per backend", "[cli]") {
    const std::string query = R"({"material": {"roughness": 0.1, "ior": 1.586,
        "prism_reflection": "tir", "era_mode": "oriented", "orientation": 40, "cant_angle": 12,
        "diffuse_color": [0.9, 0.8, 0.1], "retro_color": [1, 0.9, 0.2]},
      "samples": [{"wi": [0.3, 0.1, 0.9], "wo": [0.3, 0.1, 0.9]},
                  {"wi_deg": [30, 0], "wo_deg": [30, 0]},
                  {"wi_deg": [45, 20], "wo_deg": [45, 200]},
                  {"wi": [0, 0, 1], "wo": [0.2, 0, -0.1]}]})";
    const fs::path file = write_temp("query.json", query);
    Query q = parse_query(json::parse(query), "query");
    for (const char* backend : {"cpp-double", "cpp-float"}) {
        INFO(backend);
        Run r = run(std::string("eval --backend ") + backend + " " + file.string());
        REQUIRE(r.status == 0);
        json answer = json::parse(r.output);
        CHECK(answer["backend"] == backend);
        REQUIRE(answer["results"].size() == q.samples.size());
        // The CLI's numbers are the library's, to the last bit (JSON keeps 17 digits).
        json direct = answer_query(q, backend);
        CHECK(answer == direct);
        for (const json& res : answer["results"])
            for (const char* key : {"f", "surface", "retro", "diffuse"})
                CHECK(res[key].size() == 3);
    }
    // The same query on standard input; degrees and vectors describe the same directions.
    Run r = run("eval -", query);
    REQUIRE(r.status == 0);
    json a = json::parse(r.output);
    CHECK(a["backend"] == "cpp-double");
    PrismaticRetroreflector<double> node(q.material);
    const glm::dvec3 w30 = rptest::dir_deg(30, 0);
    CHECK(a["results"][1]["retro"][0].get<double>() == node.eval(w30, w30).f.retro.x);
    CHECK(a["results"][3]["pdf"].get<double>() == 0.0); // wo below the horizon
}

TEST_CASE("Bad queries and materials are rejected, naming what is wrong", "[cli]") {
    struct Case {
        const char* what;
        const char* text;
        const char* expect; // part of the message
    };
    const Case cases[] = {
        {"out of range", R"({"material": {"roughness": 2}, "samples": []})",
         "material.roughness = 2 is outside its range [0, 1]"},
        {"unknown input", R"({"material": {"roughnes": 0.1}, "samples": []})",
         "material.roughnes: unknown input"},
        {"bad enum", R"({"material": {"era_mode": "sideways"}, "samples": []})",
         "material.era_mode: expected one of \"averaged,matched_pair,oriented\""},
        {"colour size", R"({"material": {"diffuse_color": [1, 0]}, "samples": []})",
         "material.diffuse_color: expected an array of 3 numbers in [0, 1]"},
        {"colour range", R"({"material": {"retro_color": [1, 0, -0.5]}, "samples": []})",
         "material.retro_color[2] = -0.5 is outside its range [0, 1]"},
        {"wrong type", R"({"material": {"ior": "glass"}, "samples": []})",
         "material.ior: expected a number in [1, 3]"},
        {"no samples", R"({"material": {}})", "\"samples\" must be an array"},
        {"unknown field", R"({"materials": {}, "samples": []})", "unknown field \"materials\""},
        {"half a sample", R"({"samples": [{"wi": [0, 0, 1]}]})", "samples[0]"},
        {"mixed forms", R"({"samples": [{"wi": [0, 0, 1], "wo_deg": [10, 0]}]})", "samples[0]"},
        {"zero direction", R"({"samples": [{"wi": [0, 0, 0], "wo": [0, 0, 1]}]})",
         "samples[0].wi: a direction must not be the zero vector"},
        {"theta range", R"({"samples": [{"wi_deg": [190, 0], "wo_deg": [0, 0]}]})",
         "samples[0].wi_deg[0] (theta) = 190 is outside its range [0, 180]"},
        {"syntax", "{\"samples\": [\n  {\"wi\": [0, 0, 1],, }\n]}", ":2:"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        const fs::path file = write_temp("bad.json", c.text);
        Run r = run("eval " + file.string());
        CHECK(r.status != 0);
        CHECK(contains(r.output, c.expect));
        CHECK(contains(r.output, file.string())); // the file is named
        CHECK_FALSE(contains(r.output, "{\"backend\""));
    }
    Run missing = run("eval /nonexistent/query.json");
    CHECK(missing.status != 0);
    CHECK(contains(missing.output, "/nonexistent/query.json: cannot open file"));
    Run backend =
        run("eval --backend vulkan " + write_temp("ok.json", R"({"samples": []})").string());
    CHECK(backend.status != 0);
    CHECK(contains(backend.output,
                   "unknown backend (backends: cpp-double, cpp-float, cpp-batch, glsl, "
                   "materialx, materialx-portable)"));
}

TEST_CASE("era and albedo commands", "[cli]") {
    Run normal = run("era --theta-t 0");
    REQUIRE(normal.status == 0);
    CHECK(contains(normal.output, "ERA 0.666666667"));
    // Oriented at theta_t = 20 deg equals the core's value for that inner direction.
    Run oriented = run("era --theta-t 20 --phi 30 --mode oriented");
    REQUIRE(oriented.status == 0);
    const double t = 20 * M_PI / 180, p = 30 * M_PI / 180;
    char expect[64];
    std::snprintf(expect, sizeof expect, "ERA %.9f",
                  f64::rp_era_oriented(
                      f64::vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), -std::cos(t)),
                      f64::RP_ERA_V1, f64::RP_ERA_V2, f64::RP_ERA_V3));
    CHECK(contains(oriented.output, expect));
    CHECK(run("era").status != 0);
    Run badMode = run("era --theta-t 10 --mode tilted");
    CHECK(badMode.status != 0);
    CHECK(contains(badMode.output, "--mode tilted: expected averaged, matched_pair or oriented"));
    Run badTheta = run("era --theta-t 95");
    CHECK(badTheta.status != 0);
    CHECK(contains(badTheta.output, "--theta-t: must be in [0, 90) degrees"));
    // Canted cubes at normal incidence: MODEL.md section 8's checked values (4 decimals).
    const std::pair<const char*, const char*> canted[] = {
        {"-10", "ERA 0.5295"}, {"10", "ERA 0.4908"}, {"20", "ERA 0.2108"}};
    for (const auto& [cant, era] : canted) {
        Run c = run(std::string("era --theta-t 0 --cant ") + cant);
        REQUIRE(c.status == 0);
        CHECK(contains(c.output, era));
    }
    Run badCant = run("era --theta-t 10 --cant 40");
    CHECK(badCant.status != 0);
    CHECK(contains(badCant.output, "--cant 40: expected a number in [-30, 30]"));

    Run albedo = run("albedo --theta-i 0 45");
    REQUIRE(albedo.status == 0);
    CHECK(contains(albedo.output, "surface"));
    Run badAngle = run("albedo --theta-i 10 95");
    CHECK(badAngle.status != 0);
    CHECK(contains(badAngle.output, "--theta-i 95: must be in [0, 90) degrees"));
    CHECK_FALSE(contains(badAngle.output, "theta_i      surface")); // nothing printed first
    const fs::path bad = write_temp("material.json", R"({"ior": 0.5})");
    Run badMaterial = run("albedo --material " + bad.string() + " --theta-i 10");
    CHECK(badMaterial.status != 0);
    CHECK(contains(badMaterial.output, bad.string() + ".ior = 0.5 is outside its range [1, 3]"));
}

TEST_CASE("demo writes every material's plots, or nothing on a bad material", "[cli]") {
    const fs::path out = temp_path("demo");
    fs::remove_all(out);
    Run good = run("demo --materials " + std::string(RP_SOURCE_DIR) + "/examples/materials --out " +
                   out.string());
    REQUIRE(good.status == 0);
    int exr = 0, png = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        exr += e.path().extension() == ".exr";
        png += e.path().extension() == ".png";
    }
    CHECK(exr >= 5);
    CHECK(png >= 5);

    const fs::path mats = temp_path("bad_materials");
    fs::remove_all(mats);
    fs::create_directories(mats);
    std::ofstream(mats / "good.json") << R"({"roughness": 0.1})";
    std::ofstream(mats / "bad.json") << R"({"roughness": 1.5})";
    const fs::path out2 = temp_path("demo_bad");
    fs::remove_all(out2);
    Run bad = run("demo --materials " + mats.string() + " --out " + out2.string());
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "bad.json.roughness = 1.5 is outside its range [0, 1]"));
    bool anyFile = false;
    if (fs::exists(out2))
        for (const auto& e : fs::directory_iterator(out2))
            anyFile = anyFile || e.is_regular_file();
    CHECK_FALSE(anyFile);
}

TEST_CASE("The documentation's inputs table is the parameter table", "[cli]") {
    std::ifstream in(std::string(RP_SOURCE_DIR) + "/docs/model.md");
    std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string begin = "<!-- params:begin -->\n", end = "<!-- params:end -->";
    size_t a = page.find(begin), b = page.find(end);
    REQUIRE(a != std::string::npos);
    REQUIRE(b != std::string::npos);
    CHECK(page.substr(a + begin.size(), b - a - begin.size()) == params_markdown());
    Run r = run("params");
    CHECK(r.status == 0);
    CHECK(r.output == params_markdown());
}

TEST_CASE("export writes the MaterialX library as checked in and the GLSL as generated", "[cli]") {
    const fs::path out = temp_path("export");
    fs::remove_all(out);
    Run r = run("export --out " + out.string());
    REQUIRE(r.status == 0);
    auto read = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const fs::path src = RP_SOURCE_DIR;
    int compared = 0;
    for (const auto& e : fs::recursive_directory_iterator(src / "materialx" / "rp_pbrlib")) {
        if (!e.is_regular_file()) continue;
        const fs::path rel = fs::relative(e.path(), src / "materialx");
        CHECK(read(out / rel) == read(e.path()));
        ++compared;
    }
    for (const glsl::Variant& v : glsl::standard_variants()) {
        CHECK(read(out / "glsl" / (v.name + ".glsl")) == glsl::generate_library(v, src.string()));
        ++compared;
    }
    CHECK(read(out / "glsl" / "mrm_ggx.glsl") == glsl::generate_baseline_library(src.string()));
    CHECK(compared >= 19);
    CHECK(fs::exists(out / "README.md"));
    Run bad = run("export --out /proc/retroprism");
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "--out /proc/retroprism: cannot create the folder"));
}

TEST_CASE("bench --json prints the trade table's rows", "[cli]") {
    Run r = run("bench --json --min-time 0.01");
    REQUIRE(r.status == 0);
    const json out = json::parse(r.output);
    REQUIRE(out["rows"].size() >= 10);
    bool sawMrm = false, sawFast = false;
    for (const json& row : out["rows"]) {
        for (const char* key : {"tier", "lobes", "ns_per_eval", "ratio_to_mrm", "rel_l1_error"})
            CHECK(row.contains(key));
        CHECK(row["ns_per_eval"].get<double>() > 0);
        if (row["name"] == "mrm_ggx") {
            sawMrm = true;
            CHECK(row["ratio_to_mrm"].get<double>() == 1.0);
        }
        if (row["tier"] == "fast") {
            sawFast = true;
            // The fast tier's error against the reference is measured, not assumed.
            CHECK(row["rel_l1_error"].get<double>() > 0);
        }
    }
    CHECK(sawMrm);
    CHECK(sawFast);
    // Node construction, made and kept, for each material with series.
    REQUIRE(out["construction"].size() == 3);
    for (const json& c : out["construction"]) {
        CHECK(c["ms_made"].get<double>() > 0);
        CHECK(c["ms_kept"].get<double>() > 0);
    }
    CHECK(out["construction"][0]["name"] == "exact_tir");
    // A shading point from wi and from the incident state, for each of its materials.
    REQUIRE(out["shading_point"].size() == 7);
    for (const json& c : out["shading_point"]) {
        CHECK(c["ns_from_wi"].get<double>() > 0);
        CHECK(c["ns_from_state"].get<double>() > 0);
    }
    CHECK(out["shading_point"][2]["name"] == "exact_diffraction_rgb");
    CHECK(run("bench --min-time 100").status != 0);
    for (const char* reps : {"0", "21", "2.5", "x"}) {
        const Run bad = run(std::string("bench --repetitions ") + reps);
        CHECK(bad.status != 0);
        CHECK(contains(bad.output, "expected a whole number in [1, 20]"));
    }
}

TEST_CASE("export --max-error picks the cheapest variant that fits the document", "[cli]") {
    const fs::path out = temp_path("export_choice");
    fs::remove_all(out);
    const std::string doc = std::string(RP_SOURCE_DIR) + "/examples/documents/white_sign.mtlx";
    Run r = run("export --out " + out.string() + " --document " + doc + " --max-error 0");
    REQUIRE(r.status == 0);
    // white_sign: uncoated prisms in matched pairs, all three lobes: the variant fixing exactly
    // those modes is the smallest that fits; with no error allowed the fast tier is out.
    CHECK(contains(r.output, "chosen: prismatic_retroreflector_matched_pair_tir"));
    CHECK(fs::exists(out / "glsl" / "selected_white_sign.glsl"));
    Run bad = run("export --out " + out.string() + " --document " + doc + " --max-error 2");
    CHECK(bad.status != 0);
    CHECK(contains(bad.output, "--max-error 2: expected a relative error in [0, 1]"));
}

TEST_CASE("fit --ra --baseline-only fits the GGX baseline alone; options of the node's fit are "
          "refused",
          "[cli]") {
    // A table the baseline itself makes (its Lambert colour the fit's 0.8), at the look-dev
    // page's angles and rotation 0, written to 17 digits: the fit must find it again.
    baselines::RetroreflectiveGGX truth;
    truth.roughness = 0.03;
    truth.ior = 1.6;
    truth.specular = 0.8;
    RaMeasurements t;
    for (double a : ra_observation_angles())
        for (double b : ra_entrance_angles()) {
            RaEntry e;
            e.observation_deg = a;
            e.entrance_deg = b;
            e.rotation_deg = 0.0;
            t.entries.push_back(e);
        }
    const std::vector<double> ra = ra_mrm_values(truth, t.entries);
    std::string csv = "observation_deg,entrance_deg,rotation_deg,ra\n";
    for (size_t i = 0; i < ra.size(); ++i) {
        char row[128];
        std::snprintf(row, sizeof row, "%.17g,%.17g,0,%.17g\n", t.entries[i].observation_deg,
                      t.entries[i].entrance_deg, ra[i]);
        csv += row;
    }
    const fs::path table = write_temp("baseline_table.csv", csv);
    Run r = run("fit --ra " + table.string() + " --baseline-only --json");
    REQUIRE(r.status == 0);
    const json j = json::parse(r.output);
    auto keys = [](const json& o) {
        std::vector<std::string> k;
        for (auto it = o.begin(); it != o.end(); ++it)
            k.push_back(it.key());
        return k;
    };
    CHECK(keys(j) == std::vector<std::string>{"mrm", "table"});
    CHECK(j["table"] == table.string());
    CHECK(keys(j["mrm"]) == std::vector<std::string>{"entries", "log_rms", "max_error", "params"});
    CHECK(keys(j["mrm"]["params"]) ==
          std::vector<std::string>{"color", "ior", "roughness", "specular", "tint"});
    // No noise: the parameters within 1%, the fit within the rounding of its values to 6 digits.
    const json& p = j["mrm"]["params"];
    CHECK(p["roughness"].get<double>() == Approx(truth.roughness).epsilon(0.01));
    CHECK(p["ior"].get<double>() == Approx(truth.ior).epsilon(0.01));
    CHECK(p["specular"].get<double>() == Approx(truth.specular).epsilon(0.01));
    CHECK(p["tint"] == json({1.0, 1.0, 1.0}));
    CHECK(p["color"] == json({0.8, 0.8, 0.8}));
    CHECK(j["mrm"]["log_rms"].get<double>() < 1e-3);
    // Each entry: where it was measured, the measured value as read, and the fitted baseline's
    // R_A as the library computes it for the printed parameters (to rounding).
    baselines::RetroreflectiveGGX fitted;
    fitted.roughness = p["roughness"].get<double>();
    fitted.ior = p["ior"].get<double>();
    fitted.specular = p["specular"].get<double>();
    const std::vector<double> expected = ra_mrm_values(fitted, t.entries);
    const json& entries = j["mrm"]["entries"];
    REQUIRE(entries.size() == t.entries.size());
    double worstRel = 0, worstError = 0;
    for (size_t i = 0; i < entries.size(); ++i) {
        const json& e = entries[i];
        CHECK(keys(e) == std::vector<std::string>{"entrance_deg", "line", "mrm", "mrm_error",
                                                  "observation_deg", "presentation_deg", "ra",
                                                  "rotation_deg"});
        CHECK(e["line"] == int(i) + 2);
        CHECK(e["observation_deg"] == t.entries[i].observation_deg);
        CHECK(e["entrance_deg"] == t.entries[i].entrance_deg);
        CHECK(e["rotation_deg"] == 0.0);
        CHECK(e["ra"] == ra[i]);
        worstRel = std::max(worstRel, std::abs(e["mrm"].get<double>() / expected[i] - 1.0));
        worstError = std::max(worstError, std::abs(e["mrm_error"].get<double>()));
    }
    CHECK(worstRel < 1e-12);
    CHECK(j["mrm"]["max_error"].get<double>() == worstError);
    // The text report.
    Run text = run("fit --ra " + table.string() + " --baseline-only");
    CHECK(text.status == 0);
    CHECK(contains(text.output, "mrm (retroreflective GGX + Lambert): roughness"));

    // What goes with the node's fit, or with --ra, is refused, naming the option.
    for (const std::string& option :
         {std::string("--plot ") + temp_path("b.png").string(),
          std::string("--mtlx ") + temp_path("b.mtlx").string(), std::string("--name sheet"),
          std::string("--material ") + table.string()}) {
        Run bad = run("fit --ra " + table.string() + " --baseline-only " + option);
        INFO(option);
        CHECK(bad.status != 0);
        CHECK(contains(bad.output, option.substr(0, option.find(' ')) +
                                       " goes with the node's fit, not --baseline-only"));
    }
    CHECK_FALSE(fs::exists(temp_path("b.png")));
    CHECK_FALSE(fs::exists(temp_path("b.mtlx")));
    Run alta = run("fit " + table.string() + " --baseline-only");
    CHECK(alta.status != 0);
    CHECK(contains(alta.output, "--baseline-only goes with --ra TABLE.csv"));
    Run objective = run("fit " + table.string() + " --objective max");
    CHECK(objective.status != 0);
    CHECK(contains(objective.output, "--objective goes with --ra TABLE.csv"));
    Run minimax = run("fit --ra " + table.string() + " --baseline-only --objective minimax");
    CHECK(minimax.status != 0);
    CHECK(contains(minimax.output, "--objective minimax: not one of rms, max, relative"));
    Run largest = run("fit --ra " + table.string() + " --baseline-only --objective max");
    CHECK(largest.status == 0);
    Run photopic = run("fit --ra " + table.string() + " --baseline-only --photopic");
    CHECK(photopic.status != 0);
    CHECK(contains(photopic.output, "--photopic goes with the node's fit, not --baseline-only"));
    Run photopicAlta = run("fit " + table.string() + " --photopic");
    CHECK(photopicAlta.status != 0);
    CHECK(contains(photopicAlta.output, "--photopic goes with --ra TABLE.csv"));
    // A table the reader refuses: its message, naming the file and line (what the view server
    // passes on to the page).
    const fs::path zero =
        write_temp("baseline_zero.csv", "observation_deg,entrance_deg,rotation_deg,ra\n"
                                        "0.2,-4,0,100\n0.5,-4,0,0\n");
    Run refused = run("fit --ra " + zero.string() + " --baseline-only --json");
    CHECK(refused.status != 0);
    CHECK(contains(refused.output, zero.string() + ":3, column 4 (ra): 0 is out of range"));
    const fs::path empty = write_temp("baseline_empty.csv", "observation_deg,entrance_deg,ra\n");
    Run none = run("fit --ra " + empty.string() + " --baseline-only --json");
    CHECK(none.status != 0);
    CHECK(contains(none.output, empty.string()));
    fs::remove(table);
    fs::remove(zero);
    fs::remove(empty);
}

TEST_CASE("simulate --wave --against-node prints the library's comparison and plots it, or "
          "refuses bad input naming it",
          "[cli]") {
    // One cheap case (ideal faces, pitch 100 um, 1550 nm): the rows are sim/wave_node.h's values.
    const std::vector<double> obs = {0.2, 1.0};
    const std::vector<sim::wave::NodeWaveProfile> truth =
        sim::wave::node_wave_profiles(Params(), {{0, 100.0, 1550.0, -4.0}}, obs, 0.15);
    const fs::path png = temp_path("node_wave.png");
    fs::remove(png);
    const std::string args = "simulate --wave --against-node --pitch 100 --pitch-spread 0.15 "
                             "--wavelength 1550 --entrance -4 --plot " +
                             png.string();
    const Run good = run(args + " --observation 0.2,1");
    INFO(good.output);
    REQUIRE(good.status == 0);
    char row[96];
    std::snprintf(row, sizeof row, "%12g %12.5g %12.5g", obs[1], truth[0].node[1],
                  truth[0].wave[1]);
    CHECK(contains(good.output, row));
    CHECK(contains(good.output, "# ideal, pitch 100 um, 1550 nm, entrance -4 deg"));
    CHECK(contains(good.output, "entries within 10%"));
    CHECK(contains(good.output, "wrote " + png.string()));
    char signature[8] = {};
    std::ifstream(png, std::ios::binary).read(signature, 8);
    CHECK(std::string(signature, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
    fs::remove(png);
    // Bad input: exit status 1, the message naming the option or parameter and its range, no
    // table and no plot.
    struct Bad {
        const char* args;
        const char* message;
    };
    for (const Bad& b :
         {Bad{"--pitch 5000", "pitch 5000: expected a number in [1, 2000] um"},
          Bad{"--wavelength 2500", "wavelength 2500: expected a number in [200, 2000] nm"},
          Bad{"--observation 0.2,x", "--observation 0.2,x: x: expected a number in [1e-09, 20]"},
          Bad{"--photopic", "--against-node: at --wavelength"},
          Bad{"--era oriented", "no --photopic, --coplanar, --era or --rotation"},
          Bad{"--pitch-spread 0.6", "--pitch-spread 0.6: expected a number in "
                                    "[0, 0.5]"}}) {
        const Run r = run(args + " " + b.args);
        INFO(b.args << ": " << r.output);
        CHECK(r.status == 1);
        CHECK(contains(r.output, b.message));
        CHECK_FALSE(contains(r.output, "node/wave"));
        CHECK_FALSE(fs::exists(png));
    }
    const Run alone = run("simulate --wave --plot " + png.string());
    CHECK(alone.status == 1);
    CHECK(contains(alone.output, "--plot: only with --against-node"));
}
