// check.h: cross-checks of every backend against the C++ double reference, over one
// deterministic query set, under one tolerance contract.
#pragma once

#include <string>
#include <vector>

#include "backend.h"

namespace retroprism {

// The tolerance contract, the one place its numbers live. Each compared value x (every lobe's
// RGB and the pdf) of a backend is measured against the cpp-double reference r as
//   err = |x - r| / (max(|r|, floor_fraction * peak) + input_ulps * s / per_sample)
// where peak is the largest reference value of that lobe (or of the pdf) over the material's
// samples, and s is the reference's own sensitivity to its inputs' float rounding: the largest
// change of r when wi or wo is turned by one float ulp (2^-24) about either axis across it.
// A float backend cannot resolve a value finer than that: the lobe of roughness 1e-4 seen at
// grazing angles in a tilted frame changes by 0.4% for such a turn. A sample fails when any of
// its values has err > per_sample. A backend passes when at most allowed_fraction of its
// samples fail and no err exceeds hard_max.
struct ToleranceContract {
    // Float arithmetic on identical float inputs stays within 1e-5 of double ([stability]
    // measures 9.4e-6); GPU transcendentals (llvmpipe's exp, log, pow) and GLSL's erfc fit
    // (1.2e-7) add a little: 1e-4 leaves a margin of ten.
    double per_sample = 1e-4;
    // Values below a millionth of their lobe's peak are compared absolutely at that level:
    // they do not show, and the tails of narrow lobes amplify the rounding of a float angle.
    double floor_fraction = 1e-6;
    // Near a kink (the ERA's polygon changes, the critical angle of a prism face) a float
    // rounding of the refracted direction can cross it; such samples are rare.
    double allowed_fraction = 1e-3;
    // Nothing, anywhere, may differ by more than 1%.
    double hard_max = 1e-2;
    // Float arithmetic turns a direction by a few ulps on its way into the local frame (the
    // frame's dot products, the half vector): four ulps of input sensitivity are allowed.
    double input_ulps = 4.0;
};

// The deterministic query set: materials spanning the parameter ranges (every enum value,
// roughness 1e-4 to 1, ior 1 + 2^-13 to 3, tilted frames) and, for each, incident directions
// from normal to grazing with outgoing ones at the retro and mirror peaks, on the lobes' own
// scale around them, over the hemisphere, at grazing and below the horizon. Every direction and
// parameter is float-representable (directions unit within 1e-6), so all backends see the same
// inputs.
// The standard direction pairs for material p (360: nine incident directions, each with the
// retro and mirror peaks, their neighbours at 0.5 to 3 roughness widths, the normal, 20
// directions over the hemisphere and one below it), in the frame of p's normal and tangent,
// rounded to float.
std::vector<DirectionPair> standard_pairs(const Params& p);

std::vector<Query> check_query_set();

struct CheckReport {
    std::string backend;
    long samples = 0;
    long values = 0;
    long failures = 0;     // samples with some err > per_sample
    double max_err = 0;    // largest err as defined by the contract
    double max_rel = 0;    // largest |x - r| / max(|r|, floor), without the sensitivity term
    double median_err = 0; // median over samples of their largest err
    std::string worst;     // where max_err occurred
    bool passed = false;
};

// Runs the query set through `backend` and measures it against cpp-double.
CheckReport check_backend(const std::string& backend, const ToleranceContract& contract = {});

} // namespace retroprism
