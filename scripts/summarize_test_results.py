#!/usr/bin/env python3
"""Sums the JUnit XML files catkin's run_tests writes and prints the totals line.

Prints each failing test case, then "N passed, M failed" (with ", K skipped" when some
were skipped). Exit status: 0 when every test passed and at least one ran, else 1. A test
binary that crashed or never wrote results counts as a failure (rosunit writes a
MISSING-RESULT failure for it).
"""
import pathlib
import sys
import xml.etree.ElementTree as ET


def main(results_dir: str) -> int:
    passed = failed = skipped = 0
    failures = []
    for path in sorted(pathlib.Path(results_dir).rglob("*.xml")):
        suite_passed, suite_failed = passed, failed
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as error:
            failed += 1
            failures.append(f"{path.name}: unreadable result file ({error})")
            continue
        for case in root.iter("testcase"):
            name = f"{case.get('classname', '')}.{case.get('name', '')}"
            bad = case.find("failure") is not None or case.find("error") is not None
            # rostest adds one wrapper case per launch file beside the test node's own
            # cases; it counts only when it failed (the launch itself broke).
            if case.get("classname") == "rostest.runner.RosTest" and not bad:
                continue
            if bad:
                failed += 1
                failures.append(name)
            elif case.find("skipped") is not None or case.get("status") == "notrun":
                skipped += 1
            else:
                passed += 1
        if passed - suite_passed or failed - suite_failed:
            print(f"  {path.stem:<45} {passed - suite_passed:4d} passed {failed - suite_failed:4d} failed")
    for name in failures:
        print(f"FAILED: {name}")
    line = f"{passed} passed, {failed} failed"
    if skipped:
        line += f", {skipped} skipped"
    print(line)
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
