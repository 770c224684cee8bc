// [luminaire]: the luminous intensity distribution readers (io/luminaire.h) on files written by
// hand to the formats' specifications (tests/data/luminaire/): the values and the interpolating
// lookup in the lamp's frame, symmetry and multipliers; every error naming FILE:LINE, what is
// wrong and the allowed form; the fuzz corpus replayed. Two headlamps on approach
// (analysis/approach.h): the sign's luminance against a hand computation of one geometry, the
// angles' inverse against ra_directions, the demand.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "../../fuzz/fuzz_checks_luminaire.h"
#include "approach.h"
#include "error.h"
#include "luminaire.h"
#include "night_render.h"
#include "photometry.h"
#include "test_support.h"
#include "text_file.h"

using namespace retroprism;
namespace fs = std::filesystem;
using namespace std::placeholders;

namespace {

constexpr double kDeg = M_PI / 180.0;

std::string data(const std::string& file) {
    return std::string(RP_SOURCE_DIR) + "/tests/data/luminaire/" + file;
}

using Parser = std::function<LuminousIntensityDistribution(std::istream&, const std::string&)>;

// `original` with line `line` (1-based) replaced by `text` (a line past the end: appended; an
// empty optional: removed).
std::string edit_text(const std::string& original, int line,
                      const std::optional<std::string>& text) {
    std::istringstream in(original);
    std::vector<std::string> lines;
    std::string l;
    while (std::getline(in, l))
        lines.push_back(l);
    if (line > int(lines.size())) {
        if (text) lines.push_back(*text);
    } else if (text) {
        lines[size_t(line - 1)] = *text;
    } else {
        lines.erase(lines.begin() + (line - 1));
    }
    std::string out;
    for (const std::string& s : lines)
        out += s + "\n";
    return out;
}

std::string edit(const std::string& file, int line, const std::optional<std::string>& text) {
    return edit_text(read_text_file(data(file)), line, text);
}

void expect_error(const Parser& parse, const std::string& name, const std::string& text,
                  const std::string& message) {
    std::istringstream in(text);
    INFO("expected: " << message);
    try {
        parse(in, name);
        FAIL("no error");
    } catch (const InputError& e) {
        INFO("got: " << e.what());
        CHECK(std::string(e.what()).rfind(message, 0) == 0);
    }
}

} // namespace

TEST_CASE("IES LM-63: hand-written files of types A, B and C", "[luminaire]") {
    // Type A, 2002: candela multiplier 2; planes H = -10, 0, 10; V = -5, 0, 5.
    const LuminousIntensityDistribution a = read_luminaire(data("type_a_2002.ies"));
    CHECK(a.type == PhotometricType::A);
    CHECK(a.multiplier == 2);
    CHECK(a.intensity_at(-10, -5) == 200);
    CHECK(a.intensity_at(0, 2.5) == Approx(1100)); // (500 + 600) / 2 x 2
    CHECK(a.intensity_at(5, 0) == Approx(1300));   // (500 + 800) / 2 x 2
    CHECK(a.intensity_at(11, 0) == 0);             // outside the listed horizontal angles
    CHECK(a.intensity_at(0, -6) == 0);             // outside the listed vertical angles
    CHECK(a.intensity({0, 0, 1}) == Approx(1000)); // straight ahead: H 0, V 0
    // 10 degrees right, on the horizon: the plane H = 10 (to the right, +x), V 0.
    CHECK(a.intensity({std::sin(10 * kDeg), 0, std::cos(10 * kDeg)}) == Approx(1600));
    CHECK(a.intensity({-std::sin(10 * kDeg), 0, std::cos(10 * kDeg)}) == Approx(400));
    // 5 degrees up straight ahead: V = 5 (+y).
    CHECK(a.intensity({0, std::sin(5 * kDeg), std::cos(5 * kDeg)}) == Approx(1200));

    // Type C, 2019 (CRLF): ballast factor 0.5, quadrant symmetry (last horizontal angle 90).
    const LuminousIntensityDistribution c = read_luminaire(data("type_c_2019.ies"));
    CHECK(c.type == PhotometricType::C);
    CHECK(c.multiplier == 0.5);
    CHECK(c.intensity_at(270, 90) == Approx(20)); // folds onto C 90: 40 x 0.5
    CHECK(c.intensity_at(180, 45) == Approx(45)); // folds onto C 0: (100 + 80) / 2 x 0.5
    CHECK(c.intensity_at(45, 0) == Approx(37.5)); // (100 + 50) / 2 x 0.5
    CHECK(c.intensity({0, -1, 0}) == Approx(50)); // straight down: gamma 0
    CHECK(c.intensity({0, 0, 1}) == Approx(40));  // straight ahead: C 0, gamma 90
    CHECK(c.intensity({-1, 0, 0}) == Approx(20)); // to the left: C 90, gamma 90
    CHECK(c.intensity({0, 1, 0}) == 0);           // straight up: gamma 180, 0 cd

    // Type B, LM-63-1986 (no first line), horizontal angles from 0: symmetric about the
    // vertical plane.
    const LuminousIntensityDistribution b = read_luminaire(data("type_b_1986.ies"));
    CHECK(b.type == PhotometricType::B);
    CHECK(b.intensity_at(-20, 0) == Approx(35)); // |H| = 20: (30 + 40) / 2
    CHECK(b.intensity_at(50, 0) == 0);
    // Type B: V turns about x; a direction in the y-z plane 5 degrees up is H 0, V 5.
    CHECK(b.intensity({0, std::sin(5 * kDeg), std::cos(5 * kDeg)}) ==
          Approx(17.5)); // V 5: 3/4 of the way
}

