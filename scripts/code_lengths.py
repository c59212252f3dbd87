#!/usr/bin/env python3
"""Lists the tracked C++ files over 600 lines and the functions over 100 lines outside tests (issue 26's rule).

Usage: scripts/code_lengths.py [REPOSITORY]  (default: the current folder). A heuristic, not a parser: braces are
matched on the code with comments and string literals removed (raw strings are not), namespace, extern "C", class,
struct, union and enum braces are transparent, and a brace after a ')' (and const/noexcept/override/a trailing return
type) outside a function opens one. Exit code 0 always: it reports, it does not judge.
"""
import re
import subprocess
import sys

if len(sys.argv) < 2:
    sys.argv.append(".")
files = subprocess.run(["git", "ls-files", "*.cc", "*.h", "*.cpp", "*.hpp"], capture_output=True, text=True,
                       cwd=sys.argv[1]).stdout.split()
files = [f for f in files if not f.startswith(("tests/", "third_party/", "build/")) and "/test" not in f]
long_files, long_funcs = [], []
sig_end = re.compile(r"\)\s*(const)?\s*(noexcept)?\s*(override|final)?\s*(->\s*[\w:<>,\s]+)?\s*$")
for f in files:
    text = open(f"{sys.argv[1]}/{f}", encoding="utf-8", errors="replace").read()
    n = text.count("\n")
    if n > 600: long_files.append((n, f))
    # strip comments and strings, keep newlines
    code = re.sub(r'//[^\n]*|/\*.*?\*/|"(\\.|[^"\\\n])*"|\'(\\.|[^\'\\\n])*\'',
                  lambda m: "\n" * m.group(0).count("\n") if m.group(0).startswith("/") else '""', text, flags=re.S)
    stack = []  # (kind, start_line, name)
    last = 0
    line = 1
    for i, ch in enumerate(code):
        if ch == "\n": line += 1
        elif ch == "{":
            head = code[last:i]
            compact = " ".join(head.split())
            in_func = any(k == "f" for k, _, _ in stack)
            if not in_func and re.search(r"\b(namespace|class|struct|union|enum)\b[^()]*$", compact) or compact.endswith('extern ""'):
                stack.append(("t", line, ""))
            elif not in_func and sig_end.search(compact.split("=")[-1] if "operator" not in compact else compact) and "(" in compact:
                name = re.findall(r"([~\w:]+)\s*\(", compact)
                stack.append(("f", line, name[0] if name else compact[-40:]))
            else:
                stack.append(("o", line, ""))
            last = i + 1
        elif ch == "}":
            if stack:
                kind, start, name = stack.pop()
                if kind == "f" and line - start + 1 > 100: long_funcs.append((line - start + 1, f, start, name))
            last = i + 1
        elif ch == ";":
            last = i + 1
print("files over 600 lines:")
for n, f in sorted(long_files, reverse=True): print(f"  {n:5d} {f}")
print("functions over 100 lines:")
for n, f, start, name in sorted(long_funcs, reverse=True): print(f"  {n:5d} {f}:{start} {name}")
