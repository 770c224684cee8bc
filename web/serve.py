"""serve.py: the server of `retroprism view` (web/site.h): Python's http.server over the site's
folder on 127.0.0.1, plus one request the look-dev page makes of the C++ library:

  POST /fit-baseline   body: an R_A table as CSV (io/ra_table.h's form: observation_deg,
                       entrance_deg, rotation_deg, ra), at most 64 KiB
                       -> 200 and `retroprism fit --ra TABLE --baseline-only --json`'s JSON:
                          the MaterialX-style retroreflective GGX fitted to the table
                       -> 400 and {"error": text} when the table is refused (the reader's
                          message, naming the line and the column)

The fit is the command's own (analysis/ra_fit.h), run as a child process; nothing of the fit
lives here.

Usage: serve.py --directory ROOT --port N --retroprism EXE
"""

import argparse
import functools
import http.server
import json
import os
import subprocess
import tempfile

MAX_BODY = 64 * 1024
FIT_SECONDS = 120


class Handler(http.server.SimpleHTTPRequestHandler):
    retroprism = ""

    def reply(self, status, payload):
        body = json.dumps(payload).encode()
        self.send_response(status)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def do_POST(self):
        if self.path != "/fit-baseline":
            return self.reply(404, {"error": f"{self.path}: no such request (POST /fit-baseline)"})
        try:
            length = int(self.headers.get("Content-Length", ""))
        except ValueError:
            return self.reply(411, {"error": "POST /fit-baseline needs a Content-Length"})
        if length <= 0 or length > MAX_BODY:
            return self.reply(413, {"error": f"the R_A table has {length} bytes; allowed 1 to {MAX_BODY}"})
        table = self.rfile.read(length)
        with tempfile.TemporaryDirectory(prefix="retroprism-view-fit-") as folder:
            path = os.path.join(folder, "page_ra_table.csv")
            with open(path, "wb") as f:
                f.write(table)
            try:
                run = subprocess.run(
                    [self.retroprism, "fit", "--ra", path, "--baseline-only", "--json"],
                    capture_output=True, text=True, timeout=FIT_SECONDS)
            except subprocess.TimeoutExpired:
                return self.reply(500, {"error": f"the baseline's fit took over {FIT_SECONDS} s"})
            except OSError as e:
                return self.reply(500, {"error": f"{self.retroprism}: cannot run it to fit the baseline: {e.strerror}"})
        if run.returncode != 0:
            text = run.stderr.strip().replace(path, "the page's R_A table")
            return self.reply(400, {"error": text or f"retroprism fit exited with {run.returncode}"})
        try:
            answer = json.loads(run.stdout)
        except ValueError:
            return self.reply(500, {"error": f"retroprism fit --json printed no JSON: {run.stdout[:200]!r}"})
        return self.reply(200, answer)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--directory", required=True)
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--retroprism", required=True)
    args = parser.parse_args()
    Handler.retroprism = args.retroprism
    handler = functools.partial(Handler, directory=args.directory)
    try:
        server = http.server.ThreadingHTTPServer(("127.0.0.1", args.port), handler)
    except OSError as e:
        raise SystemExit(f"serve.py: cannot listen on 127.0.0.1:{args.port}: {e.strerror}")
    with server:
        try:
            server.serve_forever()
        except KeyboardInterrupt:
            pass


if __name__ == "__main__":
    main()