TEST_CASE("EULUMDAT and CSV: hand-written files", "[luminaire]") {
    // Symmetric about C0-C180, 2000 lm: cd/klm x 2; C 270 is C 90 mirrored.
    const LuminousIntensityDistribution l = read_luminaire(data("small.ldt"));
    CHECK(l.type == PhotometricType::C);
    CHECK(l.multiplier == 2);
    CHECK(l.intensity_at(270, 90) == Approx(100));
    CHECK(l.intensity_at(315, 90) == Approx(70)); // between C 270 (100) and C 360 = C 0 (40)
    CHECK(l.intensity_at(180, 180) == Approx(180));
    CHECK(l.intensity({0, 0, 1}) == Approx(40));  // C 0, gamma 90
    CHECK(l.intensity({1, 0, 0}) == Approx(100)); // to the right: C 270

    const LuminousIntensityDistribution p = read_luminaire(data("plane.csv"));
    CHECK(p.type == PhotometricType::A);
    CHECK(p.multiplier == 1);
    for (double h : {-30.0, -12.5, 0.0, 7.3, 30.0})
        for (double v : {-10.0, -2.2, 0.0, 9.9})
            CHECK(p.intensity_at(h, v) == Approx(3000 + 20 * h + 100 * v).epsilon(1e-12));
}

TEST_CASE("the synthetic low beam: IES type A and EULUMDAT C-gamma agree", "[luminaire]") {
    const std::string dir = std::string(RP_SOURCE_DIR) + "/examples/headlamps/";
    const LuminousIntensityDistribution ies = read_luminaire(dir + "synthetic_low_beam.ies"),
                                        ldt = read_luminaire(dir + "synthetic_low_beam.ldt");
    // Directions by type A angles (H right, V up): the hot spot at 1.5D 2R, a shoulder sign's
    // direction, its mirror on the oncoming side, and above the cut-off. The files sample one
    // model on different grids; 5% is their interpolation error there, a mirrored C axis would
    // differ by 40% at the hot spot.
    for (const auto& hv : std::vector<glm::dvec2>{{2, -1.5}, {5, 1}, {-5, 1}, {-2, -1.5}, {0, 3}}) {
        const double h = hv.x * kDeg, v = hv.y * kDeg;
        const glm::dvec3 d(std::cos(v) * std::sin(h), std::sin(v), std::cos(v) * std::cos(h));
        INFO("H " << hv.x << ", V " << hv.y);
        CHECK(ldt.intensity(d) == Approx(ies.intensity(d)).epsilon(0.05));
    }
    CHECK(ies.intensity_at(2, -1.5) > 10 * ies.intensity_at(-5, 1)); // the cut-off's step
}

