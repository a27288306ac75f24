"""Fixtures of the vpsim Python tests: the CLI binary (env VPSIM_CLI) to compare with, a kernel
cache shared by the CLI and the module, and small jobs. ctest runs these with
PYTHONPATH=build/python and Debian's /usr/bin/python3."""
import json
import os
import subprocess

import pytest

SOURCE = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("VPSIM_CLI")
    if not path or not os.path.exists(path):
        pytest.fail("set VPSIM_CLI to the vpsim binary (ctest does)")
    return path


@pytest.fixture(scope="session", autouse=True)
def cache(tmp_path_factory):
    """One kernel cache for the CLI and the module, so both see the same kernels."""
    directory = str(tmp_path_factory.mktemp("kernel-cache"))
    os.environ["VPSIM_CACHE_DIR"] = directory
    os.environ.setdefault("VPSIM_LOG", "warn")
    return directory


@pytest.fixture(scope="session")
def run_cli(cli):
    def run(*args):
        done = subprocess.run([cli, *args], capture_output=True, text=True, check=False)
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout)
    return run


def small_job(**changes):
    """A laser job of a few seconds: 1 mm L-shape, 4 layers, a given (fitted) kernel."""
    job = {
        "name": "py-small",
        "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
        "part": {"test_part": "l-shape", "size": "1 mm", "height": "0.2 mm"},
        "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                    "layer_thickness": "50 um"},
        "kernel": {"source": "given", "We3D": "60 um", "De3D": "90 um"},
        "plan": {"strategy": "aces", "homogeneity": 0.01, "edge": "cure-at-contour"},
        "simulation": {"voxel": "20 um", "slices_per_layer": 2},
    }
    for key, value in changes.items():
        job[key] = value
    return job


def write_job(tmp_path, job, name="job.json"):
    path = tmp_path / name
    path.write_text(json.dumps(job))
    return str(path)


def close(a, b, rel=1e-6):
    """Figures equal within `rel` relative (absolute 1e-12 near zero), recursively."""
    if isinstance(a, dict):
        assert set(a) == set(b), (sorted(a), sorted(b))
        for key in a:
            close(a[key], b[key], rel)
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            close(x, y, rel)
    elif isinstance(a, float) or isinstance(b, float):
        assert a == pytest.approx(b, rel=rel, abs=1e-12)
    else:
        assert a == b
