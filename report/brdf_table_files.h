// brdf_table_files.h: the files of `retroprism simulate`: a tabulated BRDF (sim/brdf_table.h) as
// a multi-part EXR (one part per grid: f and standard error per lobe and channel, and the cells'
// projected solid angle) and as the JSON entry of its incidence.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "brdf_table.h"

namespace retroprism::report {

// The JSON document's header: the material and how it was simulated ("incidences" empty).
nlohmann::json simulation_json(const Params& material, const sim::TableOptions& options);

// The JSON entry of one incidence: direction, run statistics, fates, and per grid its geometry,
// cell centres, projected solid angles and f and se per lobe (RGB), numbers to 7 digits.
nlohmann::json incidence_json(const sim::BrdfTable& table, std::uint64_t rays,
                              const std::string& exrPath);

// Writes the table as a multi-part EXR (written under a temporary name, then renamed);
// `meta` is stored in every part's retroprism:run attribute. InputError when it cannot.
void write_table_exr(const std::string& path, const sim::BrdfTable& table,
                     const nlohmann::json& meta);

// Writes doc (one line) to path under a temporary name, then renames it.
void write_json_file(const std::string& path, const nlohmann::json& doc);

} // namespace retroprism::report