TEST_CASE("IES LM-63: every error names FILE:LINE and the allowed form", "[luminaire]") {
    const Parser ies = parse_ies;
    const std::string n = "x.ies", f = "type_a_2002.ies", c = "type_c_2019.ies";
    const auto err = std::bind(expect_error, ies, n, _1, _2);
    err(edit(f, 1, "HELLO"), "x.ies:1: \"HELLO\"; expected a first line IESNA:LM-63-2002");
    err(edit(f, 4, std::nullopt),
        "x.ies:4: \"1 -1 2 3 3 3 2 0 0 0\" before the TILT line; expected a keyword line");
    err(edit(f, 4, "TILT=INCLUDE"), "x.ies:4: TILT=INCLUDE is not read; expected TILT=NONE");
    err("IESNA:LM-63-2002\n[TEST] t\n", "x.ies:2: the file ends before its TILT line");
    err(edit(f, 5, "0 -1 2 3 3 3 2 0 0 0"),
        "x.ies:5: the number of lamps \"0\"; expected a whole number in [1, 1000]");
    err(edit(f, 5, "1 -2 2 3 3 3 2 0 0 0"),
        "x.ies:5: the lumens per lamp (-1: absolute photometry) \"-2\"; expected a finite number "
        "in [-1, 1e+09]");
    err(edit(f, 5, "1 -1 inf 3 3 3 2 0 0 0"),
        "x.ies:5: the candela multiplier \"inf\"; expected a finite number in [0, 1e+09]");
    err(edit(f, 5, "1 -1 2 3.5 3 3 2 0 0 0"),
        "x.ies:5: the number of vertical angles \"3.5\"; expected a whole number in [1, 2000]");
    err(edit(f, 5, "1 -1 2 3 0 3 2 0 0 0"),
        "x.ies:5: the number of horizontal angles \"0\"; expected a whole number in [1, 2000]");
    err(edit(f, 5, "1 -1 2 2000 2000 3 2 0 0 0"),
        "x.ies:5: 2000 x 2000 candela values; expected at most 1e+06");
    err(edit(f, 5, "1 -1 2 3 3 4 2 0 0 0"), "x.ies:5: the photometric type (1: C, 2: B, 3: A) "
                                            "\"4\"; expected a whole number in [1, 3]");
    err(edit(f, 5, "1 -1 2 3 3 3 3 0 0 0"), "x.ies:5: the units type (1: feet, 2: metres) \"3\"");
    err(edit(f, 5, "1 -1 2 3 3 3 2 w 0 0"), "x.ies:5: the luminous opening's width \"w\"");
    err(edit(f, 6, "-1 1 0"), "x.ies:6: the ballast factor \"-1\"; expected a finite number");
    err(edit(f, 6, "1 nan 0"), "x.ies:6: the ballast-lamp factor or file generation type \"nan\"");
    err(edit(f, 6, "1 1 x"), "x.ies:6: the input watts \"x\"");
    err(edit(f, 7, "-5 5 0"),
        "x.ies:7: vertical angle 3 (0) does not exceed the one before it (5); expected strictly "
        "ascending angles");
    err(edit(f, 7, "-95 0 5"),
        "x.ies:7: vertical angle 1 \"-95\"; expected a finite number in [-90, 90]");
    err(edit(f, 10, "400 -500 600"),
        "x.ies:10: value 2 of plane 2 (cd) \"-500\"; expected a finite number in [0, 1e+12]");
    err(edit(f, 10, "400 nan 600"), "x.ies:10: value 2 of plane 2 (cd) \"nan\"");
    err(edit(f, 11, std::nullopt), "x.ies:10: the file ends before value 1 of plane 3 (cd)");
    err(edit(f, 12, "1000"),
        "x.ies:12: \"1000\" after the last candela value; expected the end of the file");
    err(edit(c, 9, "10 90"), "x.ies:9: the first horizontal (C) angle is 10; expected 0");
    err(edit(c, 9, "0 120"),
        "x.ies:9: the last horizontal (C) angle is 120; expected 0, 90, 180 or above 180 up to "
        "360 (LM-63 symmetry)");
}

