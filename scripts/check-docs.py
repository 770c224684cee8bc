#!/usr/bin/python3
"""Builds the documentation site and checks it (the ctest entry `docs`; the CMake target `docs`
runs the build alone, with --build-only).

1. Doxygen's XML of the public headers (docs/Doxyfile); any warning fails.
2. Sphinx (MyST pages, Breathe over that XML) into OUT/html: sphinx-build -W --keep-going -n, so
   any warning fails, unresolved references included.
3. Links: every relative link of the built site (href and src, with its #fragment) names a file
   of the site and an id in it; every relative link of README.md and docs/**/*.md (Markdown and
   HTML) names a file of the checkout and, for a #fragment, a heading of that Markdown file (the
   anchors GitHub and MyST make) or an explicit target.
4. Runnable blocks: a fenced code block right after the line `<!-- runnable -->` runs in bash
   (`set -euo pipefail`) in a temporary folder, with the build's `retroprism` first on PATH and
   the checkout's examples/, materialx/ and tests/ linked into the folder, so that commands are
   written as from the checkout's root; a non-zero exit fails. A fenced block right after
   `<!-- output -->` (only blank lines between the two blocks) is what the commands print:
   compared line by line, trailing spaces aside. `<!-- output excerpt -->` quotes consecutive
   lines of the output instead of all of it; `tolerance=R` (e.g. `<!-- output tolerance=1e-9 -->`)
   compares numbers within R relative (absolute below 1), and everything else exactly.
5. Every command of `retroprism --help` has a section in docs/commands.md and a line in the
   README's command list, and every header Doxygen read has its section on a page of docs/api/.

Exits 77 (ctest's SKIP_RETURN_CODE) when Doxygen or sphinx-build is missing.
"""
import argparse
import html.parser
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.parse

SKIP = 77


def fail(errors, message):
    errors.append(message)
    print("docs: " + message, file=sys.stderr)


# ---- 1-2: the build -------------------------------------------------------------------------


def run_tool(name, command, env, errors):
    """Runs a tool; any message it prints, or a non-zero exit, is a failure."""
    start = time.time()
    run = subprocess.run(command, env=dict(os.environ, **env), capture_output=True, text=True)
    messages = (run.stdout + run.stderr).strip()
    if run.returncode != 0 or messages:
        fail(errors, f"{name} (exit {run.returncode}):\n{messages}")
        return None
    return time.time() - start


def build(args, errors):
    xmlOut = os.path.join(args.out, "doxygen")
    shutil.rmtree(xmlOut, ignore_errors=True)
    os.makedirs(xmlOut)
    seconds = run_tool(
        "doxygen",
        [args.doxygen, os.path.join(args.source, "docs", "Doxyfile")],
        {"RP_SOURCE_DIR": args.source, "RP_DOXYGEN_OUT": xmlOut, "RP_PYTHON": sys.executable},
        errors,
    )
    if seconds is None:
        return False
    print(f"docs: doxygen XML of the headers in {seconds:.1f} s")
    html = os.path.join(args.out, "html")
    # -E -a: every page read and written again, so that every warning shows on every run.
    sphinx = [args.sphinx_build, "-W", "--keep-going", "-n", "-E", "-a", "-q", "-b", "html"]
    sphinx += ["-d", os.path.join(args.out, "doctrees"), os.path.join(args.source, "docs"), html]
    xmlEnv = {"RETROPRISM_DOXYGEN_XML": os.path.join(xmlOut, "xml")}
    seconds = run_tool("sphinx-build", sphinx, xmlEnv, errors)
    if seconds is not None:
        print(f"docs: Sphinx site in {seconds:.1f} s: {html}")
    # With --keep-going Sphinx writes the site whatever it warned of: the checks below run on it.
    return os.path.exists(os.path.join(html, "index.html"))


# ---- 3: links -------------------------------------------------------------------------------


