#!/usr/bin/python3
"""Doxygen's INPUT_FILTER for the project's headers: their plain // comments become its
documentation, line for line (the line count is kept, so Doxygen's warnings name the header's
own lines).

- The comment block at the top of a header (before its first line of code) documents the
  header's Doxygen group, named after the file (batch.h: batch_h), and every declaration in the
  header's namespaces joins that group: a section of an API page (docs/api/) shows one group.
- A block of // lines directly above a declaration at namespace, class or struct scope (no blank
  line between) documents that declaration; above a namespace it stays a plain comment (each
  header would otherwise add its preamble to the namespace's).
- A comment after a member or enumerator on its line (`int n; // what`) documents that member,
  and so do the lines that continue it, indented past the member's start.
- Comments inside function bodies, and blocks followed by a blank line (a section's heading),
  stay plain comments.
"""
import os
import re
import sys

COMMENT = re.compile(r"^(\s*)//(?![/!])(.*)$")
TRAILING_MEMBER = re.compile(r"^(\s*)(.*?[;,])(\s*)//(?![/!])(.*)$")
GROUP_NAME = re.compile(r"\W")
SCOPE_OPENER = re.compile(r"\b(namespace|struct|class|union|enum)\b|^\s*extern\s+\"C\"")


def after_literal(line, i):
    """The index after the string or character literal that starts at line[i]."""
    quote = line[i]
    i += 1
    while i < len(line) and line[i] != quote:
        i += 2 if line[i] == "\\" else 1
    return i + 1


def strip_code(line, inBlockComment):
    """The line without comments, strings and character literals (for counting braces), and
    whether a /* comment is still open at its end."""
    out = []
    i = 0
    while i < len(line):
        if inBlockComment:
            end = line.find("*/", i)
            if end < 0:
                return "".join(out), True
            i = end + 2
            inBlockComment = False
        elif line.startswith("//", i):
            break
        elif line.startswith("/*", i):
            inBlockComment = True
            i += 2
        elif line[i] in "\"'":
            i = after_literal(line, i)
        else:
            out.append(line[i])
            i += 1
    return "".join(out), inBlockComment


def comment_start(line):
    """Where the line's // comment starts (its length when it has none)."""
    i = 0
    while i < len(line):
        if line.startswith("//", i):
            return i
        i = after_literal(line, i) if line[i] in "\"'" else i + 1
    return len(line)


class Scopes:
    """Which braces are open: a namespace ('namespace'), a class, struct, union or enum body
    ('scope'), or a function body or initialiser ('body')."""

    def __init__(self):
        self.stack = []
        self.statement = ""
        self.inBlockComment = False
        self.continuedDirective = False

    def at_declaration_scope(self):
        return all(kind != "body" for kind in self.stack)

    def namespaces(self):
        return sum(kind == "namespace" for kind in self.stack)

    def feed(self, line):
        code, self.inBlockComment = strip_code(line, self.inBlockComment)
        if self.continuedDirective or code.lstrip().startswith("#"):
            self.continuedDirective = code.rstrip().endswith("\\")
            return
        for ch in code:
            if ch == "{":
                if re.search(r"\bnamespace\b", self.statement):
                    self.stack.append("namespace")
                elif SCOPE_OPENER.search(self.statement):
                    self.stack.append("scope")
                else:
                    self.stack.append("body")
                self.statement = ""
            elif ch == "}":
                if self.stack:
                    self.stack.pop()
                self.statement = ""
            elif ch == ";":
                self.statement = ""
            else:
                self.statement += ch
        self.statement += " "


def to_doc(line, marker):
    m = COMMENT.match(line)
    return f"{m.group(1)}{marker}{m.group(2)}"


def filter_header(lines, group):
    out = list(lines)
    n = len(lines)
    # The file's own block documents the header's group.
    top = 0
    while top < n and COMMENT.match(lines[top]):
        top += 1
    if top:
        for i in range(top):
            out[i] = to_doc(lines[i], "///")
        out[top - 1] += f" \\defgroup {GROUP_NAME.sub('_', group)} {group}"
    scopes = Scopes()
    for i in range(top):
        scopes.feed(lines[i])
    block = []  # indices of the pending // block
    trailingIndent = None  # indentation of the member whose trailing comment may continue
    for i in range(top, n):
        line = lines[i]
        if COMMENT.match(line):
            indent = len(line) - len(line.lstrip())
            if not block and trailingIndent is not None and indent > trailingIndent:
                out[i] = to_doc(line, "///<")
                continue
            trailingIndent = None
            block.append(i)
            continue
        stripped = line.strip()
        followsBlock = block and block[-1] == i - 1
        if followsBlock and stripped and scopes.at_declaration_scope():
            isDefine = stripped.startswith("#define")
            isDirective = stripped.startswith("#") and not isDefine
            opensNamespace = re.match(r"(inline\s+)?namespace\b", stripped) is not None
            if not isDirective and not opensNamespace and not stripped.startswith("}"):
                for j in block:
                    out[j] = to_doc(lines[j], "///")
        block = []
        trailingIndent = None
        m = TRAILING_MEMBER.match(line)
        if m and scopes.at_declaration_scope() and not m.group(2).lstrip().startswith("#"):
            out[i] = f"{m.group(1)}{m.group(2)}{m.group(3)}///<{m.group(4)}"
            trailingIndent = len(m.group(1))
        # The declarations of each namespace block join the header's group; a group is closed
        # before a namespace opens or closes and opened again inside it (Doxygen's grouping
        # markers do not reach into a nested namespace).
        namespacesBefore = scopes.namespaces()
        scopes.feed(line)
        if top and scopes.namespaces() != namespacesBefore:
            if namespacesBefore > 0:
                out[i] = "/** @} */ " + out[i]
            if scopes.namespaces() > 0:
                at = comment_start(out[i])
                opener = f" /** \\addtogroup {GROUP_NAME.sub('_', group)} */ /** @{{ */ "
                out[i] = out[i][:at].rstrip() + opener + out[i][at:]
    return out


def main():
    with open(sys.argv[1], encoding="utf-8") as f:
        text = f.read()
    lines = text.split("\n")
    sys.stdout.write("\n".join(filter_header(lines, os.path.basename(sys.argv[1]))))


if __name__ == "__main__":
    main()
