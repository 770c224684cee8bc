// backend.h: the backends that evaluate the node, behind one interface and found by name in
// one registry: cpp-double (the reference), cpp-float, cpp-batch (the float node over one batch,
// nodes/batch.h), glsl (the generated library on OpenGL)
// and materialx (the shader real MaterialX generates, on OpenGL), which implement the node
// exactly; and the approximation materialx-portable (the portable nodegraph, the node's
// implementation for OSL and MDL, through the GLSL real MaterialX generates of it, on OpenGL).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "answer.h"
#include "query.h"

namespace retroprism {

class Backend {
  public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;
    // The node with material p at each direction pair.
    virtual std::vector<BackendResult> evaluate(const Params& p,
                                                const std::vector<DirectionPair>& pairs) = 0;
};

// The exact backends' names, the reference first: what the tolerance contract checks.
const std::vector<std::string>& backend_names();

// The approximations' names: backends measured by their accuracy (approximation.h), not under
// the tolerance contract.
const std::vector<std::string>& approximation_names();

// The backend of that name, made on first use and kept for the process (a GL backend compiles
// its program once); InputError naming the known backends for any other name.
Backend& backend(const std::string& name);

// The JSON answer of a query: {"backend": name, "results": [{"f", "surface", "retro",
// "diffuse", "pdf"}, ...]}, pdf null where the backend has none.
nlohmann::json answer_query(const Query& q, const std::string& backend);

} // namespace retroprism