class HtmlLinks(html.parser.HTMLParser):
    """The ids of a page and its links (href of a, src of img)."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids = set()
        self.links = []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("id", "name"):
            if attrs.get(key):
                self.ids.add(attrs[key])
        if tag == "a" and attrs.get("href"):
            self.links.append(attrs["href"])
        if tag in ("img", "script") and attrs.get("src"):
            self.links.append(attrs["src"])
        if tag == "link" and attrs.get("href"):
            self.links.append(attrs["href"])


def resolve(page, target):
    """The file a relative link of `page` names (the page itself for a bare #fragment)."""
    if not target:
        return page
    return os.path.normpath(os.path.join(os.path.dirname(page), urllib.parse.unquote(target)))


def is_external(target):
    return re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) is not None or target.startswith("//")


def check_site_links(siteDir, errors):
    pages = {}
    for folder, _, files in os.walk(siteDir):
        for name in files:
            if name.endswith(".html"):
                path = os.path.join(folder, name)
                parser = HtmlLinks()
                with open(path, encoding="utf-8") as f:
                    parser.feed(f.read())
                pages[os.path.normpath(path)] = parser
    checked = 0
    for path, page in pages.items():
        for link in page.links:
            if is_external(link):
                continue
            target, _, fragment = link.partition("#")
            resolved = resolve(path, target.partition("?")[0])
            checked += 1
            where = os.path.relpath(path, siteDir)
            if not os.path.exists(resolved):
                fail(errors, f"site: {where}: link {link}: no such file")
            elif fragment and resolved in pages and fragment not in pages[resolved].ids:
                fail(errors, f"site: {where}: link {link}: no id '{fragment}' in the page")
    return checked


FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})(.*)$")
MD_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML_LINK = re.compile(r"<(?:a|img)\s[^>]*?(?:href|src)=\"([^\"]+)\"")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
MYST_TARGET = re.compile(r"^\(([^)]+)\)=\s*$")


def closes(line, fence):
    """Whether `line` closes a code block opened by `fence` (``` or ~~~, at least as long)."""
    stripped = line.strip()
    return stripped.startswith(fence) and stripped.strip(fence[0]) == ""


def markdown_lines(text):
    """The lines of a Markdown text outside fenced code blocks, with their numbers."""
    fence = None
    for number, line in enumerate(text.split("\n"), 1):
        m = FENCE.match(line)
        if fence is None and m:
            fence = m.group(2)[0] * len(m.group(2))
            continue
        if fence is not None:
            if closes(line, fence):
                fence = None
            continue
        yield number, line


