"""Every registered planner, cure law and exporter reached by name from Python with its key table
(vpsim.components()): each planner plans a small job of its process from its table's defaults
and examples, each cure law cures exactly the voxels at or above its critical dose, each exporter
writes a plan it accepts."""
import os

import numpy as np
import pytest

import vpsim
from conftest import small_dlp_job, small_job

COMPONENTS = vpsim.components()
# A projector calibration (seed 001's), which the greyscale planners and exporters need.
GREY_MACHINE = {"process": "dlp", "pixel_pitch": "62.5 um", "blur_radius": "40 um",
                "layer_thickness": "50 um", "exposure_time": "5 s",
                "grey_levels": [[150, "12.2 mW/cm^2"], [200, "17 mW/cm^2"], [255, "27 mW/cm^2"]]}


def section(component, **extra):
    """A component's section from its key table, as the contracts test makes it: every key
    that has an example at its example (the required ones have one), the others at their
    defaults."""
    keys = {k.name: k.example for k in component["keys"] if "example" in k}  # .keys: dict-like
    keys.update(extra)
    return keys


def names(kind):
    return [c.name for c in COMPONENTS[kind]]


@pytest.mark.parametrize("name", names("planners"))
def test_every_planner_by_name(name):
    planner = next(p for p in COMPONENTS.planners if p.name == name)
    reasons = []
    for job in (small_job(), small_dlp_job(machine=GREY_MACHINE)):
        job["plan"] = section(planner, strategy=name)
        try:
            plan = vpsim.plan(job)
        except vpsim.InputError as error:  # a planner of the other process
            reasons.append(str(error))
            continue
        assert plan.strategy == name and len(plan) == 4
        assert np.isfinite(plan.energy) and plan.energy > 0
        return
    pytest.fail(f"planner {name} planned neither job: {reasons}")


@pytest.mark.parametrize("name", names("cure_laws"))
def test_every_cure_law_by_name(name):
    law = next(c for c in COMPONENTS.cure_laws if c.name == name)
    dose = np.geomspace(1e-3, 10.0, 4001).astype(np.float32)  # mJ/mm^2, increasing
    result = vpsim.cure(section(law, model=name), dose)
    cured = result.cured.astype(bool)
    assert cured.any() and not cured.all()
    first = int(np.argmax(cured))
    assert cured[first:].all()  # monotone in dose
    assert dose[first - 1] < result.critical_dose <= dose[first] * (1 + 1e-6)


@pytest.mark.parametrize("name", names("exporters"))
def test_every_exporter_by_name(name, tmp_path):
    exporter = next(e for e in COMPONENTS.exporters if e.name == name)
    reasons = []
    for job in (small_job(), small_dlp_job()):
        path = tmp_path / f"{name}-{job['machine']['process']}"
        try:
            summary = vpsim.export(vpsim.plan(job), path, exporter=name,
                                   options=section(exporter))
        except vpsim.InputError as error:  # a plan of the other process
            reasons.append(str(error))
            continue
        assert summary.exporter == name and summary.layers == 4
        assert os.path.exists(path)
        return
    pytest.fail(f"exporter {name} wrote neither plan: {reasons}")
