"""vpsim from Python: every stage of the exposure simulator with numpy arrays in and out.

Values take the job files' keys and units: numbers in mm, s, mW, mJ (dose mJ/mm^2), or strings
with units ("50 um", "10 mW", "78 mJ/cm^2"). Jobs and materials are paths or dicts. Functions
that run physics take ``backend`` ("auto", "vulkan", "cpu"; default $VPSIM_BACKEND, else auto),
``device`` ($VPSIM_DEVICE), ``cache_dir`` (the beam-kernel cache, as the CLI's: $VPSIM_CACHE_DIR,
else $XDG_CACHE_HOME/vpsim, else ~/.cache/vpsim) and ``progress``, a callable
``progress(label, done, total)`` called with the GIL held, from whichever thread advances (TBB
workers too). The GIL is released during the work.

Errors are ``vpsim.Error`` and its subclasses ``InputError`` (``.file``, ``.key``, ``.reason``),
``ResourceError`` and ``GpuError``.

numpy arrays go in where the CLI reads a file: a part as ``part=(vertices, triangles)`` instead
of the job's STL (plan, expose, run, validate, slice), a DLP mask stack ``masks[k, ix, iy]``
(Plan.set_masks, expose, run) instead of a plan.json, a working curve's dose and depth arrays
(calibrate, and its result as cure()'s law) instead of a CSV.

Arrays of the exposure are float32 in C order with axes (x, y, z): ``array[ix, iy, iz]`` is
``exposure.vdb``'s voxel (ix, iy, iz), whose cell starts at ``origin + (ix, iy, iz) *
voxel_size`` (mm; centre at + voxel_size / 2). 2D maps (masks, slices) are ``array[ix, iy]``.
"""

import atexit
import copy
import json
import os
import tempfile

from . import _vpsim
from ._vpsim import Error, GpuError, InputError, Plan, ResourceError, ExposureSlices

__version__ = _vpsim.__version__

__all__ = [
    "Error", "InputError", "ResourceError", "GpuError", "Record", "JobResult", "Plan",
    "Exposure", "ExposureSlices", "run", "mie", "material", "mc", "kernel", "slice", "plan",
    "load_plan", "expose", "cure", "validate", "calibrate", "components", "export", "read_vdb",
    "set_log_level", "DEFAULT_MAX_EXPOSURE_BYTES",
]

#: expose() returns the whole 3D array up to this many bytes, else a slice iterator (1 GiB).
DEFAULT_MAX_EXPOSURE_BYTES = 1 << 30

atexit.register(_vpsim._release_contexts)

if os.environ.get("VPSIM_LOG"):
    try:
        _vpsim._set_log_level(os.environ["VPSIM_LOG"])
    except Error:
        pass


def set_log_level(level):
    """vpsim's messages on stderr: "error", "warn", "info" (default) or "debug"."""
    _vpsim._set_log_level(level)


def _cache_dir():
    if os.environ.get("VPSIM_CACHE_DIR"):
        return os.environ["VPSIM_CACHE_DIR"]
    if os.environ.get("XDG_CACHE_HOME"):
        return os.path.join(os.environ["XDG_CACHE_HOME"], "vpsim")
    if os.environ.get("HOME"):
        return os.path.join(os.environ["HOME"], ".cache", "vpsim")
    return ""


def _settings(backend=None, device=None, cache_dir=None):
    """The CLI's defaults from the environment (the library itself reads none)."""
    return {
        "backend": backend or os.environ.get("VPSIM_BACKEND") or "auto",
        "device": device if device is not None else os.environ.get("VPSIM_DEVICE", ""),
        "cache_dir": cache_dir if cache_dir is not None else _cache_dir(),
        "validation": os.environ.get("VPSIM_VALIDATION", "0") not in ("", "0"),
    }


def _job(job):
    """(job, base_dir): a path as given; a dict with the working directory for its paths."""
    if isinstance(job, dict):
        return job, ""
    return os.fspath(job), ""