TEST_CASE("EULUMDAT: every error names FILE:LINE and the allowed form", "[luminaire]") {
    const Parser ldt = parse_eulumdat;
    const std::string f = "small.ldt";
    const auto err = std::bind(expect_error, ldt, "x.ldt", _1, _2);
    err("", "x.ldt:1: an empty file; expected EULUMDAT lines");
    err(edit(f, 2, "5"),
        "x.ldt:2: the type indicator Ityp (line 2) \"5\"; expected a whole number in [0, 3]");
    err(edit(f, 3, "7"), "x.ldt:3: the symmetry indicator Isym (line 3) \"7\"");
    err(edit(f, 4, "0"), "x.ldt:4: the number of C planes Mc (line 4) \"0\"");
    err(edit(f, 4, "3"), "x.ldt:4: Mc 3 is odd; expected an even number of C planes");
    err(edit_text(edit(f, 3, "4"), 4, "6"),
        "x.ldt:4: Mc 6 is not a multiple of 4; expected one for symmetry indicator 4");
    err(edit(f, 5, "-1"), "x.ldt:5: the C plane spacing Dc (line 5) \"-1\"; expected a finite");
    err(edit(f, 6, "1.5"), "x.ldt:6: the number of intensities per C plane Ng (line 6) \"1.5\"");
    err(edit_text(edit(f, 4, "2000"), 6, "2000"),
        "x.ldt:6: 2000 x 2000 intensities; expected at most 1e+06");
    err(edit(f, 7, "200"), "x.ldt:7: the intensity spacing Dg (line 7) \"200\"");
    err(edit(f, 13, "abc"), "x.ldt:13: line 13 (dimensions, ratios, factors) \"abc\"");
    err(edit(f, 26, "0"),
        "x.ldt:26: the number of lamp sets (line 26) \"0\"; expected a whole number in [1, 20]");
    err(edit(f, 29, "0"),
        "x.ldt:29: the luminous flux of lamp set 1 in lm \"0\"; expected a finite number in "
        "[1e-06, 1e+09]");
    err(edit(f, 35, "x"), "x.ldt:35: direct ratio 3 (line 27) \"x\"");
    err(edit(f, 44, "0"), "x.ldt:44: C angle 2 (0) does not exceed the one before it (0)");
    err(edit(f, 43, "10"),
        "x.ldt:43: C angles from 10 to 270; expected them from 0 to below 360 (C 360 is C 0)");
    err(edit(f, 46, "360"), "x.ldt:43: C angles from 0 to 360; expected them from 0 to below 360");
    err(edit(f, 46, "361"), "x.ldt:46: C angle 4 \"361\"; expected a finite number in [0, 360]");
    err(edit(f, 46, "300"),
        "x.ldt:43: the C plane 300 has no mirror plane 60 among the listed C angles; expected C "
        "angles symmetric under the symmetry indicator");
    err(edit(f, 49, "190"),
        "x.ldt:49: gamma angle 3 \"190\"; expected a finite number in [0, 180]");
    err(edit(f, 50, "inf"), "x.ldt:50: value 1 of plane 1 (cd/klm) \"inf\"");
    err(edit(f, 52, "-30"),
        "x.ldt:52: value 3 of plane 1 (cd/klm) \"-30\"; expected a finite number in [0, 1e+12]");
    err(edit(f, 58, std::nullopt), "x.ldt:57: the file ends before value 3 of plane 3 (cd/klm)");
    err(edit(f, 59, "5"), "x.ldt:59: \"5\" after the last intensity; expected the end of the file");
}

