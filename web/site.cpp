#include "site.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "error.h"
#include "photometry.h"
#include "query.h"

namespace fs = std::filesystem;

namespace retroprism {

namespace {

// The server's process, for the signal handler that passes SIGINT and SIGTERM on to it.
volatile pid_t gServer = 0;
volatile sig_atomic_t gSignalled = 0;

void pass_signal(int sig) {
    gSignalled = 1;
    if (gServer > 0) kill(gServer, sig == SIGINT ? SIGTERM : sig);
}

void require_path(const fs::path& p, const std::string& what, const std::string& hint) {
    std::error_code ec;
    if (!fs::exists(p, ec))
        throw InputError(p.string() + ": " + what + " not found" +
                         (hint.empty() ? "" : "; " + hint));
}

} // namespace

std::string site_json(const std::string& documentUrl) {
    nlohmann::json j;
    j["params"] = params_table_json();
    j["ra"] = {{"observation", ra_observation_angles()}, {"entrance", ra_entrance_angles()}};
    // Y of unit red, green and blue: the weights of luminance_709, the one place they live.
    j["luminance"] = {luminance_709({1, 0, 0}), luminance_709({0, 1, 0}), luminance_709({0, 0, 1})};
    j["document"] = documentUrl;
    j["baseline"] = kBaselineGlslUrl;
    return j.dump(1);
}

Site make_site(const std::string& dataDir, const std::string& root, const std::string& document,
               const std::string& baselineGlsl) {
    const fs::path data(dataDir);
    require_path(data / "web" / "index.html", "the look-dev page", "");
    require_path(data / "web" / "serve.py", "the look-dev page's server", "");
    require_path(data / "materialx" / "tools" / "node_modules" / "@needle-tools" / "materialx" /
                     "bin" / "JsMaterialXGenShader.wasm",
                 "MaterialX's WebAssembly build",
                 "run scripts/setup-debian.sh (npm ci in materialx/tools)");
    if (!document.empty()) require_path(document, "the document", "");
    std::error_code ec;
    if (!fs::create_directory(root, ec))
        throw InputError(root + ": cannot create the site's folder" +
                         (ec ? ": " + ec.message() : " (it exists)"));
    for (const char* link : {"web", "materialx", "examples"}) {
        fs::create_directory_symlink(fs::absolute(data / link), fs::path(root) / link, ec);
        if (ec) throw InputError(root + "/" + link + ": cannot link: " + ec.message());
    }
    std::string documentUrl = "/examples/documents/white_sign.mtlx";
    if (!document.empty()) {
        fs::copy_file(document, fs::path(root) / "document.mtlx", ec);
        if (ec) throw InputError(document + ": cannot copy: " + ec.message());
        documentUrl = "/document.mtlx";
    }
    std::ofstream(fs::path(root) / "site.json") << site_json(documentUrl) << "\n";
    std::ofstream(fs::path(root) / fs::path(kBaselineGlslUrl).filename()) << baselineGlsl;
    return {root, "/web/index.html", (data / "web" / "serve.py").string()};
}

std::string server_python() {
    return access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
}

bool open_in_browser(const std::string& url) {
    if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) return false;
    if (std::system("command -v xdg-open >/dev/null 2>&1") != 0) return false;
    const pid_t pid = fork();
    if (pid == 0) {
        execlp("xdg-open", "xdg-open", url.c_str(), static_cast<char*>(nullptr));
        std::_Exit(127);
    }
    return pid > 0;
}

int serve_site(const Site& site, int port, const std::string& retroprism,
               const std::function<void()>& onStarted) {
    const std::string python = server_python();
    const std::string portText = std::to_string(port);
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("cannot start the server: fork failed");
    if (pid == 0) {
        const char* argv[] = {
            python.c_str(), site.server.c_str(), "--directory",  site.root.c_str(),
            "--port",       portText.c_str(),    "--retroprism", retroprism.c_str(),
            nullptr};
        execvp(argv[0], const_cast<char* const*>(argv));
        std::_Exit(127);
    }
    gServer = pid;
    struct sigaction sa {};
    sa.sa_handler = pass_signal;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    onStarted();
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    gServer = 0;
    if (WIFEXITED(status)) {
        if (WEXITSTATUS(status) == 127)
            throw std::runtime_error(python +
                                     ": cannot run it to serve the page (install python3)");
        return gSignalled ? 0 : WEXITSTATUS(status);
    }
    return gSignalled ? 0 : 1;
}

} // namespace retroprism
