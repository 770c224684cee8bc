// [backend]: every backend against the C++ double reference, through one fixture over the
// deterministic query set and the tolerance contract of cli/check.h.
#include <catch2/catch.hpp>

#include <cstdio>

#include "check.h"

using namespace retroprism;

TEST_CASE("Every backend meets the tolerance contract against cpp-double", "[backend]") {
    const std::string backend = GENERATE(from_range(backend_names()));
    INFO("backend " << backend);
    const ToleranceContract contract;
    const CheckReport r = check_backend(backend, contract);
    std::printf("MEASURED: backend %s: %ld samples (%ld values), max err %.3g (contract), max "
                "relative %.3g, median %.3g, %ld samples above %.0e\n",
                backend.c_str(), r.samples, r.values, r.max_err, r.max_rel, r.median_err,
                r.failures, contract.per_sample);
    INFO("worst: " << r.worst);
    CHECK(r.samples > 10000);
    CHECK(double(r.failures) <= contract.allowed_fraction * double(r.samples));
    CHECK(r.max_err <= contract.hard_max);
    CHECK(r.passed);
    if (backend == "cpp-double") CHECK(r.max_err == 0.0); // the reference against itself
}

TEST_CASE("The contract catches a wrong backend", "[backend]") {
    // A backend that is off by 1e-3 in one lobe must fail: evaluate the query set with a
    // retro_color scaled by 0.999 (1.001 would be clamped back to 1) and measure it with the
    // same comparison.
    std::vector<Query> queries = check_query_set();
    long compared = 0, over = 0;
    for (Query q : queries) {
        const nlohmann::json ref = answer_query(q, "cpp-double")["results"];
        for (double& c : q.material.retro_color)
            c *= 0.999;
        const nlohmann::json bad = answer_query(q, "cpp-double")["results"];
        for (size_t i = 0; i < ref.size(); ++i) {
            double r = ref[i]["retro"][0].get<double>(), b = bad[i]["retro"][0].get<double>();
            if (r > 0) {
                ++compared;
                over += std::abs(b - r) / r > ToleranceContract().per_sample;
            }
        }
    }
    CHECK(compared > 1000);
    CHECK(over == compared);
}
