// [lidar] (the OpenMATERIAL part): `retroprism export --format openmaterial` of the bundled
// microprismatic material written, read back and checked against the node: every row to the
// printed precision, the table's interpolation at its rows exact and between them measured, the
// LiDAR return through the table against the node's; the material file's R_A; the reader's
// errors, each naming the field; the fuzz target's corpus replayed through its check.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "../../fuzz/fuzz_checks_openmaterial.h"
#include "error.h"
#include "lidar.h"
#include "openmaterial.h"
#include "openmaterial_export.h"
#include "query.h"
#include "test_support.h"

using namespace retroprism;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

Params plate() {
    const std::string f =
        std::string(RP_SOURCE_DIR) + "/examples/materials/microprismatic_160um.json";
    return params_from_json(read_json(f), f);
}

// The exported files of the plate, once per process.
struct Exported {
    fs::path dir = fs::temp_directory_path() / "retroprism_test_openmaterial";
    BrdfTable written, back;
    Exported() {
        fs::create_directories(dir);
        OpenMaterialExport e;
        e.name = "plate";
        written = write_openmaterial(plate(), e, dir.string());
        back = read_brdf_table((dir / "plate_brdf.xompt").string());
    }
};
const Exported& exported() {
    static const Exported e;
    return e;
}

// The table as an isotropic BRDF in the node's local frame (phi_o relative to wi's azimuth).
LidarBrdf table_brdf(const BrdfTable& t, double wavelengthM) {
    return [&t, wavelengthM](const glm::dvec3& wi, const glm::dvec3& wo) {
        if (wi.z <= 0 || wo.z <= 0) return 0.0;
        const double phi = std::atan2(wo.y, wo.x) - std::atan2(wi.y, wi.x);
        return brdf_table_value(t, wavelengthM, std::acos(std::min(1.0, wi.z)),
                                std::acos(std::min(1.0, wo.z)), phi)
            .value_or(0.0);
    };
}

} // namespace

TEST_CASE("OpenMATERIAL: the exported table reads back as the node", "[lidar]") {
    const Exported& x = exported();
    REQUIRE(x.back.rows.size() == x.written.rows.size());
    CHECK(x.back.wavelengths.size() == 2);
    CHECK(std::regex_match(
        x.back.metadata.uuid,
        std::regex("[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}")));
    const TableCheck c = check_brdf_table(x.back, plate(), 0);
    std::printf("[lidar] OpenMATERIAL table: %zu rows, largest difference from the node %.2e; "
                "interpolation at %zu centres near the retro direction: median %.2e, 90th "
                "percentile %.2e, largest %.2e\n",
                c.rows, c.max_row_error, c.centres, c.median_centre_error, c.p90_centre_error,
                c.max_centre_error);
    // Rows are printed to 9 significant digits, angles too: on the lobe's flanks an angle's
    // rounding moves f by up to ~3e-5 relative.
    CHECK(c.max_row_error < 1e-4);
    // At its rows the interpolation returns the rows.
    for (std::size_t i = 0; i < x.back.rows.size(); i += 97) {
        const auto& r = x.back.rows[i];
        const std::optional<double> v = brdf_table_value(x.back, r[0], r[1], r[2], r[3]);
        REQUIRE(v);
        CHECK(*v == r[4]);
    }
    CHECK_FALSE(brdf_table_value(x.back, 1e-6, 0.1, 0.1, 0.0));
}

TEST_CASE("OpenMATERIAL: the material file's R_A, and the LiDAR return through the table",
          "[lidar]") {
    const Exported& x = exported();
    const nlohmann::json m = read_json((x.dir / "plate.xomp").string());
    const double ra =
        m["materialProperties"]["retroreflectivityData"]["coefficientOfRetroreflection"];
    CHECK(std::abs(ra / openmaterial_ra(plate()) - 1.0) < 1e-8);
    CHECK(m["materialProperties"]["brdfUris"][0] == "plate_brdf.xompt");
    // The return of the table (linear interpolation) against the node's at the example's
    // geometries: the table's interpolation error as a LiDAR sees it. Both by the same coarse
    // quadrature (the table's lookups are slow; the comparison needs the same rule, not the
    // converged one).
    LidarQuadrature q;
    q.footprint = 4;
    q.aperture_radial = 4;
    q.aperture_angular = 16;
    double worst = 0;
    for (double nm : {905.0, 1550.0})
        for (double range : {5.0, 50.0})
            for (double entrance : {0.0, 20.0}) {
                LidarTarget t;
                t.range_m = range;
                t.entrance_deg = entrance;
                const double node = lidar_return(lidar_node_brdf(plate(), nm), {}, t, q).fraction;
                const double table = lidar_return(table_brdf(x.back, nm * 1e-9), {}, t, q).fraction;
                std::printf("[lidar] OpenMATERIAL table: %g nm, %g m, entrance %g: return %.4e, "
                            "node %.4e (%+.2f%%)\n",
                            nm, range, entrance, table, node, 100.0 * (table / node - 1.0));
                worst = std::max(worst, std::abs(table / node - 1.0));
            }
    // The table's linear interpolation across the lobe's grid (offsets 0.02-4 deg) against the
    // node's smooth lobe: the 90th percentile of its interpolation error near the retro
    // direction is 2.8% (printed above), the bound.
    CHECK(worst < 0.03);
}

