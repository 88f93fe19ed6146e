#!/usr/bin/python3
"""How long the untangling of `hexmesh run` goes without fewer inverted elements, from its logs.

usage: untangling_plateaus.py LOG...   (the logs of `hexmesh run`, e.g. try_bodies.py's *.log or
                                        bench/run_bodies.sh's)

An untangling call is a run of the log's progress lines `untangle N  E ...  inverted K ...  T s`
(T counted from the call's start); a line with N = 1 starts the next call. Within a call, the
fewest inverted elements so far fall at some lines; a plateau is the time between two such
lines (from the call's start to its first line counts as progress), or, when the call ends with
elements still inverted, from the last such line to its end. Prints one row per log: the
untangling time (the calls' last T, summed), the longest plateau, its share of the untangling
time and the call it is in (1-based, in log order), and whether the share is over 20 %.
"""
import re
import sys

LINE = re.compile(r"^\s+untangle\s+(\d+)\s+E\s+\S+\s+eps\s+\S+\s+min det\s+\S+\s+inverted\s+(\d+)"
                  r".*?([0-9.]+) s\s*$")


def calls(text):
    """The untangling calls of a log, each a list of (inverted, seconds)."""
    out = []
    for line in text.splitlines():
        m = LINE.match(line)
        if not m:
            continue
        n, inverted, seconds = int(m.group(1)), int(m.group(2)), float(m.group(3))
        if n == 1 or not out:
            out.append([])
        out[-1].append((inverted, seconds))
    return out


def longest_plateau(call):
    """The longest time within one call without a new fewest inverted count."""
    fewest, since, longest = None, 0.0, 0.0
    for inverted, seconds in call:
        if fewest is None or inverted < fewest:
            if fewest is not None:  # the first line's time is progress, not a plateau
                longest = max(longest, seconds - since)
            fewest, since = inverted, seconds
    if call and fewest > 0:
        longest = max(longest, call[-1][1] - since)
    return longest


def main(paths):
    if not paths:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    print("| log | untangling calls | untangling s | longest plateau s | share | in call | over 20 % |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for path in paths:
        try:
            text = open(path, errors="replace").read()
        except OSError as e:
            print(f"untangling_plateaus.py: cannot read {path}: {e.strerror}", file=sys.stderr)
            return 1
        cs = calls(text)
        total = sum(c[-1][1] for c in cs)
        plateaus = [longest_plateau(c) for c in cs]
        worst = max(range(len(cs)), key=lambda i: plateaus[i]) if cs else -1
        longest = plateaus[worst] if cs else 0.0
        share = longest / total if total > 0 else 0.0
        print(f"| {path} | {len(cs)} | {total:.2f} | {longest:.2f} | {100 * share:.0f} % | "
              f"{worst + 1 if cs else '-'} | {'yes' if share > 0.2 else 'no'} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
