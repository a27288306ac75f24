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


def small_dlp_job(**changes):
    """A DLP job of a few seconds: 1 mm L-shape, 4 layers of uniform masks."""
    job = {
        "name": "py-small-dlp",
        "cure": {"model": "fpp", "K": "0.0052808 cm^2/mJ", "gel_point": 0.276,
                 "penetration_depth": "0.36594 mm"},
        "part": {"test_part": "l-shape", "size": "1 mm", "height": "0.2 mm"},
        "machine": {"process": "dlp", "pixel_pitch": "62.5 um", "blur_radius": "40 um",
                    "layer_thickness": "50 um"},
        "plan": {"strategy": "uniform-mask", "dose": "78 mJ/cm^2"},
        "simulation": {"voxel": "31.25 um", "slices_per_layer": 2, "write_vdb": False},
    }
    job.update(changes)
    return job


def step_mesh():
    """A closed two-step block (an L in x-z), coordinates exact in float32 so that an STL file
    holds them unchanged: (vertices (N, 3) mm, triangles (M, 3))."""
    import numpy as np
    # profile in x-z, extruded along y from 0 to 0.75 mm
    profile = [(0, 0), (1, 0), (1, 0.125), (0.5, 0.125), (0.5, 0.25), (0, 0.25)]
    n = len(profile)
    vertices = [(x, 0.0, z) for x, z in profile] + [(x, 0.75, z) for x, z in profile]
    triangles = []
    for i in range(n):  # side walls, outward
        j = (i + 1) % n
        triangles += [(i, n + j, j), (i, n + i, n + j)]
    # the caps: the profile split into two convex quadrilaterals; y = 0 faces -y
    for a, b, c, d in [(0, 1, 2, 3), (0, 3, 4, 5)]:
        triangles += [(a, b, c), (a, c, d), (n + a, n + c, n + b), (n + a, n + d, n + c)]
    return np.array(vertices, dtype=float), np.array(triangles)


def write_stl(path, vertices, triangles):
    """A binary STL of the mesh (float32, as vpsim writes them)."""
    import struct
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(triangles)))
        for t in triangles:
            f.write(struct.pack("<3f", 0, 0, 0))
            for k in t:
                f.write(struct.pack("<3f", *vertices[k]))
            f.write(b"\0\0")
    return str(path)
