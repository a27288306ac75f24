"""numpy inputs where the CLI reads a file, each against the file-based input on the same data
(figures within 1e-6 relative): a part as vertex and triangle arrays against its STL file, a
DLP mask stack against a plan.json holding the same masks, a working curve's arrays against its
CSV (as calibrate's figures and as cure()'s law)."""
import json

import numpy as np
import pytest

import vpsim
from conftest import close, small_dlp_job, small_job, step_mesh, write_job, write_stl

FIGURES = ("iou", "overcure_below_downfacing_mm", "cured_volume_mm3", "validation", "exposure",
           "plan")


def timeless(value):
    """A report's figures without its timings (keys with "seconds")."""
    if isinstance(value, dict):
        return {k: timeless(v) for k, v in value.items() if "seconds" not in k}
    return value


def without_part(job):
    return {key: value for key, value in job.items() if key != "part"}


def test_part_arrays_against_stl_file(run_cli, tmp_path):
    vertices, triangles = step_mesh()
    stl = write_stl(tmp_path / "step.stl", vertices, triangles)
    job = small_job(part={"stl": stl})
    cli = run_cli("run", write_job(tmp_path, job), "--out", str(tmp_path / "cli"), "--json")
    arrays = without_part(job)
    py = vpsim.run(arrays, part=(vertices, triangles)).to_dict()
    for key in FIGURES:
        close(timeless(py[key]), timeless(cli[key]))
    assert py["iou"] > 0.5  # the step is printed, not an empty part

    # the plan and the validation from the arrays too
    assert vpsim.plan(arrays, part=(vertices, triangles)).to_json() == vpsim.plan(job).to_json()
    exposure = vpsim.expose(arrays, part=(vertices, triangles))
    close(vpsim.validate(arrays, exposure, part=(vertices, triangles)).to_dict(),
          cli["validation"])

    with pytest.raises(vpsim.InputError) as error:  # both a part section and arrays
        vpsim.plan(job, part=(vertices, triangles))
    assert error.value.key == "part"
    with pytest.raises(vpsim.InputError) as error:  # an open mesh is refused as its STL is
        vpsim.plan(arrays, part=(vertices, triangles[:-1]))
    assert "open edges" in str(error.value)


def mask_stack(plan):
    """Doses that vary over each mask: the uniform plan's dose times a ramp in x and y."""
    layers = [plan.layer(k)["masks"][0]["dose"] for k in range(len(plan))]
    nx, ny = layers[0].shape
    ramp = (0.6 + 0.8 * np.add.outer(np.arange(nx) / nx, np.arange(ny) / ny) / 2)
    return np.stack([(d * ramp).astype(np.float32) for d in layers])


def test_mask_stack_against_plan_file(run_cli, tmp_path):
    job = small_dlp_job()
    uniform = vpsim.plan(job)
    stack = mask_stack(uniform)
    # the file-based input: plan.json with the same doses (row-major, row j at y)
    document = uniform.to_json()
    for k, layer in enumerate(document["layers"]):
        layer["masks"][0]["dose_mJ_per_mm2"] = stack[k].T.ravel().astype(float).tolist()
    plan_file = tmp_path / "masks.json"
    plan_file.write_text(json.dumps(document))
    path = write_job(tmp_path, job)
    cli = run_cli("run", path, "--plan", str(plan_file), "--out", str(tmp_path / "cli"),
                  "--json")
    py = vpsim.run(job, masks=stack).to_dict()
    for key in ("iou", "overcure_below_downfacing_mm", "cured_volume_mm3", "validation"):
        close(py[key], cli[key])
    assert py["cured_volume_mm3"] != pytest.approx(
        vpsim.run(job).cured_volume_mm3, rel=1e-3)  # the stack did change the print

    # Plan.set_masks and expose(masks=) hold exactly these doses
    changed = uniform.copy()
    changed.set_masks(stack)
    assert changed.to_json() == document
    assert uniform.to_json() != document  # copy() left the original alone
    exposure = vpsim.expose(job, masks=stack)
    for k in range(len(uniform)):
        assert np.array_equal(exposure.plan.layer(k)["masks"][0]["dose"], stack[k])

    # uint8 grey levels: level g gives g / 255 of full_dose
    grey = np.round(stack / stack.max() * 255).astype(np.uint8)
    levels = uniform.copy()
    levels.set_masks(grey, full_dose="100 mJ/cm^2")
    expected = (grey.astype(np.float64) * (1.0 / 255.0)).astype(np.float32)  # mJ/mm^2
    for k in range(len(uniform)):
        assert np.allclose(levels.layer(k)["masks"][0]["dose"], expected[k], rtol=1e-6)

    with pytest.raises(vpsim.InputError) as error:
        uniform.copy().set_masks(grey)
    assert error.value.key == "full_dose"
    with pytest.raises(vpsim.InputError) as error:
        uniform.copy().set_masks(stack[:-1])
    assert error.value.key == "masks"
    with pytest.raises(vpsim.InputError):
        uniform.copy().set_masks(-stack)


def test_working_curve_arrays_against_csv(run_cli, tmp_path):
    doses = np.array([0.2, 0.3, 0.5, 0.8, 1.2, 2.0])  # mJ/mm^2
    depths = 0.36 * np.log(doses / 0.09) * np.array([1.01, 0.99, 1.0, 1.02, 0.98, 1.0])
    csv = tmp_path / "wc.csv"
    csv.write_text("dose_mJ_per_cm2,thickness_um\n" +
                   "".join(f"{e * 100!r},{d * 1000!r}\n" for e, d in zip(doses, depths)))
    cli = run_cli("calibrate", "--working-curve", str(csv), "--gel-point", "0.276", "--json")
    py = vpsim.calibrate(doses, depths, gel_point=0.276)
    for key in ("penetration_depth_mm", "penetration_depth_mm_stderr",
                "critical_dose_mJ_per_cm2", "critical_dose_mJ_per_cm2_stderr", "K_cm2_per_mJ",
                "r_squared", "residual_std_mm", "cure_model"):
        close(py.to_dict()[key], cli[key])
    # the calibration as a cure law gives the CSV's law's cured voxels and conversion
    dose = np.linspace(0.0, 3.0, 301, dtype=np.float32).reshape(7, 43)
    from_arrays = vpsim.cure(py, dose)
    from_csv = vpsim.cure(cli["cure_model"], dose)
    assert np.array_equal(from_arrays.cured, from_csv.cured)
    assert np.allclose(from_arrays.conversion, from_csv.conversion, rtol=1e-6, atol=0)
    assert 0 < from_arrays.cured.sum() < dose.size