class Record:
    """Attribute access to a JSON document: ``r.validation.iou``; ``r["key"]`` for any key;
    ``to_dict()`` gives the document itself (a deep copy)."""

    def __init__(self, document):
        object.__setattr__(self, "_document", document)

    @staticmethod
    def _wrap(value):
        if isinstance(value, dict):
            return Record(value)
        if isinstance(value, list):
            return [Record._wrap(v) for v in value]
        return value

    def __getattr__(self, name):
        document = object.__getattribute__(self, "_document")
        if name in document:
            return Record._wrap(document[name])
        raise AttributeError(f"no field {name!r} (fields: {', '.join(sorted(document))})")

    def __getitem__(self, key):
        return Record._wrap(self._document[key])

    def __contains__(self, key):
        return key in self._document

    def __iter__(self):
        return iter(self._document)

    def keys(self):
        return self._document.keys()

    def __dir__(self):
        return sorted(set(super().__dir__()) | {k for k in self._document if k.isidentifier()})

    def to_dict(self):
        return copy.deepcopy(self._document)

    def __repr__(self):
        return f"{type(self).__name__}({self._document!r})"


class JobResult(Record):
    """report.json's document, field by field (``to_dict()`` equals report.json's content);
    ``out`` is the output directory (a temporary one lives as long as this object)."""

    def __init__(self, document, out, keep=None):
        super().__init__(document)
        object.__setattr__(self, "out", out)
        object.__setattr__(self, "_keep", keep)


def _with_masks(job, plan, masks, full_dose, part, overrides, settings, progress):
    """``plan`` (else the job's) with its DLP masks replaced by the stack ``masks``."""
    if masks is None:
        if full_dose is not None:
            raise InputError("full_dose goes with masks")
        return plan
    if plan is None:
        source, base = _job(job)
        plan = _vpsim._plan(source, base, list(overrides), part, _settings(**settings), progress)
    elif not isinstance(plan, Plan):
        plan = load_plan(plan)
    plan = plan.copy()
    plan.set_masks(masks, full_dose)
    return plan


def run(job, out=None, overrides=(), backend=None, progress=None, plan=None, dry_run=False,
        device=None, cache_dir=None, part=None, masks=None, full_dose=None):
    """The main job, as ``vpsim run JOB --out OUT``: returns report.json as a JobResult.

    ``job`` a path or a dict (relative paths in a dict from the working directory); ``out``
    None writes into a temporary directory removed with the result; ``overrides`` are
    "key.path=value" (the CLI's --set); ``plan`` a saved plan.json or a Plan (the CLI's
    --plan); ``part`` (vertices (N, 3) mm, triangles (M, 3)) instead of the job's part section;
    ``masks`` a DLP mask stack for the plan (Plan.set_masks, with ``full_dose``);
    ``dry_run`` returns the estimate (memory, files, time) and computes nothing."""
    settings = {"backend": backend, "device": device, "cache_dir": cache_dir}
    plan = _with_masks(job, plan, masks, full_dose, part, overrides, settings, progress)
    job, base = _job(job)
    keep = None
    if out is None and not dry_run:
        keep = tempfile.TemporaryDirectory(prefix="vpsim-")
        out = keep.name
    saved = None
    if isinstance(plan, Plan):  # through plan.json, as the CLI's --plan
        saved = tempfile.TemporaryDirectory(prefix="vpsim-plan-")
        plan.save(os.path.join(saved.name, "plan.json"))
        plan = os.path.join(saved.name, "plan.json")
    try:
        document = _vpsim._run(job, base, os.fspath(out) if out else "", list(overrides), part,
                               os.fspath(plan) if plan else "", dry_run,
                               _settings(backend, device, cache_dir), progress)
    finally:
        if saved:
            saved.cleanup()
    if dry_run:
        return Record(document)
    return JobResult(document, os.fspath(out), keep)


