#!/usr/bin/env python3
"""Fails when a test that is not GPU-only skipped: CI (scripts/test.sh under CI=true) must run
every test but the ones that need a GPU, which CI does not have.

    scripts/check_skips.py JUNIT_XML BUILD_DIR

JUNIT_XML is what `ctest --output-junit` wrote; BUILD_DIR the CTest build folder, whose
`ctest --show-only=json-v1` gives each test's labels (CTest's JUnit file has none). A test may
skip only if it carries the label `gpu` (tests/gpu/: gtest_discover_tests labels them so).

Two kinds of skip are caught:
  - CTest's own: a <skipped> result (SKIP_REGULAR_EXPRESSION matched GoogleTest's
    "[  SKIPPED ]", or SKIP_RETURN_CODE 77 from a script);
  - a hidden one: a test CTest counted as passed whose output still shows "[  SKIPPED ]" (a
    GoogleTest binary registered by add_test without SKIP_REGULAR_EXPRESSION; gtest_discover_tests
    sets it). ctest must keep the whole output of passed tests for this (scripts/test.sh passes
    --test-output-size-passed).
Exit 0: no such skip; 1: some; 2: bad arguments or unreadable files.
"""
import json
import subprocess
import sys
import xml.etree.ElementTree as ET

ALLOWED_LABEL = "gpu"
GTEST_SKIP_MARK = "[  SKIPPED ]"


def labels_by_test(build_dir):
    out = subprocess.run(["ctest", "--test-dir", build_dir, "--show-only=json-v1"], check=True,
                         capture_output=True, text=True).stdout
    labels = {}
    for test in json.loads(out)["tests"]:
        props = {p["name"]: p["value"] for p in test.get("properties", [])}
        labels[test["name"]] = props.get("LABELS", [])
    return labels


def skip_reason(out):
    """GoogleTest's skip message (the line after "FILE:LINE: Skipped") or a script's "SKIP: ..."."""
    lines = [l.strip() for l in out.splitlines()]
    for i, line in enumerate(lines):
        if line.endswith(": Skipped") and i + 1 < len(lines):
            return lines[i + 1]
        if line.startswith("SKIP:"):
            return line
    return ""


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    junit, build_dir = argv[1], argv[2]
    try:
        cases = ET.parse(junit).getroot().iter("testcase")
        labels = labels_by_test(build_dir)
    except (OSError, ET.ParseError, subprocess.CalledProcessError, ValueError, KeyError) as e:
        print(f"check_skips: cannot read {junit} or the tests of {build_dir}: {e}", file=sys.stderr)
        return 2

    ran = skipped_gpu = 0
    bad = []
    for case in cases:
        name = case.get("name")
        skipped = case.find("skipped")
        out = case.findtext("system-out") or ""
        if skipped is not None:
            why = skipped.get("message", "skipped")
        elif GTEST_SKIP_MARK in out:
            why = "counted as passed by CTest, but GoogleTest says SKIPPED: no SKIP_REGULAR_EXPRESSION"
        else:
            ran += 1
            continue
        if ALLOWED_LABEL in labels.get(name, []):
            skipped_gpu += 1
        else:
            bad.append((name, why, labels.get(name, []), skip_reason(out)))

    for name, why, test_labels, reason in bad:
        print(f"check_skips: {name} skipped ({why}); labels {test_labels or 'none'}: only tests labelled "
              f"'{ALLOWED_LABEL}' may skip{': ' + reason if reason else ''}", file=sys.stderr)
    print(f"check_skips: {ran} ran, {skipped_gpu} GPU-only skipped, {len(bad)} other skipped", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
