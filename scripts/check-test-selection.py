#!/usr/bin/env python3
"""Checks which labels a CTest test preset selects, from CTest's own listing.

    check-test-selection.py PRESET [--without LABEL...] [--with LABEL...] [--only LABEL]

Runs `ctest --preset PRESET --show-only=json-v1` in the repository root (the
preset's build folder must be configured) and fails, naming the tests, when a
selected test carries a --without label, when a --with label selects nothing,
or when --only is given and a selected test lacks that label. Why: a preset's
label filter is easy to defeat silently (CTest 3.25 drops it when -LE is also
given), and CI then runs hours of tests it meant to leave out.
"""
import argparse
import json
import pathlib
import subprocess
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("preset")
    parser.add_argument("--without", nargs="*", default=[], metavar="LABEL")
    parser.add_argument("--with", dest="required", nargs="*", default=[], metavar="LABEL")
    parser.add_argument("--only", metavar="LABEL")
    args = parser.parse_args()
    root = pathlib.Path(__file__).resolve().parent.parent
    listing = subprocess.run(["ctest", "--preset", args.preset, "--show-only=json-v1"],
                             cwd=root, check=True, capture_output=True, text=True).stdout
    labels = {}
    for test in json.loads(listing)["tests"]:
        found = [p["value"] for p in test.get("properties", []) if p["name"] == "LABELS"]
        labels[test["name"]] = set(found[0]) if found else set()
    errors = []
    for label in args.without:
        names = sorted(n for n, l in labels.items() if label in l)
        if names:
            errors.append(f"label '{label}' should be left out but selects {', '.join(names)}")
    for label in args.required:
        if not any(label in l for l in labels.values()):
            errors.append(f"label '{label}' selects no test")
    if args.only:
        names = sorted(n for n, l in labels.items() if args.only not in l)
        if names or not labels:
            errors.append(f"only label '{args.only}' wanted, also selected: {', '.join(names)}")
    for error in errors:
        print(f"check-test-selection: preset '{args.preset}': {error}", file=sys.stderr)
    if not errors:
        print(f"preset '{args.preset}': {len(labels)} tests, selection as expected")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