def mie(m, x, angles=None):
    """Lorenz-Mie of one sphere (``vpsim mie --m M --x X --angles ...``): qext, qsca, qabs,
    qback, g, terms, and for ``angles`` (degrees) s1, s2 as complex arrays. ``m`` = n - ik
    (complex, number or "1.5-0.1i"); ``x`` the size parameter."""
    import numpy as np
    out = _vpsim._mie(m, float(x), [float(a) for a in (angles if angles is not None else [])])
    for key in ("s1", "s2"):
        if key in out:
            out[key] = np.array([complex(re, im) for re, im in out[key]])
    if "angles_deg" in out:
        out["angles_deg"] = np.asarray(out["angles_deg"], dtype=float)
    out["m"] = complex(*out["m"])
    return Record(out)


class _MaterialFile:
    """A material given as a dict, written to a temporary file for the library (which reads
    and hashes material files for the kernel cache)."""

    def __init__(self, material):
        self.dir = None
        if isinstance(material, dict):
            self.dir = tempfile.TemporaryDirectory(prefix="vpsim-material-")
            self.path = os.path.join(self.dir.name, "material.json")
            with open(self.path, "w") as f:
                json.dump(material, f)
        else:
            self.path = os.fspath(material)

    def __enter__(self):
        return self.path

    def __exit__(self, *exc):
        if self.dir:
            self.dir.cleanup()


def material(material, overrides=(), angles=(), cdf_angles=()):
    """A material's optics (``vpsim mie --material FILE``): size parameter x, m, efficiencies,
    mean free paths (um), mus/mua (1/mm); for a slurry the phase-function table as arrays
    (phase_theta_edges_rad, phase_cdf, phase_inverse_cdf). ``material`` a path or a dict."""
    with _MaterialFile(material) as path:
        out = _vpsim._material(path, list(overrides), [float(a) for a in angles],
                               [float(a) for a in cdf_angles])
    if isinstance(out.get("m"), list):
        out["m"] = complex(*out["m"])
    return Record(out)


def mc(material, photons=100000, seed=1, thickness=None, beam="pencil", w0="50 um", depths=(),
       estimator=None, n_outside=1.0, r_max="0.5 mm", z_max="0.5 mm", bins=100, roulette=None,
       direct_beam=False, control_variates=True, overrides=(), backend=None, progress=None,
       device=None, cache_dir=None):
    """Photon Monte Carlo (``vpsim mc --json``'s figures: specular, diffuse, transmitted,
    absorbed with standard errors, absorbed_within for ``depths``), plus absorbed_rz, the
    absorbed fraction per (r, z) bin as array[ir, iz]."""
    arguments = {
        "photons": photons, "seed": int(seed), "thickness": thickness, "beam": beam,
        "w0": w0, "depths": list(depths), "estimator": estimator or "collision",
        "n_outside": float(n_outside), "r_max": r_max, "z_max": z_max, "bins": int(bins),
        "roulette": 0.001 if roulette is None else float(roulette),
        "direct_beam": bool(direct_beam), "control_variates": bool(control_variates),
        "overrides": list(overrides),
    }
    with _MaterialFile(material) as path:
        return Record(_vpsim._mc(path, arguments, _settings(backend, device, cache_dir),
                                 progress))


