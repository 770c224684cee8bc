// [util]: the shared pieces every library stands on: the number parser's accepted forms and
// error texts, the RNG's determinism and uniformity, parallel_for and parallel_ranges visiting
// every item once whatever the thread count, median, the small linear solver, the fitters' bounded
// search (search_box), and where the run-time data is found.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "error.h"
#include "linalg.h"
#include "minimize.h"
#include "parallel.h"
#include "parse.h"
#include "paths.h"
#include "rng.h"
#include "stats.h"

using namespace retroprism;
namespace fs = std::filesystem;

namespace {

// The message of the InputError that f throws ("" when it throws none).
template <class F>
std::string error_of(F f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("the number parser accepts whole finite numbers and names what it rejects", "[util]") {
    CHECK(try_parse_number("1.5") == 1.5);
    CHECK(try_parse_number("-2e-3") == -2e-3);
    CHECK(try_parse_number("4e6") == 4e6);
    for (const char* bad : {"", " ", "1x", "x1", "1.5 ", "nan", "inf", "-inf", "1e400"})
        CHECK_FALSE(try_parse_number(bad).has_value());
    CHECK(std::isnan(*try_parse_number("nan", false)));
    CHECK(*try_parse_number("-inf", false) == -INFINITY);
    CHECK_FALSE(try_parse_number("abc", false).has_value());

    CHECK(error_of([] { parse_number("ten", "--rays"); }) ==
          "--rays ten: expected a finite number");
    CHECK(parse_number_in("5", "--width", 0, 10) == 5);
}

TEST_CASE("range and count errors say the allowed range", "[util]") {
    CHECK(error_of([] { parse_number_in("9000", "--width", 8, 8192); }) ==
          "--width 9000: expected a number in [8, 8192]");
    CHECK(error_of([] { parse_number_in("x", "--width", 8, 8192); }) ==
          "--width x: expected a number in [8, 8192]");
    CHECK(parse_count("4e6", "--rays", 1, 1e12) == 4000000u);
    CHECK(error_of([] { parse_count("1.5", "--rays", 1, 10); }) ==
          "--rays 1.5: expected a whole number in [1, 10]");
    CHECK(error_of([] { parse_count("0", "--rays", 1, 10); }) ==
          "--rays 0: expected a whole number in [1, 10]");
}

TEST_CASE("a list of numbers: each item through the parser, the bad one named", "[util]") {
    CHECK(parse_number_list("0.1,-2,3e2", "--range") == std::vector<double>{0.1, -2, 300});
    CHECK(parse_number_list("5", "--width", 0, 10) == std::vector<double>{5});
    CHECK(error_of([] { parse_number_list("2,x", "--range"); }) ==
          "--range 2,x: x: expected a finite number");
    CHECK(error_of([] { parse_number_list("1,,3", "--range"); }) ==
          "--range 1,,3: : expected a finite number");
    CHECK(error_of([] { parse_number_list("0.2,30", "--observation", 0, 20); }) ==
          "--observation 0.2,30: 30: expected a number in [0, 20]");
    CHECK(error_of([] { parse_number_list("30", "--observation", 0, 20); }) ==
          "--observation 30: expected a number in [0, 20]");
}

TEST_CASE("Rng: one stream per (seed, stream), uniform in [0, 1)", "[util]") {
    Rng a(7, 3), b(7, 3), c(7, 4), d(8, 3);
    bool differsStream = false, differsSeed = false;
    for (int i = 0; i < 64; ++i) {
        const std::uint64_t x = a.next();
        CHECK(x == b.next());
        differsStream = differsStream || x != c.next();
        differsSeed = differsSeed || x != d.next();
    }
    CHECK(differsStream);
    CHECK(differsSeed);
    // The mean of n uniforms has standard deviation sqrt(1 / (12 n)); with a fixed seed the test
    // is deterministic, and 5 standard deviations (two-sided p = 5.7e-7 for a good generator)
    // would catch a biased conversion (e.g. 32 bits, or (0, 1] with a shifted mean).
    Rng r(2018);
    const int n = 200000;
    double sum = 0, lo = 1, hi = 0;
    for (int i = 0; i < n; ++i) {
        const double u = r.uniform();
        sum += u;
        lo = std::min(lo, u);
        hi = std::max(hi, u);
    }
    CHECK(lo >= 0.0);
    CHECK(hi < 1.0);
    CHECK(std::abs(sum / n - 0.5) < 5.0 * std::sqrt(1.0 / (12.0 * n)));
    Rng open(1);
    for (int i = 0; i < 1000; ++i) {
        const double u = open.uniform_open();
        CHECK((u > 0.0 && u < 1.0));
    }
}

TEST_CASE("parallel_for and parallel_ranges visit every item once, whatever the threads",
          "[util][threads]") {
    for (const int threads : {0, 1, 2, 3, 8})
        for (const std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(1000)}) {
            INFO("threads " << threads << ", n " << n);
            std::vector<std::atomic<int>> seen(n);
            parallel_for(n, threads, [&](std::size_t i) { ++seen[i]; });
            for (const auto& s : seen)
                CHECK(s == 1);
            std::vector<std::atomic<int>> ranged(n);
            // Catch2's assertions are not thread-safe (ThreadSanitizer, scripts/tsan.sh): the
            // workers count what the checks read afterwards.
            std::atomic<int> reversed{0};
            parallel_ranges(n, threads, 16, [&](std::size_t b, std::size_t e) {
                if (b > e) ++reversed;
                for (std::size_t i = b; i < e; ++i)
                    ++ranged[i];
            });
            CHECK(reversed == 0);
            for (const auto& s : ranged)
                CHECK(s == 1);
        }
    CHECK(thread_count(3) == 3);
    CHECK(thread_count(0) >= 1);
}

TEST_CASE("median: the middle value (the upper one of an even count), 0 when empty", "[util]") {
    CHECK(median({}) == 0.0);
    CHECK(median({3.0}) == 3.0);
    CHECK(median({5.0, 1.0, 3.0}) == 3.0);
    CHECK(median({4.0, 1.0, 3.0, 2.0}) == 3.0);
}

TEST_CASE("solve_linear: exact small systems, several right-hand sides, singular ones refused",
          "[util]") {
    // A x = b with x = (1, -2, 3); a zero first pivot forces a row exchange.
    double A[9] = {0, 2, 1, 1, 1, 1, 2, 0, 3}, b[3] = {-1, 2, 11}, x[3];
    REQUIRE(solve_linear(3, 1, A, b, x));
    CHECK(x[0] == Approx(1.0).epsilon(1e-14));
    CHECK(x[1] == Approx(-2.0).epsilon(1e-14));
    CHECK(x[2] == Approx(3.0).epsilon(1e-14));
    // With B = I the solution is the inverse: M inv(M) = I.
    const double M[9] = {4, 1, 0, 1, 3, 1, 0, 1, 2};
    double m[9], I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, inv[9];
    std::copy(M, M + 9, m);
    REQUIRE(solve_linear(3, 3, m, I, inv));
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            double s = 0;
            for (int k = 0; k < 3; ++k)
                s += M[r * 3 + k] * inv[k * 3 + c];
            CHECK(s == Approx(r == c ? 1.0 : 0.0).margin(1e-14));
        }
    double S[4] = {1, 2, 2, 4}, sb[2] = {1, 2}, sx[2];
    CHECK_FALSE(solve_linear(2, 1, S, sb, sx));
}

