// fit_json.h: the JSON `retroprism fit` prints (`--json`), its keys in this order: the ALTA
// fit's {"params", "rel_rms", "log_rms", "mrm"}, the R_A fit's {"table", "fitted", "params",
// "log_rms", "max_error", "entries", "mrm"[, "colors"]} and the baseline alone's {"table", "mrm":
// {"params", "log_rms", "max_error", "entries"}}.
#pragma once

#include <nlohmann/json.hpp>

#include "fitting.h"
#include "ra_fit.h"

namespace retroprism {

// The ALTA fit (fitting.h): the node's fitted inputs as a material, the baseline's parameters.
nlohmann::ordered_json fit_json(const NodeFit& nf, const MrmFit& mf);
// The R_A fit (ra_fit.h) of a table, a coloured one's colours included.
nlohmann::ordered_json ra_fit_json(const RaColoredFit& cf, const RaMrmFit& mf);
// The baseline alone fitted to the table t.
nlohmann::ordered_json ra_baseline_json(const RaMeasurements& t, const RaMrmFit& mf);

} // namespace retroprism
