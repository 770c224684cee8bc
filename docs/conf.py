# Sphinx configuration of the documentation site: the pages are Markdown (MyST), the API
# reference is Breathe over Doxygen's XML of the public headers (docs/Doxyfile). Built by
# scripts/check-docs.py (the CMake target `docs`, the ctest entry `docs`), which runs Doxygen
# first and passes its XML folder in RETROPRISM_DOXYGEN_XML.
import os

project = "retroprism"
author = "retroprism"
copyright = "retroprism"
version = release = "0.1.0"

extensions = ["myst_parser", "breathe"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["Doxyfile", "accuracy.md.in"]

# Headings get GitHub's anchors, so that page.md#heading links work on GitHub and here alike.
myst_heading_anchors = 4

_here = os.path.dirname(os.path.abspath(__file__))
_xml = os.path.join(_here, "..", "build", "docs", "doxygen", "xml")
breathe_projects = {"retroprism": os.environ.get("RETROPRISM_DOXYGEN_XML", _xml)}
breathe_default_project = "retroprism"
breathe_domain_by_extension = {"h": "cpp"}
breathe_show_include = False
breathe_default_members = ("members",)

# Names from other libraries that the signatures use; Sphinx cannot link them.
nitpick_ignore_regex = [
    ("cpp:identifier", r"(std|glm|nlohmann|pugi|OIIO|OCIO|fs)(::.*)?"),
    ("cpp:identifier", r"(size_t|uint\d+_t|int\d+_t|ptrdiff_t)"),
    # The math core's types (nodes/prism_core.inc, instantiated per precision by
    # nodes/prism_core.h), which Doxygen does not parse: the model's page describes them.
    ("cpp:identifier", r"(f32|f64|core<\w+>)(::\w+)?"),
    # Members of a class template's instantiation, which Sphinx's C++ domain does not look up.
    ("cpp:identifier", r"\w+<\w+>::\w+"),
]


# Each header is a Doxygen group (scripts/doxygen-filter.py), and each API page shows its headers'
# groups: a header per group, where `doxygenfile` would render the shared namespace once per
# header (Sphinx's duplicate declarations). Breathe 4.34 renders a group's functions, variables,
# enums and aliases without their namespace, so that `retroprism::Params` in one signature would
# not find `Params` declared at the top level: the namespace of each member is read from
# Doxygen's index and given back to it.
def _group_member_namespaces(xmlDir):
    import xml.etree.ElementTree as ET

    namespaces = {}
    index = os.path.join(xmlDir, "index.xml")
    if not os.path.exists(index):
        return namespaces
    for compound in ET.parse(index).getroot().iter("compound"):
        if compound.get("kind") != "namespace":
            continue
        name = compound.findtext("name")
        for member in compound.iter("member"):
            namespaces[member.get("refid")] = name.split("::")
    return namespaces


def _qualify_group_members(xmlDir):
    from breathe.renderer.sphinxrenderer import SphinxRenderer

    namespaces = _group_member_namespaces(xmlDir)
    unqualified = SphinxRenderer.get_qualification

    def get_qualification(self):
        names = unqualified(self)
        if names or self.nesting_level > 0 or not self.qualification_stack:
            return names
        inGroup = any(
            getattr(n, "node_type", None) in ("compound", "compounddef")
            and getattr(n, "kind", None) == "group"
            for n in self.qualification_stack
        )
        member = self.qualification_stack[0]
        if getattr(member, "node_type", None) != "memberdef" and self.context:
            member = self.context.node_stack[0] if self.context.node_stack else None
        if inGroup and getattr(member, "node_type", None) == "memberdef":
            return list(namespaces.get(member.id, []))
        return names

    SphinxRenderer.get_qualification = get_qualification


_qualify_group_members(breathe_projects["retroprism"])

html_theme = "furo"
html_title = "retroprism"
# Blocks without a language (command output, tables) are shown as written.
highlight_language = "none"
