"""Functions a reader can hold in mind (docs/architecture.md, "Code style"): in the C and
C++ sources of the library and the programs, no function runs over 100 lines, and one
that takes 8 or more parameters says why in the comment just above its definition (a
sentence naming its "arguments" or saying it is "positional"), as the lobe kernels and
the public positional functions do.

    check_functions.py SOURCE_DIR

Definitions are read from the layout .clang-format gives them: a header starting at
column 0, its opening brace alone on the next line, its closing brace alone at column 0.
"""
import os
import re
import sys

FOLDERS = ["lib/src", "cmd", "data_synth", "pages"]
MAX_LINES = 100
MAX_PARAMS = 8
REASON = re.compile(r"argument|positional", re.I)
HEADER = re.compile(r"^(?!(?:if|for|while|switch|return|else|do|typedef|struct|enum|union)\b)[A-Za-z_]")


def params(header):
    """The parameter count of a function header: top-level commas of its first
    parenthesised list after the name (function-pointer parameters count once)."""
    start = header.find("(")
    depth, count, seen = 0, 1, False
    for ch in header[start:]:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                break
        elif ch == "," and depth == 1:
            count += 1
        elif depth >= 1 and not ch.isspace():
            seen = True
    inner = header[start + 1:header.find(")", start)].strip() if start >= 0 else ""
    return 0 if not seen or inner == "void" else count


def comment_above(lines, i):
    """The comment lines directly above line i, joined."""
    out = []
    j = i - 1
    while j >= 0 and re.match(r"^\s*(/\*|\*|//)", lines[j]):
        out.append(lines[j])
        j -= 1
    return " ".join(reversed(out))


def functions(path):
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        if HEADER.match(lines[i]) and "(" in lines[i]:
            j = i
            while j < len(lines) - 1 and j < i + 10 and not lines[j + 1] == "{" and not lines[j].rstrip().endswith(";"):
                j += 1
                if HEADER.match(lines[j]):  # a new header: line i was a macro's use, not a definition
                    break
            if j + 1 < len(lines) and lines[j + 1] == "{" and not (j > i and HEADER.match(lines[j])):
                end = j + 2
                while end < len(lines) and lines[end] != "}":
                    end += 1
                header = " ".join(l.strip() for l in lines[i:j + 1])
                name = re.search(r"(\w+)\s*\(", header)
                yield (i + 1, name.group(1) if name else "?", end - i + 1, params(header), comment_above(lines, i))
                i = end
        i += 1


def main():
    root = sys.argv[1]
    bad = []
    n = 0
    for folder in FOLDERS:
        for dirpath, _, files in os.walk(os.path.join(root, folder)):
            for f in sorted(files):
                if not f.endswith((".c", ".cc")):
                    continue
                path = os.path.join(dirpath, f)
                rel = os.path.relpath(path, root)
                for line, name, length, np, comment in functions(path):
                    n += 1
                    if length > MAX_LINES:
                        bad.append("%s:%d: %s is %d lines (split it into named phases)" % (rel, line, name, length))
                    if np >= MAX_PARAMS and not REASON.search(comment):
                        bad.append("%s:%d: %s takes %d parameters and its comment does not say why (a struct, or the "
                                   "reason in the comment above it)" % (rel, line, name, np))
    for b in bad:
        print(b)
    if bad:
        sys.exit(1)
    print("functions: %d read, none over %d lines, every one with %d or more parameters says why"
          % (n, MAX_LINES, MAX_PARAMS))


if __name__ == "__main__":
    main()
