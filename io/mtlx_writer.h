// mtlx_writer.h: MaterialX documents of the node's materials, the form io/mtlx_reader.h reads:
// per material the chain `<rp_prismatic_retroreflector_bsdf>` -> `<surface>` ->
// `<surfacematerial>`, every input of the parameter table with a constant value except the
// vectors (normal and tangent keep their geometric defaults), colours in lin_rec709.
#pragma once

#include <string>
#include <vector>

#include "prismatic_retroreflector.h"

namespace retroprism {

struct MtlxMaterialOut {
    std::string name; // the surfacematerial's name; its nodes are NAME_bsdf and NAME_surface
    Params params;
};

// The document's text; `comment` lines go into an XML comment at its top. InputError when a
// name is not a MaterialX name (a letter or '_', then letters, digits or '_').
std::string mtlx_document(const std::vector<MtlxMaterialOut>& materials,
                          const std::vector<std::string>& comment);

// Writes the document to `path` (InputError naming the path when it cannot).
void write_mtlx(const std::string& path, const std::vector<MtlxMaterialOut>& materials,
                const std::vector<std::string>& comment);

} // namespace retroprism
