// [cli] `retroprism params --json` and `retroprism view`'s site (web/site.h): the page's controls
// come from the parameter table, its R_A angles and luminance weights from the photometry
// library, its baseline's GLSL from glsl_gen; bad documents and folders are named. The page and
// its server (web/serve.py) run in the ctest entry web.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "embedded_files.h"
#include "error.h"
#include "glsl_gen.h"
#include "photometry.h"
#include "query.h"
#include "site.h"
#include "test_support.h"

using namespace retroprism;
using nlohmann::json;
namespace fs = std::filesystem;

TEST_CASE("params --json is the parameter table", "[cli]") {
    const rptest::CommandRun r = rptest::run_cli("params --json");
    REQUIRE(r.status == 0);
    const json table = json::parse(r.output);
    CHECK(table == params_table_json());
    REQUIRE(table.size() == param_table().size());
    const json defaults = params_to_json(Params{});
    for (size_t i = 0; i < table.size(); ++i) {
        const ParamInfo& info = param_table()[i];
        INFO(info.name);
        CHECK(table[i]["name"] == info.name);
        CHECK(table[i]["default"] == defaults[info.name]);
        if (info.type == ParamType::Float) {
            CHECK(table[i]["type"] == "float");
            CHECK(table[i]["min"] == info.min_value);
            CHECK(table[i]["max"] == info.max_value);
        }
        if (info.type == ParamType::Enum) CHECK(table[i]["values"] == enum_values(info));
    }
}

TEST_CASE("view's site: links, site.json, the document; errors name what is missing", "[cli]") {
    const fs::path dir = fs::temp_directory_path() / "retroprism_test_site";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string doc = std::string(RP_SOURCE_DIR) + "/examples/documents/white_sign.mtlx";
    const std::string baseline = embedded_variant("mrm_ggx");
    CHECK(baseline == glsl::generate_baseline_library(RP_SOURCE_DIR));
    const Site site = make_site(RP_SOURCE_DIR, (dir / "a").string(), doc, baseline);
    CHECK(site.page == "/web/index.html");
    CHECK(site.server == std::string(RP_SOURCE_DIR) + "/web/serve.py");
    for (const char* f : {"web/index.html", "web/main.js", "web/baseline.js", "web/serve.py",
                          "materialx/rp_pbrlib/rp_pbrlib_defs.mtlx",
                          "examples/documents/white_sign.mtlx", "document.mtlx"})
        CHECK(fs::exists(dir / "a" / f));
    // The baseline's GLSL where site.json says.
    std::ifstream glslIn(dir / "a" / fs::path(kBaselineGlslUrl).relative_path());
    CHECK(std::string(std::istreambuf_iterator<char>(glslIn), {}) == baseline);
    std::ifstream in(dir / "a" / "site.json");
    const json j = json::parse(in);
    CHECK(j["params"] == params_table_json());
    CHECK(j["ra"]["observation"] == json(ra_observation_angles()));
    CHECK(j["ra"]["entrance"] == json(ra_entrance_angles()));
    CHECK(j["document"] == "/document.mtlx");
    CHECK(j["baseline"] == kBaselineGlslUrl);
    // The luminance weights are luminance_709's: they sum to 1 and weigh green most.
    CHECK(j["luminance"][0].get<double>() + j["luminance"][1].get<double>() +
              j["luminance"][2].get<double>() ==
          Approx(1.0).epsilon(1e-12));
    CHECK(json::parse(site_json("/x.mtlx"))["document"] == "/x.mtlx");

    CHECK_THROWS_WITH(make_site(RP_SOURCE_DIR, (dir / "a").string(), "", baseline),
                      Catch::Contains("cannot create the site's folder (it exists)"));
    CHECK_THROWS_WITH(
        make_site(RP_SOURCE_DIR, (dir / "b").string(), (dir / "nope.mtlx").string(), baseline),
        Catch::Contains("nope.mtlx: the document not found"));
    CHECK_THROWS_WITH(make_site(dir.string(), (dir / "c").string(), "", baseline),
                      Catch::Contains("web/index.html: the look-dev page not found"));
    // A data folder with the page but not its server.
    fs::create_directories(dir / "data" / "web");
    std::ofstream(dir / "data" / "web" / "index.html") << "<!doctype html>";
    CHECK_THROWS_WITH(make_site((dir / "data").string(), (dir / "d").string(), "", baseline),
                      Catch::Contains("web/serve.py: the look-dev page's server not found"));
    fs::remove_all(dir);
}

TEST_CASE("view rejects a bad document or port before serving", "[cli]") {
    const fs::path bad = fs::temp_directory_path() / "retroprism_test_view_bad.mtlx";
    std::ofstream(bad) << "<materialx version=\"1.39\"><surfacematerial name=\"m\"";
    rptest::CommandRun r = rptest::run_cli("view " + bad.string() + " --no-open");
    CHECK(r.status != 0);
    CHECK(rptest::contains(r.output, bad.string()));
    r = rptest::run_cli("view --port 0 --no-open");
    CHECK(r.status != 0);
    CHECK(rptest::contains(r.output, "--port"));
    fs::remove(bad);
}
