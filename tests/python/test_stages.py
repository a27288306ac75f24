"""Each stage of the vpsim module against the CLI on the same inputs (figures within 1e-6
relative), the exposure array's axis order against exposure.vdb, and the error classes."""
import json
import os

import numpy as np
import pytest

import vpsim
from conftest import SOURCE, close, small_job, write_job

MATERIAL = os.path.join(SOURCE, "examples", "materials", "alumina-seed000.json")
SLAB = os.path.join(SOURCE, "examples", "materials", "vandehulst-slab.json")


def test_import_and_components(run_cli):
    assert vpsim.components().to_dict() == run_cli("components", "--json")
    names = [p.name for p in vpsim.components().planners]
    assert "aces" in names


def test_mie_sphere(run_cli):
    py = vpsim.mie("1.5-0.1i", 10, angles=[0, 140, 180])
    cli = run_cli("mie", "--m", "1.5-0.1i", "--x", "10", "--angles", "0,140,180", "--json")
    for key in ("qext", "qsca", "qabs", "qback", "g", "terms"):
        close(py[key], cli[key])
    assert np.allclose(py.s1.real, [s[0] for s in cli["s1"]], rtol=1e-6, atol=1e-12)
    assert np.allclose(py.s2.imag, [s[1] for s in cli["s2"]], rtol=1e-6, atol=1e-12)
    assert vpsim.mie(complex(1.5, -0.1), 10).qext == pytest.approx(cli["qext"], rel=1e-12)


def test_material(run_cli):
    py = vpsim.material(MATERIAL, cdf_angles=[10, 90])
    cli = run_cli("mie", "--material", MATERIAL, "--cdf-angles", "10,90", "--json")
    for key, value in cli.items():
        if key in ("m", "material"):
            continue
        close(py[key], value)
    assert py.phase_cdf[0] == 0 and py.phase_cdf[-1] == pytest.approx(1)
    assert py.phase_inverse_cdf.dtype == np.float32
    with open(MATERIAL) as f:  # a dict gives the same optics
        assert vpsim.material(json.load(f)).mus_per_mm == pytest.approx(py.mus_per_mm)


def test_mc(run_cli):
    py = vpsim.mc(SLAB, photons=20000, seed=3, thickness="0.2 mm", depths=["30 um"])
    cli = run_cli("mc", "--material", SLAB, "--photons", "20000", "--seed", "3",
                  "--thickness", "0.2mm", "--depths", "30um", "--json")
    for key, value in cli.items():
        if key in ("material", "photons_per_second", "seconds", "backend"):
            continue
        close(py[key], value)
    assert py.absorbed_rz.shape == (100, 100)


def test_kernel(run_cli, tmp_path):
    py = vpsim.kernel(MATERIAL, photons=20000, seed=2, bins=40)
    cli = run_cli("kernel", "--material", MATERIAL, "--photons", "20000", "--seed", "2",
                  "--bins", "40", "--out", str(tmp_path / "k"), "--json")
    assert cli["from_cache"]  # the module's run filled the shared cache
    for key in ("We3D_um", "De3D_um", "zmax_um", "amplitude_mW_per_mm2", "residual",
                "fit_energy_fraction", "W0_um"):
        close(py[key], cli[key])
    table = json.loads((tmp_path / "k" / "kernel.json").read_text())
    assert py.intensity.shape == (40, 40)
    # array[ir, iz] is the table's bin (ir, iz), stored z-major in kernel.json
    stored = np.asarray(table["intensity_mW_per_mm2"], dtype=np.float32)  # [iz][ir]
    assert np.array_equal(py.intensity, stored.T)
    assert py.r[0] == pytest.approx(0.5 * py.r_bin_mm)


