// accuracy_report.h: docs/accuracy.md, the accuracy study's document, from its template
// (docs/accuracy.md.in: the prose, with placeholders for every number, table and data-dependent
// choice of words) and a study's results (sim/study.h).
#pragma once

#include <string>

#include "study.h"

namespace retroprism::report {

// The document of `study`: `tmpl` (the template's text, `where` its file name for errors)
// filled in. docPath: where the document is written (the command line it names includes
// --doc docPath unless it is docs/accuracy.md); plotDir: the folder of its plots and
// results.csv relative to the document.
std::string accuracy_report(const sim::StudyResults& study, const std::string& tmpl,
                            const std::string& where, const std::string& docPath,
                            const std::string& plotDir);

} // namespace retroprism::report