def kernel(material, power="10 mW", w0="50 um", photons=1000000, seed=1, thickness=None,
           n_outside=1.0, r_max=None, z_max=None, bins=80, estimator="track-length", out=None,
           overrides=(), backend=None, progress=None, device=None, cache_dir=None):
    """The beam kernel (``vpsim kernel --json``'s figures: We3D_um, De3D_um, zmax_um, ...,
    fitted_beam) with the table ``intensity`` (mW/mm^2) as array[ir, iz] on the bin centres
    ``r`` and ``z`` (mm), and the per-depth fits depth_amplitude, depth_radius. Uses the same
    kernel cache as the CLI; ``out`` also writes the CLI's files there."""
    arguments = {
        "power": power, "w0": w0, "photons": photons, "seed": int(seed),
        "thickness": thickness, "n_outside": float(n_outside), "r_max": r_max, "z_max": z_max,
        "bins": int(bins), "estimator": estimator,
        "out": os.fspath(out) if out is not None else None, "overrides": list(overrides),
    }
    with _MaterialFile(material) as path:
        return Record(_vpsim._kernel(path, arguments, _settings(backend, device, cache_dir),
                                     progress))


def slice(part, layer_thickness, pitch=None, plane=0.5, z_start=None, layers=None, scale=1.0,
          progress=None):
    """A part sliced into layers (``vpsim slice --json``'s figures per layer: index, z, area,
    perimeter, outer_contours, holes) with its contours as (n, 2) arrays (``contours``, and
    ``parts`` [{outer, holes}]); with ``pitch`` each layer's ``mask`` (uint8) and ``coverage``
    (float32) as array[ix, iy] on one grid (raster_origin, raster_pitch). ``part`` an STL path
    or (vertices (N, 3) mm, triangles (M, 3))."""
    arguments = {"pitch": pitch, "plane": float(plane), "z_start": z_start,
                 "layers": list(layers) if layers is not None else None, "scale": float(scale)}
    if not isinstance(part, (tuple, list)):
        part = os.fspath(part)
    return Record(_vpsim._slice(part, layer_thickness, arguments, progress))


def plan(job, overrides=(), backend=None, progress=None, device=None, cache_dir=None, part=None):
    """The job's scan plan (the stages up to the plan, as ``vpsim plan``; nothing written):
    a Plan with layers as arrays, to_json() in plan.json's format, save(path), set_mask(),
    set_masks(), copy(). ``part`` (vertices, triangles) replaces the job's part section."""
    job, base = _job(job)
    return _vpsim._plan(job, base, list(overrides), part, _settings(backend, device, cache_dir),
                        progress)


def load_plan(plan):
    """A saved plan (plan.json path or its dict) as a Plan."""
    return _vpsim._load_plan(plan if isinstance(plan, dict) else os.fspath(plan))


class Exposure:
    """The exposure of a job: ``array`` (float32, mJ/mm^2, C order, axes (x, y, z): array[ix,
    iy, iz] is exposure.vdb's voxel (ix, iy, iz)), or, beyond ``max_bytes``, ``slices``, an
    iterator over (x, y) slices from the top down; ``origin`` (mm, corner of voxel (0, 0, 0)),
    ``voxel_size`` (mm), ``grid``, ``critical_dose`` (mJ/mm^2), ``vdb_threshold`` (values at or
    below it are left out of ``vpsim run``'s .vdb), ``plan``, ``beam``, ``model``, ``backend``."""

    def __init__(self, document):
        self.array = document.pop("array", None)
        self.slices = document.pop("slices", None)
        self.plan = document.pop("plan")
        self.grid = document["grid"]
        self.origin = tuple(self.grid["origin"])
        self.voxel_size = tuple(self.grid["voxel_size"])
        self.critical_dose = document["critical_dose"]
        self.vdb_threshold = document["vdb_threshold"]
        self.beam = document["beam"]
        self.model = document["model"]
        self.backend = document["backend"]
        self.kept_energy_fraction = document["kept_energy_fraction"]
        self.engine_seconds = document.get("engine_seconds")

    @property
    def shape(self):
        return (self.grid["nx"], self.grid["ny"], self.grid["nz"])

    def centres(self):
        """The voxel centres (mm) along x, y and z as three 1D arrays."""
        import numpy as np
        return tuple(o + (np.arange(n) + 0.5) * v
                     for o, n, v in zip(self.origin, self.shape, self.voxel_size))

    def __repr__(self):
        kind = "array" if self.array is not None else "slices"
        return f"<vpsim.Exposure {self.model} {self.shape} ({kind})>"