TEST_CASE("OpenMATERIAL: the reader names the field of every error", "[lidar]") {
    const std::string good =
        R"({"metadata": {"name": "m", "uuid": "0b5e8a3c-1d2e-8f40-9a1b-2c3d4e5f6a7b", "materialVersion": "1.0.0",
        "openMaterial3dVersion": "1.1.0", "copyrights": ["c"], "license": "l", "authors": ["a"],
        "sources": "s"}, "brdf": {"wavelengths": [9.05e-07], "lookupTable": [
        [9.05e-07, 0.1, 0.1, 0.0, 2.0], [9.05e-07, 0.1, 0.1, 3.0, 1.0]]}})";
    const BrdfTable t = parse_brdf_table(nlohmann::json::parse(good), "t.xompt");
    CHECK(t.rows.size() == 2);
    CHECK(*brdf_table_value(t, 9.05e-7, 0.1, 0.1, 1.5) == Approx(1.5));
    struct Bad {
        const char* from;
        const char* to;
        const char* message;
    };
    for (const Bad& b :
         {Bad{"\"sources\": \"s\"", "\"x\": \"s\"", "t.xompt: metadata.sources: required"},
          Bad{"[9.05e-07, 0.1, 0.1, 3.0, 1.0]", "[9.05e-07, 0.1, 0.1, 0.0, 1.0]",
              "t.xompt: brdf.lookupTable[1]: rows must be sorted"},
          Bad{"[9.05e-07, 0.1, 0.1, 3.0, 1.0]", "[9.06e-07, 0.1, 0.1, 3.0, 1.0]",
              "t.xompt: brdf.lookupTable[1][0] (wavelength) 9.06e-07: not among brdf.wavelengths"},
          Bad{"[9.05e-07, 0.1, 0.1, 3.0, 1.0]", "[9.05e-07, 0.1, 1.6, 3.0, 1.0]",
              "t.xompt: brdf.lookupTable[1][2] (theta_o) 1.6: must be in [0, 1.570796]"},
          Bad{"[9.05e-07, 0.1, 0.1, 3.0, 1.0]", "[9.05e-07, 0.1, 0.1, 3.0, -1.0]",
              "t.xompt: brdf.lookupTable[1][4] (f) -1: must be in [0, inf]"},
          Bad{"[9.05e-07, 0.1, 0.1, 3.0, 1.0]", "[9.05e-07, 0.1, 0.1, 3.0, null]",
              "t.xompt: brdf.lookupTable[1][4] (f): null"},
          Bad{"[9.05e-07, 0.1, 0.1, 3.0, 1.0]", "[9.05e-07, 0.1, 0.1, 3.0]",
              "t.xompt: brdf.lookupTable[1]: expected [wavelength, theta_i, theta_o, phi_o, f]"},
          Bad{"[9.05e-07]", "[0]", "t.xompt: brdf.wavelengths[0] 0: must be in [1e-09, 0.01716]"},
          Bad{"\"1.0.0\"", "\"1.0\"",
              "t.xompt: metadata.materialVersion 1.0: expected a semantic version N.N.N"},
          Bad{"0b5e8a3c-", "0b5e8a3-",
              "t.xompt: metadata.uuid 0b5e8a3-1d2e-8f40-9a1b-2c3d4e5f6a7b: expected 8-4-4-4-12 "
              "hexadecimal digits"},
          Bad{"\"authors\": [\"a\"]", "\"authors\": []",
              "t.xompt: metadata.authors: expected an array of at least one string"}}) {
        std::string text = good;
        text.replace(text.find(b.from), std::string(b.from).size(), b.to);
        try {
            parse_brdf_table(nlohmann::json::parse(text), "t.xompt");
            FAIL("no error for " << b.to);
        } catch (const InputError& e) {
            INFO(e.what());
            CHECK(rptest::contains(e.what(), b.message));
        }
    }
    const fs::path missing = fs::temp_directory_path() / "retroprism_no_such_brdf.xompt";
    CHECK_THROWS_WITH(read_brdf_table(missing.string()), Catch::Contains(missing.string()));
}

TEST_CASE("OpenMATERIAL: the fuzz corpus replays cleanly", "[lidar]") {
    int files = 0;
    for (const rptest::CorpusFile& f : rptest::fuzz_corpus("openmaterial")) {
        INFO(f.path);
        CHECK_NOTHROW(rpfuzz::check_openmaterial(f.bytes.data(), f.bytes.size()));
        ++files;
    }
    CHECK(files >= 5);
}
