#!/usr/bin/env python3
"""Every Catch2 test case is a CTest test.

catch_discover_tests turns a binary's `--list-test-names-only` into a CMake list.
A ';' in a name splits it into pieces that match no case (13 cases never ran;
their pieces "passed"), and an unbalanced '[' (as in "a radius to [1, 2)")
swallows every name after it (117 of test_runtime's cases once left CTest
without a word). This compares, for each Catch2 binary CTest runs, the names it
registers with the names the binary lists, both ways.

Usage: registration_check.py BUILD_DIR
"""
import collections
import json
import subprocess
import sys


def main() -> int:
    build = sys.argv[1]
    shown = subprocess.run(["ctest", "--show-only=json-v1"], cwd=build, check=True,
                           capture_output=True, text=True).stdout
    registered = collections.defaultdict(set)
    for test in json.loads(shown)["tests"]:
        command = test.get("command") or []
        # catch_discover_tests: BINARY TEST-NAME [EXTRA_ARGS...]
        if len(command) >= 2 and command[0].split("/")[-1].startswith("test_"):
            registered[command[0]].add(test["name"])
    if not registered:
        print("no Catch2 binaries registered in", build)
        return 1
    failed = False
    for binary, names in sorted(registered.items()):
        # Catch2 exits with the number of cases it listed.
        listed = subprocess.run([binary, "--list-test-names-only"], check=False,
                                capture_output=True, text=True).stdout
        cases = {line.strip() for line in listed.splitlines() if line.strip()}
        missing, stray = sorted(cases - names), sorted(names - cases)
        print(f"{binary}: {len(cases)} cases, {len(names)} registered")
        for what, which in (("cases CTest does not run", missing),
                            ("CTest tests that name no case", stray)):
            if which:
                failed = True
                print(f"  {len(which)} {what}, such as:")
                for name in which[:5]:
                    print("   ", name)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