TEST_CASE("candela CSV: every error names FILE:LINE and the allowed form", "[luminaire]") {
    const Parser csv = parse_candela_csv;
    const std::string f = "plane.csv";
    const auto err = std::bind(expect_error, csv, "x.csv", _1, _2);
    err("# only a comment\n", "x.csv:1: no header row; expected a row TYPE, H1, H2, ...");
    err(edit(f, 2, "D, 0"),
        "x.csv:2, column 1: \"D\"; expected the photometric type A, B or C, then the horizontal "
        "angles");
    err(edit(f, 2, "A"), "x.csv:2: 0 horizontal angles; expected 1 to 2000");
    std::string wide = "A";
    for (int k = 0; k <= 2000; ++k)
        wide += ", " + std::to_string(k * 0.05);
    err(wide + "\n", "x.csv:1: 2001 horizontal angles; expected 1 to 2000");
    err(edit(f, 2, "A, 0, -10, 5, 6, 7, 8, 9"),
        "x.csv:2: horizontal angle 2 (-10) does not exceed the one before it (0)");
    err(edit(f, 2, "A, x, 0, 5, 6, 7, 8, 9"),
        "x.csv:2: horizontal angle 1 \"x\"; expected a finite number in [-180, 180]");
    err(edit(f, 2, "C, 10, 20, 30, 40, 50, 60, 70"),
        "x.csv:2: the first horizontal (C) angle is 10; expected 0");
    err(edit(f, 5, "0, 1, 2"),
        "x.csv:5: 3 fields; expected 8 (a vertical angle, then one intensity per horizontal "
        "angle)");
    err(edit(f, 4, "-10, 1, 1, 1, 1, 1, 1, 1"),
        "x.csv:4: the vertical angle -10 does not exceed the row before it (-10); expected rows "
        "by ascending vertical angle");
    err(edit(f, 3, "-95, 1, 1, 1, 1, 1, 1, 1"),
        "x.csv:3: the vertical angle \"-95\"; expected a finite number in [-90, 90]");
    err(edit(f, 3, "-10, -1, 1, 1, 1, 1, 1, 1"),
        "x.csv:3: value 1 (cd) \"-1\"; expected a finite number in [0, 1e+12]");
    err(edit(f, 3, "-10, 1, nan, 1, 1, 1, 1, 1"), "x.csv:3: value 2 (cd) \"nan\"");
    err("A, 0\n", "x.csv:1: no rows; expected one row per vertical angle after the header row");
    std::string tall = "A, 0\n";
    for (int k = 0; k <= 2000; ++k)
        tall += std::to_string(-90 + k * 0.05) + ", 1\n";
    err(tall, "x.csv:2002: more than 2000 rows; expected at most 2000 vertical angles and 1e+06 "
              "values");
    std::string big = "A";
    for (int k = 0; k < 1000; ++k)
        big += ", " + std::to_string(k * 0.1);
    std::string bigRow;
    for (int k = 0; k < 1000; ++k)
        bigRow += ", 1";
    for (int k = 0; k <= 1000; ++k)
        big += "\n" + std::to_string(-50 + k * 0.05) + bigRow;
    err(big + "\n", "x.csv:1002: more than 1000 rows; expected at most 2000 vertical angles and "
                    "1e+06 values");
}

TEST_CASE("read_luminaire and read_headlamp_pair: file types and lists", "[luminaire]") {
    CHECK_THROWS_WITH(read_luminaire("lamp.txt"),
                      Catch::StartsWith("lamp.txt: unknown luminaire file type \".txt\"; "
                                        "expected .ies (IES LM-63), .ldt (EULUMDAT) or .csv"));
    const std::string missing = (fs::temp_directory_path() / "retroprism_no_lamp.ies").string();
    CHECK_THROWS_WITH(read_luminaire(missing), missing + ": cannot open file");
    CHECK_THROWS_WITH(read_headlamp_pair("a.ies,b.ies,c.ies"),
                      Catch::StartsWith("--headlamps a.ies,b.ies,c.ies: expected FILE (both "
                                        "lamps) or LEFT,RIGHT"));
    CHECK_THROWS_WITH(read_headlamp_pair(""), Catch::StartsWith("--headlamps : expected FILE"));
    const auto pair = read_headlamp_pair(data("plane.csv") + "," + data("type_a_2002.ies"));
    CHECK(pair.first.intensity_at(0, 0) == 3000);
    CHECK(pair.second.intensity_at(0, 0) == 1000);
}

TEST_CASE("luminaire: the fuzz corpus replays cleanly", "[luminaire]") {
    int files = 0;
    for (const rptest::CorpusFile& f : rptest::fuzz_corpus("luminaire")) {
        INFO(f.path);
        CHECK_NOTHROW(rpfuzz::check_luminaire(f.bytes.data(), f.bytes.size()));
        ++files;
    }
    CHECK(files >= 5);
}

// ---------------------------------------------------------------------------------------------
// Two headlamps on approach (analysis/approach.h)

TEST_CASE("ra_geometry inverts ra_directions", "[luminaire]") {
    for (double beta : {5.0, 30.0, 60.0})
        for (double alpha : {0.2, 1.0, 3.0})
            for (double eps : {-150.0, -20.0, 0.0, 45.0, 170.0})
                for (double gamma : {-120.0, 0.0, 35.0}) {
                    glm::dvec3 wi, wo;
                    ra_directions(beta, alpha, eps, wi, wo, gamma);
                    const RaGeometry g = ra_geometry(wi, wo);
                    INFO(beta << " " << alpha << " " << eps << " " << gamma);
                    // Tolerance: atan2 of rounded vectors, far below the angles' meaning.
                    CHECK(g.entrance == Approx(beta).margin(1e-9));
                    CHECK(g.observation == Approx(alpha).margin(1e-9));
                    CHECK(g.rotation == Approx(eps).margin(1e-9));
                    CHECK(g.presentation == Approx(gamma).margin(1e-7));
                }
}

