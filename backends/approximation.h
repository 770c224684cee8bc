// approximation.h: the accuracy of an approximation of the node (backend.h's
// approximation_names(), e.g. materialx-portable) against the cpp-double reference: the relative
// L1 error of each lobe over the standard direction pairs (check.h), and the bundled sheetings
// it is measured on (their R_A tables are compared by analysis/photometry.h).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "backend.h"

namespace retroprism {

// Relative L1 errors: sum over the direction pairs and RGB of |x - r| / sum of |r|, per lobe
// and for their sum f (r the reference's value; a lobe the reference has nowhere is 0).
struct LobeErrors {
    double surface = 0;
    double retro = 0;
    double diffuse = 0;
    double total = 0;
    long pairs = 0;
};

// `backend` against cpp-double at the standard direction pairs of p (check.h standard_pairs).
LobeErrors lobe_l1_errors(const std::string& backend, const Params& p);

// f (RGB, 1/sr, the lobes' sum) of `backend` for material p at (wi, wo) pairs: the batch form
// analysis/photometry.h's ra_table takes.
std::vector<glm::dvec3> backend_f(const std::string& backend, const Params& p,
                                  const std::vector<std::array<glm::dvec3, 2>>& dirs);

struct NamedMaterial {
    std::string name;
    Params params;
};

// The bundled sheetings: the materials of examples/materials/*.json and the documents of
// examples/sheeting/*.mtlx under data_dir() (util/paths.h), in name order, each twice: with
// prism_reflection ideal ("NAME ideal") and tir ("NAME tir", uncoated prisms); and a third time
// when its era_mode is not averaged, with uncoated prisms and era_mode averaged ("NAME tir
// averaged").
std::vector<NamedMaterial> bundled_sheetings();

} // namespace retroprism
