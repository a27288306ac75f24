#!/usr/bin/env python3
"""Checks report.json files against docs/report-schema.json (JSON Schema draft 2020-12).

Usage:
  check_report.py SCHEMA REPORT...         exit 1 when any report breaks the schema
  check_report.py --self-test SCHEMA GOOD  the checker must accept GOOD and reject copies of it
                                           with a key missing, mistyped or out of range
Needs Debian's python3-jsonschema (tools/debian-packages.txt).
"""
import copy
import json
import sys

try:
    import jsonschema
except ImportError:
    sys.exit("check_report: python3 module jsonschema is missing (apt-get install python3-jsonschema)")


def validator(schema_path):
    with open(schema_path) as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def errors(check, report):
    found = sorted(check.iter_errors(report), key=lambda e: list(e.absolute_path))
    return ["/".join(str(p) for p in e.absolute_path) + ": " + e.message[:200] for e in found]


def self_test(check, good_path):
    with open(good_path) as f:
        good = json.load(f)
    problems = errors(check, good)
    if problems:
        print(f"check_report: the good report {good_path} is rejected: {problems[:3]}")
        return 1

    def without(*path):
        def change(r):
            node = r
            for key in path[:-1]:
                node = node[key]
            del node[path[-1]]
        return change

    def setting(value, *path):
        def change(r):
            node = r
            for key in path[:-1]:
                node = node[key]
            node[path[-1]] = value
        return change

    cases = {
        "no iou": without("iou"),
        "iou as a string": setting("0.9", "iou"),
        "iou above 1": setting(1.5, "iou"),
        "no surface_deviation_mm": without("surface_deviation_mm"),
        "surface_deviation_mm.rms as a string": setting("x", "surface_deviation_mm", "rms"),
        "no validation.layers": without("validation", "layers"),
        "a layer's z as a string": setting("0", "validation", "layers", 0, "z"),
        "no stage_seconds.expose": without("stage_seconds", "expose"),
        "build_time_s as a number": setting(3.0, "build_time_s"),
        "exposure.grid of two": setting([1, 2], "exposure", "grid"),
        "plan.layers fractional": setting(2.5, "plan", "layers"),
        "features as an object": setting({}, "features"),
        "scan_order without layers": without("scan_order", "layers"),
        "layer_exposure_error.top_layer as a list": setting([], "layer_exposure_error",
                                                            "top_layer"),
        "kernel.from_cache as a number": setting(1, "kernel", "from_cache"),
    }
    failed = 0
    for name, change in cases.items():
        report = copy.deepcopy(good)
        try:
            change(report)
        except (KeyError, IndexError) as e:
            print(f"check_report: self-test case '{name}' needs key {e} in {good_path}")
            failed += 1
            continue
        if not errors(check, report):
            print(f"check_report: FAILED: a report with {name} passes the schema")
            failed += 1
    print(f"check_report: self-test: {len(cases) - failed} of {len(cases)} broken reports rejected")
    return 1 if failed else 0


def main(argv):
    if len(argv) == 4 and argv[1] == "--self-test":
        return self_test(validator(argv[2]), argv[3])
    if len(argv) < 3:
        print(__doc__)
        return 2
    check = validator(argv[1])
    failed = 0
    for path in argv[2:]:
        with open(path) as f:
            problems = errors(check, json.load(f))
        for problem in problems:
            print(f"check_report: {path}: {problem}")
        failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
