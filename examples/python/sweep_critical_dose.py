#!/usr/bin/python3
"""Sweep: volume IoU of a small laser part against the resin's critical dose.

The plan is made once for the nominal resin (10 mJ/cm^2) and exposed once; each point then
cures and validates the same exposure with another critical dose (as if the resin batch were
off), which takes a fraction of a second. Writes sweep.csv and, with matplotlib
(python3-matplotlib), sweep.png into --out. Run from the repository root:

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sweep_critical_dose.py --out out/sweep
"""
import argparse
import os
import time

import numpy as np

import vpsim

JOB = {
    "name": "sweep",
    "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
    "part": {"test_part": "l-shape", "size": "1 mm", "height": "0.2 mm"},
    "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                "layer_thickness": "50 um"},
    "kernel": {"source": "given", "We3D": "60 um", "De3D": "90 um"},
    "plan": {"strategy": "aces", "homogeneity": 0.01, "edge": "cure-at-contour"},
    "simulation": {"voxel": "20 um", "slices_per_layer": 2},
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out/sweep", help="output directory")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    start = time.time()
    exposure = vpsim.expose(JOB)  # the whole array: (x, y, z), mJ/mm^2
    doses = np.linspace(4, 20, 17)  # mJ/cm^2
    rows = []
    for dose in doses:
        figures = vpsim.validate(JOB, exposure, overrides=[f"cure.critical_dose={dose} mJ/cm^2"])
        rows.append((dose, figures.iou, figures.xy_contour_error_mm.mean * 1000,
                     figures.overcure_below_downfacing_mm.median * 1000))
    with open(os.path.join(args.out, "sweep.csv"), "w") as f:
        f.write("critical_dose_mJ_per_cm2,iou,xy_error_um,overcure_um\n")
        for row in rows:
            f.write(",".join(f"{v:.6g}" for v in row) + "\n")
    best = max(rows, key=lambda r: r[1])
    print(f"exposure {exposure.shape} on {exposure.backend}, max "
          f"{exposure.array.max() * 100:.1f} mJ/cm^2; {len(rows)} critical doses in "
          f"{time.time() - start:.1f} s")
    for dose, iou, xy, over in rows:
        print(f"  Ec {dose:5.1f} mJ/cm^2  IoU {iou:.4f}  XY error {xy:6.1f} um  "
              f"over-cure {over:6.1f} um")
    print(f"best IoU {best[1]:.4f} at Ec = {best[0]:.1f} mJ/cm^2 (planned for 10)")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed (python3-matplotlib): no sweep.png")
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r[0] for r in rows], [r[1] for r in rows], "o-")
    ax.axvline(10, color="grey", linestyle="--", label="planned for")
    ax.set_xlabel("resin critical dose (mJ/cm$^2$)")
    ax.set_ylabel("volume IoU")
    ax.set_title("L-shape, ACES plan for 10 mJ/cm$^2$")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "sweep.png"), dpi=120)
    print("wrote", os.path.join(args.out, "sweep.png"))


if __name__ == "__main__":
    main()