def test_slice(run_cli):
    stl = os.path.join(SOURCE, "examples", "parts", "holes.stl")
    py = vpsim.slice(stl, "100 um", pitch="20 um")
    cli = run_cli("slice", stl, "--layer", "100um", "--json")
    assert py.layer_count == cli["layer_count"]
    for a, b in zip(py.layers, cli["layers"]):
        for key, value in b.items():
            close(a[key], value)
        assert a.mask.dtype == np.uint8 and a.mask.shape == a.coverage.shape
    layer = py.layers[len(py.layers) // 2]
    assert all(c.ndim == 2 and c.shape[1] == 2 for c in layer.contours)
    assert len(layer.parts) == layer.outer_contours
    # the same part as arrays
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                     [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
    faces = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                      [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    box = vpsim.slice((cube, faces), 0.25)
    assert box.layer_count == 4
    assert box.layers[0].area == pytest.approx(1.0)


def test_plan_and_export(run_cli, tmp_path):
    job = write_job(tmp_path, small_job())
    plan = vpsim.plan(job)
    cli = run_cli("plan", job, "--out", str(tmp_path / "p"), "--json")
    assert len(plan) == cli["layers"]
    assert plan.energy == pytest.approx(cli["energy_mJ"], rel=1e-6)
    saved = json.loads((tmp_path / "p" / "plan.json").read_text())
    close(plan.to_json(), saved)
    layer = plan.layer(0)
    assert layer["vectors"].shape[1] == 6 and layer["vectors"].shape[0] > 0
    summary = vpsim.export(plan, str(tmp_path / "scan.cli"))
    assert summary.exporter == "cli" and os.path.getsize(tmp_path / "scan.cli") > 0


def test_run_matches_cli(run_cli, tmp_path):
    job = write_job(tmp_path, small_job())
    result = vpsim.run(job, out=str(tmp_path / "py"))
    cli = run_cli("run", job, "--out", str(tmp_path / "cli"), "--json")
    report = json.loads((tmp_path / "py" / "report.json").read_text())
    assert result.to_dict() == report
    for key in ("iou", "overcure_below_downfacing_mm", "cured_volume_mm3", "validation"):
        close(result.to_dict()[key], cli[key])
    assert result.validation.iou == result.iou
    assert vpsim.run(small_job(), dry_run=True).to_dict()  # a dict job, estimate only


def test_expose_axis_order_against_vdb(tmp_path):
    job = small_job()
    result = vpsim.run(job, out=str(tmp_path / "run"))
    exposure = vpsim.expose(job)
    a = exposure.array
    assert a.dtype == np.float32 and a.flags.c_contiguous and a.shape == exposure.shape
    assert exposure.shape == tuple(result.exposure.grid)
    vdb = vpsim.read_vdb(tmp_path / "run" / "exposure.vdb", shape=a.shape)
    v = vdb.array
    stored = np.where(a > exposure.vdb_threshold, a, 0)  # what the .vdb keeps
    assert float(v.max()) == float(a.max())
    assert float(v.astype(np.float64).sum()) == pytest.approx(
        float(stored.astype(np.float64).sum()), rel=1e-6)
    peak = np.unravel_index(np.argmax(a), a.shape)
    for index in [peak, (a.shape[0] // 3, a.shape[1] // 2, a.shape[2] - 1),
                  (a.shape[0] // 2, a.shape[1] // 3, 0)]:
        assert v[index] == stored[index]
    assert vdb.voxel_size == pytest.approx(exposure.voxel_size)
    assert a.max() * 100 == pytest.approx(result.exposure.max_mJ_per_cm2, rel=1e-6)

    # cure and validate from the array give the run's figures
    cured = vpsim.cure(job["cure"], exposure)
    assert cured.cured.shape == a.shape and cured.cured.dtype == np.uint8
    assert int(cured.cured.sum()) == int((a >= exposure.critical_dose).sum())
    figures = vpsim.validate(job, exposure)
    close(figures.to_dict(), result.validation.to_dict())

    # the same exposure slice by slice
    streamed = vpsim.expose(job, max_bytes=1)
    assert streamed.array is None
    total, count = 0.0, 0
    for item in streamed.slices:
        assert item["values"].shape == a.shape[:2]
        assert np.array_equal(item["values"], a[:, :, item["index"]])
        total += float(item["values"].sum(dtype=np.float64))
        count += 1
    assert count == a.shape[2]
    assert total == pytest.approx(float(a.sum(dtype=np.float64)), rel=1e-6)


def test_plan_round_trip_and_progress(tmp_path):
    job = small_job()
    calls = []
    plan = vpsim.plan(job, progress=lambda label, done, total: calls.append((label, done)))
    exposure = vpsim.expose(job, plan=plan)
    assert exposure.plan.energy == pytest.approx(plan.energy)
    plan.save(str(tmp_path / "plan.json"))
    assert vpsim.load_plan(tmp_path / "plan.json").energy == pytest.approx(plan.energy)

    def fail(label, done, total):
        raise KeyError("stop")
    with pytest.raises(KeyError):
        vpsim.slice(os.path.join(SOURCE, "examples", "parts", "holes.stl"), "50 um",
                    progress=fail)


def test_calibrate(run_cli, tmp_path):
    doses = np.array([0.1, 0.2, 0.4, 0.8, 1.6])  # mJ/mm^2
    depths = 0.1 * np.log(doses / 0.05) + np.array([0.001, -0.001, 0.0005, 0.0, -0.0005])
    csv = tmp_path / "wc.csv"
    csv.write_text("dose_mJ_per_cm2,thickness_mm\n" +
                   "".join(f"{e * 100!r},{d!r}\n" for e, d in zip(doses, depths)))
    cli = run_cli("calibrate", "--working-curve", str(csv), "--gel-point", "0.276", "--json")
    py = vpsim.calibrate(doses, depths, gel_point=0.276)
    for key in ("penetration_depth_mm", "critical_dose_mJ_per_cm2", "K_cm2_per_mJ",
                "r_squared", "cure_model"):
        close(py.to_dict()[key], cli[key])


def test_errors(tmp_path):
    job = small_job(machine={"process": "laser", "laser_power": "10 mW",
                             "beam_radius": "2 mW", "layer_thickness": "50 um"})
    with pytest.raises(vpsim.InputError) as error:
        vpsim.plan(job)
    assert error.value.key == "machine.beam_radius"
    assert "machine.beam_radius" in str(error.value)
    assert isinstance(error.value, vpsim.Error)
    path = write_job(tmp_path, job)
    with pytest.raises(vpsim.InputError) as error:
        vpsim.run(path)
    assert error.value.file == path and error.value.key == "machine.beam_radius"
    with pytest.raises(vpsim.InputError) as error:
        vpsim.mc(SLAB, photons=10, w0="5 mW")
    assert error.value.key == "w0"
    # the kernel's arguments are checked as `vpsim kernel` checks its options
    for arguments, key in [({"thickness": "-1 mm"}, "thickness"), ({"photons": "1.5"}, "photons"),
                           ({"power": 0}, "power"), ({"bins": 2}, "bins")]:
        with pytest.raises(vpsim.InputError) as error:
            vpsim.kernel(MATERIAL, **arguments)
        assert error.value.key == key
    with pytest.raises(vpsim.InputError):
        vpsim.run(small_job(plan={"strategy": "no-such-planner"}))
    with pytest.raises(vpsim.InputError):
        vpsim.read_vdb(tmp_path / "missing.vdb")
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                     [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
    faces = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                      [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    with pytest.raises(vpsim.ResourceError):  # 5 million layers of a 1 mm cube
        vpsim.slice((cube, faces), "0.2 nm")
    assert issubclass(vpsim.GpuError, vpsim.Error)
