#!/usr/bin/env python3
"""Replaces one function of a WGSL text with another text of the same function, for
experiments on the shader's form (`compare_shader` renders a scene with its own shader and
with the result): the text from its comment block to the closing brace at the start of a
line is swapped. Not part of the compiler (only `sdfc-wgsl` spells the product's WGSL).

    scripts/swap-function.py IN.wgsl NAME REPLACEMENT.wgsl OUT.wgsl
"""
import sys


def span(text, name):
    """Where `fn NAME(` starts, with the comment lines just above it, and ends."""
    start = text.find(f"\nfn {name}(")
    if start < 0:
        sys.exit(f"no function {name}")
    start += 1
    while True:
        prev = text.rfind("\n", 0, start - 1) + 1
        if start == 0 or not text[prev:start].startswith("//"):
            break
        start = prev
    end = text.find("\n}\n", start)
    if end < 0:
        sys.exit(f"no end of function {name}")
    return start, end + 3


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    src, name, repl, out = sys.argv[1:]
    text = open(src).read()
    new = open(repl).read()
    if not new.endswith("\n"):
        new += "\n"
    a, b = span(text, name)
    swapped = text[:a] + new + text[b:]
    if swapped == text:
        sys.exit("the replacement is the function itself")
    open(out, "w").write(swapped)


main()
