// site.h: what `retroprism view` serves: the look-dev page (web/), the MaterialX library and
// its WebAssembly build (materialx/), the example documents, the GLSL of the MaterialX-style GGX
// baseline and a site.json the page reads (the parameter table, the R_A table's angles, the
// luminance weights, the document to open, the baseline's GLSL), gathered in a fresh folder;
// and the server run over it: web/serve.py, Python's http.server (an existing server, not a
// hand-written one) with one request more, POST /fit-baseline, which fits the baseline to the
// page's R_A table by running `retroprism fit --ra TABLE --baseline-only --json`.
#pragma once

#include <functional>
#include <string>

namespace retroprism {

struct Site {
    std::string root;   // the folder served
    std::string page;   // the page's path and query, e.g. "/web/index.html"
    std::string server; // the server's script, the data folder's web/serve.py
};

// The URL path of the baseline's GLSL in the site.
inline const char* const kBaselineGlslUrl = "/mrm_ggx.glsl";

// The site.json the page reads: {"params": params_table_json(), "ra": {"observation": [...],
// "entrance": [...]}, "luminance": [wR, wG, wB], "document": URL path of the document,
// "baseline": kBaselineGlslUrl}.
std::string site_json(const std::string& documentUrl);

// Gathers the site in `root` (created; it must not exist) from the run-time data folder
// `dataDir` (util/paths.h): links web, materialx and examples, writes site.json and
// `baselineGlsl` (the generated library glsl/mrm_ggx.glsl) at kBaselineGlslUrl, and copies
// `document` (a MaterialX document, when not empty) as document.mtlx, the page's document.
// InputError naming what is missing (the data folder's page or server, MaterialX's WebAssembly
// build with the hint to run scripts/setup-debian.sh, the document).
Site make_site(const std::string& dataDir, const std::string& root, const std::string& document,
               const std::string& baselineGlsl);

// The Python interpreter that serves: /usr/bin/python3 (Debian's) when present, else
// python3 on PATH.
std::string server_python();

// Serves the site on 127.0.0.1:port with `python3 SERVER --directory ROOT --port N
// --retroprism EXE` (web/serve.py; EXE the retroprism command that fits the baseline) in a child
// process until it exits or this process gets SIGINT or SIGTERM (passed on to it); `onStarted`
// runs once the child is started. Returns the server's exit status (0 after a passed-on signal).
int serve_site(const Site& site, int port, const std::string& retroprism,
               const std::function<void()>& onStarted);

// Opens `url` with xdg-open in the background when a desktop session is there ($DISPLAY or
// $WAYLAND_DISPLAY set, xdg-open found); false otherwise.
bool open_in_browser(const std::string& url);

} // namespace retroprism
