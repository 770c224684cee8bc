// fuzz_checks_openmaterial.h: the property fuzz_openmaterial checks, in the form of
// fuzz_checks.h (shared by the target and by the [lidar] test that replays
// fuzz/corpus/openmaterial): the bytes are a JSON document; parsing it either succeeds or throws
// one of nlohmann's exceptions; parse_brdf_table (io/openmaterial.h) then either returns a table or
// throws an InputError naming the source. A table it returns has at least one row, every value
// within the schema's ranges, rows sorted without repeats, each row's wavelength listed;
// brdf_table_value gives each row's f at the row's coordinates and finite non-negative values
// elsewhere; written by brdf_table_json and read again it has the same rows to 9 digits (or, where
// the 9 digits merge two rows, the reader says the rows are out of order).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_checks.h"
#include "openmaterial.h"

namespace rpfuzz {

inline void check_openmaterial(const std::uint8_t* data, size_t size) {
    const std::string source = "fuzz_brdf.xompt";
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(data, data + size);
    } catch (const nlohmann::json::exception&) {
        return;
    }
    retroprism::BrdfTable t;
    try {
        t = retroprism::parse_brdf_table(j, source);
    } catch (const retroprism::InputError& e) {
        if (!names(e.what(), source))
            throw Violation(std::string("parse_brdf_table's error does not name the source: ") +
                            e.what());
        return;
    } catch (const std::exception& e) {
        throw Violation(std::string("parse_brdf_table threw ") + typeid(e).name() + ": " +
                        e.what());
    }
    if (t.rows.empty()) throw Violation("parse_brdf_table returned no rows");
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
        const auto& r = t.rows[i];
        if (!(r[0] >= 1e-9 && r[0] <= 17.16e-3 && r[1] >= 0 && r[1] <= 1.570796 && r[2] >= 0 &&
              r[2] <= 1.570796 && r[3] >= 0 && r[3] <= 6.283185 && r[4] >= 0 &&
              std::isfinite(r[4])))
            throw Violation("row " + std::to_string(i) + " outside the schema's ranges");
        if (i > 0 && !std::lexicographical_compare(t.rows[i - 1].begin(), t.rows[i - 1].begin() + 4,
                                                   r.begin(), r.begin() + 4))
            throw Violation("row " + std::to_string(i) + " out of order passed the reader");
        if (i < 64) {
            const std::optional<double> v = retroprism::brdf_table_value(t, r[0], r[1], r[2], r[3]);
            if (!v || *v != r[4])
                throw Violation("the table's value at row " + std::to_string(i) +
                                " is not the row's");
            const std::optional<double> m =
                retroprism::brdf_table_value(t, r[0], 0.5 * r[1] + 0.3, r[2] * 0.7, r[3] + 1.0);
            if (!m || !(*m >= 0) || !std::isfinite(*m))
                throw Violation("an interpolated value is negative or not finite");
        }
    }
    retroprism::BrdfTable back;
    try {
        back = retroprism::parse_brdf_table(nlohmann::json::parse(retroprism::brdf_table_json(t)),
                                            source);
    } catch (const retroprism::InputError& e) {
        if (std::string(e.what()).find("rows must be sorted") == std::string::npos)
            throw Violation(std::string("the written table does not read back: ") + e.what());
        return;
    }
    if (back.rows.size() != t.rows.size()) throw Violation("the written table lost rows");
    for (std::size_t i = 0; i < t.rows.size(); ++i)
        for (int c = 0; c < 5; ++c)
            if (!(std::abs(back.rows[i][c] - t.rows[i][c]) <= 5e-9 * std::abs(t.rows[i][c])))
                throw Violation("the written table's row " + std::to_string(i) +
                                " differs beyond 9 digits");
}

} // namespace rpfuzz