TEST_CASE("two headlamps: the sign's luminance against a hand computation", "[luminaire]") {
    // One geometry computed here from the scene's description (approach.h), independently of
    // the library's helpers: the car preset's numbers, the shoulder sign, a straight road, 120 m.
    const LuminousIntensityDistribution lid = read_luminaire(data("plane.csv"));
    Params material;
    material.roughness = 0.05;
    const LobeBrdf brdf = node_lobes(material);
    HeadlampSettings s;
    s.vehicle = vehicle_preset("car");
    s.far_m = s.near_m = 120;
    s.steps = 1;
    const std::vector<HeadlampPoint> points = approach_headlamps(brdf, lid, lid, s);
    REQUIRE(points.size() == 1);

    const double d = 120, signX = 5.5, signY = 2.1;
    const glm::dvec3 sign(signX, signY, d), eye(-0.37, 1.08, 0);
    const glm::dvec3 lampPos[2] = {{-0.6, 0.6, 0}, {0.6, 0.6, 0}};
    // The sign faces the driver: normal -z; tangent +x; bitangent n x t = (0, -1, 0).
    const glm::dvec3 n(0, 0, -1), t(1, 0, 0), b(0, -1, 0);
    double luminance = 0, e = 0;
    for (int k = 0; k < 2; ++k) {
        const glm::dvec3 toSign = sign - lampPos[k];
        const double r2 = glm::dot(toSign, toSign);
        // Type A angles of the direction from the lamp to the sign; the file's field is linear.
        const double h = std::atan2(toSign.x, toSign.z) / kDeg;
        const double v = std::atan2(toSign.y, std::hypot(toSign.x, toSign.z)) / kDeg;
        const double intensity = 3000 + 20 * h + 100 * v;
        const glm::dvec3 li = -toSign / std::sqrt(r2), lo = glm::normalize(eye - sign);
        const glm::dvec3 wi(glm::dot(li, t), glm::dot(li, b), glm::dot(li, n));
        const glm::dvec3 wo(glm::dot(lo, t), glm::dot(lo, b), glm::dot(lo, n));
        glm::dvec3 lobes[3];
        brdf(wi, wo, lobes); // the node's BRDF, once per lamp
        const glm::dvec3 f = lobes[0] + lobes[1] + lobes[2];
        const double y = 0.2126 * f.x + 0.7152 * f.y + 0.0722 * f.z; // Rec. 709 luminance
        luminance += y * wi.z * intensity / r2;
        e += intensity / r2;
        const double obs = std::acos(glm::dot(li, lo)) / kDeg;
        INFO("lamp " << k);
        // Tolerance: acos near 1 loses digits; 1e-6 degrees is far below any use of the angle.
        CHECK(points[0].lamps[k].angles.observation == Approx(obs).margin(1e-6));
        CHECK(points[0].lamps[k].intensity == Approx(intensity).epsilon(1e-12));
    }
    // Tolerance: the acceptance bound, 0.1%; both sides evaluate the same BRDF in
    // double precision, so they agree far closer.
    CHECK(points[0].luminance == Approx(luminance).epsilon(1e-3));
    const double cosO = glm::dot(glm::normalize(eye - sign), n);
    CHECK(points[0].ra_needed == Approx(2.4 * cosO / e).epsilon(1e-3));
    CHECK(points[0].ra_supplied == Approx(luminance * cosO / e).epsilon(1e-3));
    std::printf("MEASURED: two headlamps at 120 m: L = %.6g cd m^-2 (hand %.6g), relative "
                "difference %.2e\n",
                points[0].luminance, luminance, points[0].luminance / luminance - 1);
}