def expose(job, plan=None, max_bytes=DEFAULT_MAX_EXPOSURE_BYTES, overrides=(), backend=None,
           progress=None, device=None, cache_dir=None, part=None, masks=None, full_dose=None):
    """The job's exposure (of ``plan``, a Plan or a saved plan's path, else of the job's
    planner) as an Exposure: the whole 3D array when it takes at most ``max_bytes``, else a
    slice iterator. ``part`` (vertices, triangles) replaces the job's part section; ``masks``
    a DLP mask stack replacing the plan's masks (Plan.set_masks, with ``full_dose``)."""
    settings = {"backend": backend, "device": device, "cache_dir": cache_dir}
    plan = _with_masks(job, plan, masks, full_dose, part, overrides, settings, progress)
    if plan is not None and not isinstance(plan, Plan):
        plan = load_plan(plan)
    job, base = _job(job)
    return Exposure(_vpsim._expose(job, base, list(overrides), part, plan, float(max_bytes),
                                   _settings(backend, device, cache_dir), progress))


def cure(law, exposure):
    """A cure law (a cure section dict, e.g. {"model": "threshold", "critical_dose":
    "10 mJ/cm^2"}, or calibrate()'s result: its cure_model) applied to an exposure (an Exposure
    or an array of mJ/mm^2): ``cured`` (uint8, same shape), ``conversion`` (float32, laws with
    conversion kinetics), ``critical_dose`` (mJ/mm^2)."""
    if isinstance(law, Record) and "cure_model" in law:
        law = law.to_dict()["cure_model"]
    dose = exposure.array if isinstance(exposure, Exposure) else exposure
    if dose is None:
        raise InputError("the exposure was streamed as slices: cure each slice's values")
    return Record(_vpsim._cure(law, dose))


def validate(job, exposure, overrides=(), progress=None, part=None):
    """The slice validation of an Exposure against the job's part (or ``part``, vertices and
    triangles), as report.json's "validation" (iou, overcure below down-facing surfaces, XY
    contour error per layer)."""
    if exposure.array is None:
        raise InputError("validate needs the exposure as an array (raise max_bytes)")
    job, base = _job(job)
    return Record(_vpsim._validate(job, base, list(overrides), part, exposure.array,
                                   exposure.grid, progress))


def calibrate(doses, depths, gel_point=None):
    """Working-curve calibration (``vpsim calibrate --working-curve CSV --json``'s figures):
    ``doses`` (mJ/mm^2) and cured ``depths`` (mm) as arrays; ``gel_point`` adds the FPP rate
    constant K. The result's ``cure_model`` is a cure section; cure() takes the result as law."""
    import numpy as np
    return Record(_vpsim._calibrate(np.asarray(doses, dtype=float),
                                    np.asarray(depths, dtype=float), gel_point))


def components():
    """Every registered planner, cure law and exporter with its key table (``vpsim components
    --json``): {"planners": [...], "cure_laws": [...], "exporters": [...]}."""
    return Record(_vpsim._components())


def export(plan, path, exporter=None, options=None):
    """Writes a Plan (or a saved plan's path) as a machine file through a registered exporter
    (``exporter`` by name, else by the file's extension), with its section ``options``."""
    if not isinstance(plan, Plan):
        plan = load_plan(plan)
    return Record(_vpsim._export(plan, os.fspath(path), exporter or "", options))


def read_vdb(path, grid=None, shape=None):
    """A float grid of a .vdb file (the first, or ``grid`` by name) as a dense float32 array,
    axes (x, y, z), covering the active voxels (``index_min`` gives the first index) or, with
    ``shape``, indices 0 .. shape - 1 (so it lines up with expose()'s array)."""
    return Record(_vpsim._read_vdb(os.fspath(path), grid or "", shape))