TEST_CASE("search_box: a known minimum inside the box, one on its border, bounds kept, "
          "deterministic",
          "[util]") {
    // A narrow curved valley with its minimum 0 at (0.3, 2, 25): x linear in [-1, 1], y on a log
    // scale in [0.1, 10], z linear in [0, 60].
    const std::vector<BoxVar> box = {{-1.0, 1.0, false}, {0.1, 10.0, true}, {0.0, 60.0, false}};
    int outside = 0;
    auto valley = [&](const std::vector<double>& v) {
        for (size_t k = 0; k < v.size(); ++k)
            if (!(v[k] >= box[k].lo && v[k] <= box[k].hi)) ++outside;
        const double a = v[0] - 0.3, b = std::log(v[1] / 2.0), c = (v[2] - 25.0) / 60.0;
        return 50.0 * (b - a * a) * (b - a * a) + a * a + c * c;
    };
    const std::vector<double> base = {-0.9, 0.2, 5.0};
    const std::vector<std::vector<double>> starts = box_starts(box, base);
    REQUIRE(starts.size() == 2 + 2 * box.size());
    CHECK(starts[0] == base);
    const NmResult r = search_box(valley, box, starts, 450);
    // Tolerances: the search stops when the simplex is 1e-4 wide in logistic coordinates, about
    // 2.5e-5 of each range near the centre; 1e-3 of each value is well above that.
    CHECK(r.x[0] == Approx(0.3).margin(1e-3));
    CHECK(r.x[1] == Approx(2.0).epsilon(1e-3));
    CHECK(r.x[2] == Approx(25.0).margin(1e-3 * 60.0));
    CHECK(r.f < 1e-8);
    CHECK(outside == 0);
    // The same starts give the same bits.
    const NmResult again = search_box(valley, box, starts, 450);
    CHECK(again.x == r.x);
    CHECK(again.f == r.f);
    CHECK(again.evaluations == r.evaluations);

    // A minimum beyond the box (x = 3 > 1, z = -10 < 0): the search ends at the border, inside.
    auto beyond = [&](const std::vector<double>& v) {
        for (size_t k = 0; k < v.size(); ++k)
            if (!(v[k] >= box[k].lo && v[k] <= box[k].hi)) ++outside;
        return (v[0] - 3.0) * (v[0] - 3.0) + std::log(v[1]) * std::log(v[1]) +
               (v[2] + 10.0) * (v[2] + 10.0);
    };
    const NmResult e = search_box(beyond, box, box_starts(box, base), 450);
    CHECK(outside == 0);
    // Tolerances: the logistic coordinate approaches the border as e^-u; 1e-3 of the range is
    // reached within the evaluations allowed.
    CHECK(e.x[0] == Approx(1.0).margin(2e-3));
    CHECK(e.x[0] <= 1.0);
    CHECK(e.x[1] == Approx(1.0).epsilon(1e-3));
    CHECK(e.x[2] == Approx(0.0).margin(2e-3 * 60.0));
    CHECK(e.x[2] >= 0.0);

    // Coordinates and values: inverse of each other inside, clamped 1e-3 of the range inside.
    CHECK(box_value(box[1], box_coordinate(box[1], 2.0)) == Approx(2.0).epsilon(1e-12));
    CHECK(box_value(box[2], box_coordinate(box[2], -5.0)) == Approx(0.06).epsilon(1e-9));
    // No variables: f once at the empty point.
    const NmResult none = search_box([](const std::vector<double>&) { return 4.0; }, {}, {{}}, 10);
    CHECK(none.f == 4.0);
    CHECK(none.evaluations == 1);
}

TEST_CASE("the run-time data: RETROPRISM_DATA_DIR, else the checkout above the executable",
          "[util]") {
    const fs::path root = fs::canonical(RP_SOURCE_DIR);
    unsetenv("RETROPRISM_DATA_DIR");
    CHECK(fs::canonical(data_dir()) == root);
    CHECK(data_path("materialx/tools/mx.cjs") == data_dir() + "/materialx/tools/mx.cjs");
    setenv("RETROPRISM_DATA_DIR", root.c_str(), 1);
    CHECK(fs::canonical(data_dir()) == root);
    const std::string empty = fs::temp_directory_path().string();
    setenv("RETROPRISM_DATA_DIR", empty.c_str(), 1);
    const std::string err = error_of([] { data_dir(); });
    CHECK(err.find("RETROPRISM_DATA_DIR=" + empty) != std::string::npos);
    CHECK(err.find("materialx/tools/mx.cjs") != std::string::npos);
    unsetenv("RETROPRISM_DATA_DIR");
}
