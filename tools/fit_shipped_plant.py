"""How models/crs_arm/params.toml's drive, friction and rotor inertias were found: a joint
``crslab identify`` of the course's recording and the course's friction table, from several
starts.

    python tools/fit_shipped_plant.py [--starts 5] [--jobs 2]

Each start draws every fitted value uniformly within 20 % of ``--around`` (a plant file; default
crslab's arm), fits them all (drive, friction, static friction, rotor inertias) to
models/crs_arm/recordings/lab2_square_pid_real.csv (+- crslab.identify.fit.RECORDING_SIGMA_RAD per
sample) and lab3_friction_table_course.toml (+- its stated uncertainty) together, and the script
writes the fit that agrees best with both (the least reduced chi-square) to build/fitted_plant.toml
and prints, per value, where each fit ended and the largest of their own standard deviations and
of the spread between starts, doubled (95 %), as params.toml and models/crs_arm/README.md state
them. (Not the mean of the fits: how far a joint slides after a step hinges on whether it enters
the lab's integral window, so values between two good fits need not be good.) It takes a few
minutes on two cores.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools" / "benchmarks"))

from real_recording import REAL_RECORDING  # noqa: E402

from crslab.identify.fit import Source, TableSource, fit, names_to_fit  # noqa: E402
from crslab.identify.friction_table import load_table  # noqa: E402
from crslab.identify.recording import read_recording  # noqa: E402
from crslab.identify.runs import lab_offsets  # noqa: E402
from crslab.plant.plant_params import PlantParams  # noqa: E402
from crslab.resources import path as resource_path  # noqa: E402
from crslab.run.api import make_config  # noqa: E402

COURSE_TABLE = ROOT / "models" / "crs_arm" / "recordings" / "lab3_friction_table_course.toml"
NAMES = ("drive", "friction", "static", "inertia")


def experiments() -> tuple[Source, TableSource]:
    config = make_config(resource_path("csrc", "labs", "lab2_square_pid.c"), "hands_off", startup_delay=False)
    recording = Source(read_recording(REAL_RECORDING), config, lab_offsets(config))
    return recording, TableSource(load_table(COURSE_TABLE), str(COURSE_TABLE.relative_to(ROOT)))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=5)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--around", type=Path, help="plant file to start around (default: crslab's arm)")
    parser.add_argument("--max-iterations", type=int, default=60)
    args = parser.parse_args(argv)
    recording, table = experiments()
    base = PlantParams.load(args.around) if args.around else PlantParams.defaults()
    rng = np.random.default_rng(23)
    results = []
    names = names_to_fit(NAMES, {1, 2, 3})
    for k in range(args.starts):
        start = base.with_values({n: base.value(n) * rng.uniform(0.8, 1.2) for n in names})
        result = fit([recording], tables=[table], names=NAMES, start=start, jobs=args.jobs,
                     max_iterations=args.max_iterations)
        results.append(result)
        rms = " ".join(f"{v:.4f}" for v in result.rms_after[0])
        print(f"start {k + 1}: RMS {rms} rad, table RMS gap {result.tables[0].rms_gap():.1%}, "
              f"chi2 {result.chi2_reduced:.2f}, {result.message}", flush=True)
    best_k = int(np.argmin([r.chi2_reduced for r in results]))
    best = results[best_k]
    print(f"the best: start {best_k + 1}")
    print(f"{'value':18s} {'best':>10s} {'95 %':>8s}   (fit sd, spread sd)   every start")
    for i, f in enumerate(best.values):
        ends = np.array([r.values[i].value for r in results])
        own = max(r.values[i].sigma for r in results)
        spread = float(np.std(ends, ddof=1)) if len(ends) > 1 else 0.0
        print(f"{f.name:18s} {f.value:10.4g} {2 * max(own, spread):8.2g}   ({own:.2g}, {spread:.2g})   "
              + " ".join(f"{v:.4g}" for v in ends))
    out = ROOT / "build" / "fitted_plant.toml"
    out.parent.mkdir(exist_ok=True)
    out.write_text(best.plant.to_toml(f"tools/fit_shipped_plant.py: the best of {len(results)} starts"))
    print(f"wrote {out.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
