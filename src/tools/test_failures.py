#!/usr/bin/env python3
"""The messages of failed test cases in catkin's JUnit results, shortened.

`make test` prints them last, so that a CI log that keeps only its end
still shows why a test failed, not only that it did.

usage: test_failures.py TEST_RESULTS_DIR [MAX_LINES_PER_CASE]
"""
import pathlib
import sys
import xml.etree.ElementTree as ET


def main() -> int:
    root = pathlib.Path(sys.argv[1])
    max_lines = int(sys.argv[2]) if len(sys.argv) > 2 else 16
    for xml in sorted(root.rglob("*.xml")):
        try:
            tree = ET.parse(xml)
        except ET.ParseError as e:
            print(f"{xml.name}: unreadable ({e})")
            continue
        for case in tree.iter("testcase"):
            for failure in list(case.iter("failure")) + list(case.iter("error")):
                text = (failure.text or failure.get("message") or "").strip().splitlines()
                name = f"{case.get('classname', '')}.{case.get('name', '')}"
                print(f"--- {name} ({xml.name}):")
                # The end of a long message says most (a log's last lines).
                if len(text) > max_lines:
                    print(f"  [{len(text) - max_lines} lines left out]")
                    text = text[-max_lines:]
                for line in text:
                    print("  " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
