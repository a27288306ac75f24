#!/usr/bin/env python3
"""Every figure a run's report lists (an <img> of index.html, an .svg of manifest.json) is read as
a reader would: the SVG parses, its title, axis labels (with units) and tick labels are SVG text,
a map (an embedded raster) has its colour bar label with a unit besides its axes, the figures with
curves or outlines have their legend entries, and the PNG is beside it.
Usage: check_figures.py RUN_DIR...   (exit 1 on the first report with a failure)"""
import json
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

SVG = "{http://www.w3.org/2000/svg}"
# Legend text expected in the figures that have a legend (stem: words).
LEGENDS = {
    "exposure_xz": ["model", "cured"],
    "exposure_xy": ["model", "cured"],
    "deviation_map_top": ["model silhouette", "cured silhouette"],
    "scan_path": ["marks", "jumps"],
    "kernel/intensity_scattered": ["of I"],
    "kernel/intensity_no_scattering": ["of I"],
    "kernel/radius_vs_depth": ["Monte Carlo", "Eq. 12"],
    "exposure_top_layer": ["model outline", "E"],
    "exposure_error_sorted": ["every layer", "top layer"],
    "dlp_features": ["objective", "this plan"],
    "dlp_dose_along_z": ["optimised dose", "quantised dose"],
    "dlp_conversion_along_z": ["conversion", "gel point"],
}
# The colour bar label (with its unit) of each map the reports write.
COLOUR_BARS = {
    "exposure_xz": "exposure (mJ/cm",
    "exposure_xy": "exposure (mJ/cm",
    "deviation_map_top": "deviation (µm)",
    "kernel/intensity_scattered": "I(r, z) (mW/mm",
    "kernel/intensity_no_scattering": "I(r, z) (mW/mm",
    "exposure_top_layer": "surface exposure (mJ/cm",
    "dlp_mask": "dose of the grey level (mJ/cm",
}
NUMBER = re.compile(r"^[-−]?\d+(\.\d+)?(e[-+]?\d+)?$")
UNIT = re.compile(r"\(.+\)")


def texts(root):
    return [" ".join("".join(t.itertext()).split()) for t in root.iter(SVG + "text")]


def check(run, stem):
    problems = []
    svg = run / (stem + ".svg")
    try:
        root = ET.parse(svg).getroot()
    except (OSError, ET.ParseError) as error:
        return [f"{stem}.svg does not parse: {error}"]
    words = texts(root)
    labels = [t for t in words if re.search(r"[A-Za-z]", t)]
    numbers = [t for t in words if NUMBER.match(t)]
    units = [t for t in labels if UNIT.search(t)]
    is_map = root.find(f".//{SVG}image") is not None
    if len(labels) < 2:
        problems.append(f"{stem}.svg: fewer than 2 labels as text: {labels}")
    if len(numbers) < 4:
        problems.append(f"{stem}.svg: fewer than 4 tick labels as text: {numbers}")
    if len(units) < (3 if is_map else 1):
        problems.append(f"{stem}.svg: axis/colour-bar labels with units missing: {units}")
    bar = COLOUR_BARS.get(stem)
    if is_map and bar is not None and not any(bar in t for t in labels):
        problems.append(f"{stem}.svg: colour bar label '{bar}' missing")
    for word in LEGENDS.get(stem, []):
        if not any(word in t for t in labels):
            problems.append(f"{stem}.svg: legend entry '{word}' missing")
    if not (run / (stem + ".png")).is_file():
        problems.append(f"{stem}.png missing")
    return problems


def main(runs):
    failed = 0
    for run in map(Path, runs):
        html = (run / "index.html").read_text(encoding="utf-8")
        listed = set(re.findall(r"<img src='([^']+)\.svg'", html))
        manifest = json.loads((run / "manifest.json").read_text(encoding="utf-8"))
        names = [f["name"] if isinstance(f, dict) else f for f in manifest.get("files", [])]
        listed |= {n[:-4] for n in names if isinstance(n, str) and n.endswith(".svg")}
        missing = [s for s in ("exposure_xz", "exposure_xy", "deviation_map_top") if s not in listed]
        problems = [f"{s}.svg not listed" for s in missing]
        for stem in sorted(listed):
            problems += check(run, stem)
        for p in problems:
            print(f"figures: FAIL: {run.name}: {p}")
        failed += len(problems)
        print(f"figures: {run.name}: {len(listed)} figures checked")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