def slug(heading):
    """The anchor GitHub and MyST (myst_heading_anchors) make of a heading's text."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = text.strip().lower().replace(" ", "-")
    return re.sub(r"[^\w\-]", "", text)


def anchors(text):
    found = set()
    counts = {}
    for _, line in markdown_lines(text):
        m = HEADING.match(line)
        if m:
            base = slug(m.group(2))
            n = counts.get(base, 0)
            counts[base] = n + 1
            found.add(base if n == 0 else f"{base}-{n}")
        m = MYST_TARGET.match(line)
        if m:
            found.add(m.group(1))
        for name in re.findall(r"<a\s+(?:name|id)=\"([^\"]+)\"", line):
            found.add(name)
    return found


def check_markdown_links(source, files, errors):
    cache = {}

    def anchors_of(path):
        if path not in cache:
            with open(path, encoding="utf-8") as f:
                cache[path] = anchors(f.read())
        return cache[path]

    checked = 0
    for path in files:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for number, line in markdown_lines(text):
            code = re.sub(r"`[^`]*`", "", line)
            for target in MD_LINK.findall(code) + HTML_LINK.findall(code):
                if is_external(target):
                    continue
                checked += 1
                file, _, fragment = target.partition("#")
                where = f"{os.path.relpath(path, source)}:{number}"
                resolved = resolve(path, file)
                if not os.path.exists(resolved):
                    fail(errors, f"{where}: link {target}: no such file")
                elif fragment and resolved.endswith(".md") and fragment not in anchors_of(resolved):
                    name = os.path.relpath(resolved, source)
                    fail(errors, f"{where}: link {target}: no heading '{fragment}' in {name}")
    return checked


# ---- 4: runnable blocks ---------------------------------------------------------------------


def fenced_blocks(text):
    """(line of the fence, marker comment before it or None, body, next line after it)."""
    lines = text.split("\n")
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence = m.group(2)
        start = i
        body = []
        i += 1
        while i < len(lines) and not closes(lines[i], fence):
            body.append(lines[i])
            i += 1
        marker = lines[start - 1].strip() if start > 0 else ""
        yield start + 1, marker, "\n".join(body), i + 1
        i += 1


OUTPUT_MARKER = re.compile(r"^<!--\s*output((?:\s+(?:excerpt|tolerance=[0-9.eE+-]+))*)\s*-->$")
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?%?")


def same_line(expected, actual, tolerance):
    expected, actual = expected.rstrip(), actual.rstrip()
    if tolerance is None:
        return expected == actual
    e, a = NUMBER.split(expected), NUMBER.split(actual)
    en, an = NUMBER.findall(expected), NUMBER.findall(actual)
    if e != a or len(en) != len(an):
        return False
    for x, y in zip(en, an):
        if x == y:
            continue
        if x.endswith("%") != y.endswith("%"):
            return False
        vx, vy = float(x.rstrip("%")), float(y.rstrip("%"))
        if abs(vx - vy) > tolerance * max(1.0, abs(vx)):
            return False
    return True


def compare_output(expected, actual, excerpt, tolerance):
    want = expected.rstrip("\n").split("\n")
    got = actual.rstrip("\n").split("\n")
    if not excerpt:
        return len(want) == len(got) and all(same_line(w, g, tolerance) for w, g in zip(want, got))
    for start in range(len(got) - len(want) + 1):
        if all(same_line(w, g, tolerance) for w, g in zip(want, got[start:])):
            return True
    return False


def run_blocks(source, files, retroprism, errors):
    ran = compared = 0
    binDir = os.path.dirname(os.path.abspath(retroprism))
    for path in files:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        blocks = list(fenced_blocks(text))
        lines = text.split("\n")
        for k, (line, marker, body, after) in enumerate(blocks):
            if marker != "<!-- runnable -->":
                continue
            where = f"{os.path.relpath(path, source)}:{line}"
            expected = None
            if k + 1 < len(blocks):
                nextLine, nextMarker, nextBody, _ = blocks[k + 1]
                between = lines[after : nextLine - 2]
                m = OUTPUT_MARKER.match(nextMarker)
                if m and all(not s.strip() for s in between):
                    options = m.group(1).split()
                    tolerance = None
                    for option in options:
                        if option.startswith("tolerance="):
                            tolerance = float(option.split("=", 1)[1])
                    expected = (nextBody, "excerpt" in options, tolerance)
            with tempfile.TemporaryDirectory(prefix="retroprism-docs-") as work:
                for folder in ("examples", "materialx", "tests"):
                    os.symlink(os.path.join(source, folder), os.path.join(work, folder))
                env = dict(os.environ, PATH=binDir + os.pathsep + os.environ.get("PATH", ""))
                start = time.time()
                try:
                    run = subprocess.run(
                        ["bash", "-c", "set -euo pipefail\n" + body],
                        cwd=work,
                        env=env,
                        capture_output=True,
                        text=True,
                        timeout=120,
                    )
                except subprocess.TimeoutExpired:
                    fail(errors, f"{where}: the block did not finish in 120 s")
                    continue
                seconds = time.time() - start
            ran += 1
            if run.returncode != 0:
                fail(errors, f"{where}: exit {run.returncode}\n{body}\n{run.stdout}{run.stderr}")
                continue
            if expected is not None:
                compared += 1
                quoted, excerpt, tolerance = expected
                if not compare_output(quoted, run.stdout, excerpt, tolerance):
                    how = "the excerpt" if excerpt else "the output"
                    within = f" (numbers within {tolerance:g})" if tolerance is not None else ""
                    fail(errors, f"{where}: the commands' output differs from {how} quoted after them"
                                 f"{within}:\nquoted:\n{quoted}\nprinted:\n{run.stdout}")
                    continue
            quotedOutput = ", output as quoted" if expected else ""
            print(f"docs: {where}: ran in {seconds:.1f} s{quotedOutput}")
    return ran, compared


# ---- 5: the command list --------------------------------------------------------------------


def check_commands(source, retroprism, errors):
    usage = subprocess.run([retroprism, "--help"], capture_output=True, text=True).stdout
    names = re.findall(r"^  ([a-z]+)\b", usage, re.M)
    with open(os.path.join(source, "docs", "commands.md"), encoding="utf-8") as f:
        reference = f.read()
    with open(os.path.join(source, "README.md"), encoding="utf-8") as f:
        readme = f.read()
    for name in names:
        if not re.search(rf"^#+ .*`{name}`", reference, re.M):
            fail(errors, f"docs/commands.md: no section on `retroprism {name}`")
        if not re.search(rf"^\| `{name}` \|", readme, re.M):
            fail(errors, f"README.md: `retroprism {name}` missing from the command list")
    return len(names)


def check_api_pages(source, xmlDir, errors):
    """Every header Doxygen read (a group each) has its section on an API page."""
    with open(os.path.join(xmlDir, "index.xml"), encoding="utf-8") as f:
        groups = re.findall(r'kind="group"><name>(\w+)</name>', f.read())
    shown = ""
    apiDir = os.path.join(source, "docs", "api")
    for name in sorted(os.listdir(apiDir)):
        with open(os.path.join(apiDir, name), encoding="utf-8") as f:
            shown += f.read()
    for group in groups:
        if f"{{doxygengroup}} {group}\n" not in shown:
            fail(errors, f"docs/api: no section shows the header of Doxygen's group {group}")
    return len(groups)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", required=True, help="the checkout")
    parser.add_argument("--out", required=True, help="where the site goes (OUT/html)")
    parser.add_argument("--doxygen", default=shutil.which("doxygen") or "")
    parser.add_argument("--sphinx-build", default=shutil.which("sphinx-build") or "")
    parser.add_argument("--retroprism", help="the build's retroprism command")
    parser.add_argument("--build-only", action="store_true", help="build the site, check nothing")
    args = parser.parse_args()
    args.source = os.path.abspath(args.source)
    args.out = os.path.abspath(args.out)

    for tool, path in (("doxygen", args.doxygen), ("sphinx-build", args.sphinx_build)):
        if not path or not os.path.exists(path):
            print(f"docs: skipped: {tool} not found (scripts/setup-debian.sh installs it)")
            return SKIP
    errors = []
    built = build(args, errors)
    if not built or args.build_only:
        return 1 if errors else 0

    docsDir = os.path.join(args.source, "docs")
    markdown = [os.path.join(args.source, "README.md")]
    for folder, _, files in os.walk(docsDir):
        markdown += sorted(os.path.join(folder, name) for name in files if name.endswith(".md"))
    headers = check_api_pages(args.source, os.path.join(args.out, "doxygen", "xml"), errors)
    print(f"docs: {headers} headers, each on an API page")
    links = check_site_links(os.path.join(args.out, "html"), errors)
    links += check_markdown_links(args.source, markdown, errors)
    print(f"docs: {links} relative links checked")
    if not args.retroprism:
        fail(errors, "--retroprism is needed to run the runnable blocks")
    else:
        ran, compared = run_blocks(args.source, markdown, args.retroprism, errors)
        print(f"docs: {ran} runnable blocks ran, {compared} outputs compared")
        commands = check_commands(args.source, args.retroprism, errors)
        print(f"docs: {commands} commands, each in docs/commands.md and the README")
    if errors:
        print(f"docs: {len(errors)} problems", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
