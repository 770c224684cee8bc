// cmd_view.cpp: `retroprism view [DOC.mtlx]`: serves the look-dev page (web/site.h) on
// localhost with web/serve.py, which runs this executable to fit the page's GGX baseline, and
// opens it in the browser when there is a desktop.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <OpenImageIO/argparse.h>

#include "color.h"
#include "commands.h"
#include "embedded_files.h"
#include "error.h"
#include "parse.h"
#include "paths.h"
#include "site.h"

namespace fs = std::filesystem;

namespace retroprism {

int cmd_view(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism view: the look-dev page in the browser: the node's MaterialX shader "
             "(ESSL, generated in the page by MaterialX's WebAssembly build) in WebGL2, the night "
             "scene of `retroprism render`, controls for every input, the R_A table computed by "
             "the shader, export as .mtlx, a switch to the MaterialX-style GGX baseline fitted "
             "to the node's R_A table. Serves it on 127.0.0.1 with web/serve.py (Python's "
             "http.server, and POST /fit-baseline, which runs `retroprism fit --ra TABLE "
             "--baseline-only --json`) until interrupted")
        .usage("retroprism view [DOC.mtlx] [--port N] [--no-open]");
    std::string doc;
    ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) { doc = a[0]; });
    ap.arg("--port N").help("the port on 127.0.0.1 (default 8620)").defaultval("8620");
    ap.arg("--no-open").help("only print the address; do not start a browser").store_true();
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const int port = int(parse_number_in(ap["port"].get<std::string>(), "--port", 1, 65535));
    std::string material;
    // The document is read as `retroprism render` reads it, so that a bad one is named here.
    if (!doc.empty()) document_params(doc, "", &material);

    std::string tmpl = (fs::temp_directory_path() / "retroprism-view-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a folder in " + tmpl);
    const Site site = make_site(data_dir(), tmpl + "/site", doc, embedded_variant("mrm_ggx"));
    const std::string url = "http://127.0.0.1:" + std::to_string(port) + site.page;
    const bool noOpen = ap["no-open"].get<int>() != 0;
    const int rc = serve_site(site, port, executable_dir() + "/retroprism", [&] {
        std::printf("retroprism view: %s%s\n", url.c_str(),
                    doc.empty() ? " (the bundled white_sign.mtlx)"
                                : (" (" + doc + ", material \"" + material + "\")").c_str());
        if (!noOpen && !open_in_browser(url))
            std::printf("open it in a browser with WebGL2 (no desktop session here)\n");
        std::printf("serving %s; Ctrl-C stops\n", site.root.c_str());
        std::fflush(stdout);
    });
    std::error_code ec;
    fs::remove_all(tmpl, ec);
    return rc;
}

} // namespace retroprism
