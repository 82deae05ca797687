#!/usr/bin/env python3
"""Each test's time in the last ctest run of a build, beside its label and TIMEOUT (tests/CMakeLists.txt).

    scripts/test_times.py [BUILD_DIR [LOG...]]   (default: build; run after `ctest` there)

Reads BUILD_DIR/Testing/Temporary/LastTest.log, or the ctest logs given (the times; a later log wins) and `ctest --show-only=json-v1` (labels and
timeouts), prints one line per test, slowest first, with the timeout the project's rule gives (five times
the measured time rounded up to 10 s, at least 60 s, at most 1500 s) and marks a test whose TIMEOUT is under twice
its time. Exits 1 when such a test exists, 2 when the log is missing.
"""
import json
import math
import os
import re
import subprocess
import sys


def measured_times(log_path):
    times, name = {}, None
    with open(log_path, encoding="utf-8", errors="replace") as log:
        for line in log:
            m = re.match(r'^"(.+)" start time:', line)
            if m:
                name = m.group(1)
                continue
            m = re.match(r"^Test time =\s*([0-9.]+) sec", line)
            if m and name:
                times[name] = float(m.group(1))
                name = None
    return times


def configured(build):
    out = subprocess.run(["ctest", "--show-only=json-v1"], cwd=build, check=True, capture_output=True, text=True)
    tests = {}
    for t in json.loads(out.stdout)["tests"]:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        tests[t["name"]] = (",".join(props.get("LABELS", [])) or "-", props.get("TIMEOUT"))
    return tests


def rule(seconds):
    return min(1500, max(60, int(math.ceil(5 * seconds / 10.0)) * 10))


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    logs = sys.argv[2:] or [os.path.join(build, "Testing", "Temporary", "LastTest.log")]
    times = {}
    for log in logs:
        if not os.path.exists(log):
            print(f"test_times: {log} is missing: run ctest in {build} first", file=sys.stderr)
            return 2
        times.update(measured_times(log))
    tests = configured(build)
    short = 0
    print(f"{'test':36} {'label':8} {'seconds':>8} {'timeout':>8} {'rule':>6}")
    for name in sorted(tests, key=lambda n: -times.get(n, -1.0)):
        label, timeout = tests[name]
        t = times.get(name)
        shown = f"{t:8.1f}" if t is not None else f"{'not run':>8}"
        flag = ""
        if t is not None and timeout is not None and timeout < 2 * t:
            flag, short = "  TIMEOUT under twice the time", short + 1
        rule_text = str(rule(t)) if t is not None else "-"
        print(f"{name:36} {label:8} {shown} {timeout if timeout is not None else '-':>8} {rule_text:>6}{flag}")
    unit = sum(times.get(n, 0.0) for n, (label, _) in tests.items() if label == "unit")
    print(f"unit tests together: {unit:.1f} s (one at a time)")
    return 1 if short else 0


if __name__ == "__main__":
    sys.exit(main())