TEST_CASE("two headlamps: a curve's sign, presets and bad input", "[luminaire]") {
    const LuminousIntensityDistribution lid = read_luminaire(data("plane.csv"));
    Params material;
    material.roughness = 0.05;
    const LobeBrdf brdf = node_lobes(material);
    HeadlampSettings s;
    s.far_m = 300;
    s.near_m = 30;
    s.steps = 10;
    const std::vector<HeadlampPoint> straight = approach_headlamps(brdf, lid, lid, s);
    // A radius of 100 km is straight to within a millimetre over 300 m (d^2 / 2R = 0.45 m is the
    // sideways shift; the sign turns with the road, so the geometry at the sign moves by
    // less than 0.2 degrees): luminances within 1%.
    s.curve_radius = 1e5;
    const std::vector<HeadlampPoint> gentle = approach_headlamps(brdf, lid, lid, s);
    for (size_t i = 0; i < straight.size(); ++i)
        CHECK(gentle[i].luminance == Approx(straight[i].luminance).epsilon(0.01));
    // On a curve to the right of radius 300 m, at 150 m the road has turned 28.6 degrees: the
    // sign, 5.5 m right of the lane, faces the car from the right at a large entrance angle.
    s.curve_radius = 300;
    s.far_m = s.near_m = 150;
    s.steps = 1;
    const HeadlampPoint c = approach_headlamps(brdf, lid, lid, s).front();
    const double th = 150.0 / 300.0;
    const glm::dvec3 sign(300 - 300 * std::cos(th) + 5.5 * std::cos(th), 2.1,
                          300 * std::sin(th) - 5.5 * std::sin(th));
    const glm::dvec3 n(-std::sin(th), 0, -std::cos(th));
    const glm::dvec3 li = glm::normalize(glm::dvec3(-0.6, 0.6, 0) - sign);
    CHECK(c.lamps[0].angles.entrance == Approx(std::acos(glm::dot(li, n)) / kDeg).margin(1e-6));
    CHECK(c.lamps[0].angles.entrance > 10);

    CHECK(vehicle_presets().size() == 3);
    CHECK(vehicle_preset("truck").eye_height > vehicle_preset("suv").eye_height);
    CHECK_THROWS_WITH(vehicle_preset("bus"), "--vehicle bus: expected car, suv or truck");
    CHECK_THROWS_WITH(sign_position("left"), "--sign left: expected shoulder or overhead");
    s.curve_radius = -90; // 150 m along it the road turns by 95 degrees
    CHECK_THROWS_WITH(approach_headlamps(brdf, lid, lid, s),
                      "--curve-radius -90: expected 0 (straight) or a radius of at least 95.493 m "
                      "(the road turning at most 90 degrees over 150 m)");
}

TEST_CASE("approach --headlamps end to end: the tables, and nothing written on bad input",
          "[luminaire]") {
    const std::string src = std::string(RP_SOURCE_DIR) + "/";
    const fs::path out = fs::temp_directory_path() / "retroprism_luminaire_approach";
    fs::remove_all(out);
    const std::string common = src + "examples/sheeting/dg983_white.mtlx --table " + src +
                               "examples/sheeting/dg983_white.csv --out " + out.string() +
                               " --width 16 --height 9 --samples 1 --headlamps ";
    const rptest::CommandRun bad = rptest::run_cli("approach " + common + data("plane.csv") + "," +
                                                   data("type_c_2019.ies") + " --sign up");
    CHECK(bad.status != 0);
    CHECK(rptest::contains(bad.output, "--sign up: expected shoulder or overhead"));
    const std::string broken = (fs::temp_directory_path() / "retroprism_broken.ies").string();
    std::ofstream(broken) << edit("type_a_2002.ies", 10, "400 -500 600");
    const rptest::CommandRun badFile = rptest::run_cli("approach " + common + broken);
    CHECK(badFile.status != 0);
    CHECK(rptest::contains(badFile.output, broken + ":10: value 2 of plane 2 (cd) \"-500\""));
    CHECK(!fs::exists(out));

    const rptest::CommandRun ok = rptest::run_cli(
        "approach " + common + src + "examples/headlamps/synthetic_low_beam.ldt --vehicle suv");
    INFO(ok.output);
    REQUIRE(ok.status == 0);
    CHECK(rptest::contains(ok.output, "L needed"));
    CHECK(rptest::contains(ok.output, "     120 m right "));
    CHECK(fs::exists(out / "dg983_white_approach.png"));
    fs::remove_all(out);
}
