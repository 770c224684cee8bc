// template.h: documents filled in from a template file. Placeholders:
//   {{name}}                   the text value `name`;
//   {{?name}}...{{/name}}      the enclosed text when flag `name` is true;
//   {{^name}}...{{/name}}      the enclosed text when flag `name` is false.
// A section tag alone on its line takes the line's end with it. Sections do not nest with the
// same name; a name without a value or flag is an error, so the
// template and the program that fills it cannot drift apart unnoticed.
#pragma once

#include <map>
#include <string>

namespace retroprism::report {

struct TemplateValues {
    std::map<std::string, std::string> text;
    std::map<std::string, bool> flags;
};

// The template with every placeholder filled in; InputError naming `where` (the template's
// file) and the placeholder for an unknown name or an unclosed section.
std::string fill_template(const std::string& tmpl, const TemplateValues& values,
                          const std::string& where);

} // namespace retroprism::report
