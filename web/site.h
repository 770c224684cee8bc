// site.h: what `retroprism view` serves: the look-dev page (web/), the MaterialX library and
// its WebAssembly build (materialx/), the example documents and a site.json the page reads
// (the parameter table, the R_A table's angles, the luminance weights, the document to open),
// gathered in a fresh folder of links; and the static server (Python's http.server, an existing
// server, not a hand-written one) run over it.
#pragma once

#include <functional>
#include <string>

namespace retroprism {

struct Site {
    std::string root; // the folder served
    std::string page; // the page's path and query, e.g. "/web/index.html"
};

// The site.json the page reads: {"params": params_table_json(), "ra": {"observation": [...],
// "entrance": [...]}, "luminance": [wR, wG, wB], "document": URL path of the document}.
std::string site_json(const std::string& documentUrl);

// Gathers the site in `root` (created; it must not exist) from the run-time data folder
// `dataDir` (util/paths.h): links web, materialx and examples, writes site.json, and copies
// `document` (a MaterialX document, when not empty) as document.mtlx, the page's document.
// InputError naming what is missing (the data folder's page, MaterialX's WebAssembly build
// with the hint to run scripts/setup-debian.sh, the document).
Site make_site(const std::string& dataDir, const std::string& root, const std::string& document);

// The Python interpreter that serves: /usr/bin/python3 (Debian's) when present, else
// python3 on PATH.
std::string server_python();

// Serves `root` on 127.0.0.1:port with `python3 -m http.server` in a child process until it
// exits or this process gets SIGINT or SIGTERM (passed on to it); `onStarted` runs once the
// child is started. Returns the server's exit status (0 after a passed-on signal).
int serve_site(const std::string& root, int port, const std::function<void()>& onStarted);

// Opens `url` with xdg-open in the background when a desktop session is there ($DISPLAY or
// $WAYLAND_DISPLAY set, xdg-open found); false otherwise.
bool open_in_browser(const std::string& url);

} // namespace retroprism
