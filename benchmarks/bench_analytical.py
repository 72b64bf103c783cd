"""Analytical-package benchmark: the issue's speed targets, measured side by side.

    .venv/bin/python benchmarks/bench_analytical.py   (or: make bench)

Measures, on this machine:
  * one MDOF response (160 elements, 50 ms record, modal solution, model cached),
    against the direct Newmark loop with the study's settings (160 elements, dt = 1e-6 s):
    speed-up and the difference in peak base shear;
  * one column pulse as the one-way transport resolves it (contact integration and base shear),
    against the same impact with steps phased to the column's modes up to 4 kHz and Newmark
    for the base shear;
  * one MDOF fit and one SDOF fit of a noisy 60 ms record;
  * the whole 22-record synthetic study (one variant) on 2 cores.
Writes benchmarks/analytical.md (the table the README quotes).
"""

from __future__ import annotations

import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from analytical.column import Column  # noqa: E402
from analytical.fitting import fit_mdof, fit_sdof  # noqa: E402
from analytical.mdof import column_model, mdof_response  # noqa: E402
from analytical.asce7 import STUDY_DEBRIS_MASS_KG  # noqa: E402
from analytical.contact_law import (  # noqa: E402
    CONTAINER,
    STUDY_CONTAINER_SIZE_M,
    STUDY_CONTAINER_WALL_M,
    box_inertia,
    column_impact,
)
from analytical.impact import Body, ColumnTarget, impact, inverse_inertia_tensor  # noqa: E402
from analytical.newmark import phase_limited_step  # noqa: E402
from analytical.pulses import HalfSine  # noqa: E402


def best_of(fn, repeat=5):
    times = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> None:
    column = Column()
    column_model(column)  # build and cache the matrices and modes (reported separately)
    t_build0 = time.perf_counter()
    column_model.cache_clear() if hasattr(column_model, "cache_clear") else None
    column_model(column)
    build_s = time.perf_counter() - t_build0
    pulse = HalfSine(236.93, 0.0047, 0.0)  # the study's Table 1 MDOF pulse
    t = np.arange(0.0, 0.05 + 1e-12, 1e-5)
    modal_s, modal = best_of(lambda: mdof_response(pulse, column, 0.40, t))
    newmark_s, newmark = best_of(lambda: mdof_response(pulse, column, 0.40, t, method="newmark", dt=1e-6), repeat=1)
    diff = abs(modal.peak_N - newmark.peak_N) / newmark.peak_N

    # One column pulse as the transport resolves it (the container law, 1.4 m/s at 0.088 m), against
    # the same impact with steps phased to the column's modes up to 4 kHz and the base shear of
    # its longer pulse by Newmark (the pipeline before the modal recurrence), side by side.
    impact_s, strike = best_of(lambda: column_impact(CONTAINER, 1.4, 0.088))

    def fine_pipeline():
        inertia = box_inertia(STUDY_CONTAINER_SIZE_M, STUDY_DEBRIS_MASS_KG, STUDY_CONTAINER_WALL_M)
        body = Body(STUDY_DEBRIS_MASS_KG, inverse_inertia_tensor(inertia, np.eye(3)), (-0.075, 0.0, 0.088),
                    (1.4, 0.0, 0.0))
        r = impact(body, (0.0, 0.0, 0.088), (-1.0, 0.0, 0.0), ColumnTarget(column, 0.088),
                   dt_s=phase_limited_step(column_model(column)), **CONTAINER.options())
        shear = mdof_response(r.force, column, 0.088, r.base_shear.time_s, method="newmark")
        return r, shear

    fine_s, (fine, fine_shear) = best_of(fine_pipeline, repeat=2)
    impact_diff = max(abs(strike.peak_force_N / fine.peak_force_N - 1.0),
                      abs(strike.base_shear.peak_N / fine_shear.peak_N - 1.0))

    rng = np.random.default_rng(0)
    tr = np.arange(0.0, 0.06, 1e-4)
    truth = HalfSine(171.0, 0.0047, 0.012)
    record = mdof_response(truth, column, 0.40, tr).response_N
    record = record + 3.0 + rng.normal(0, 0.025 * record.max(), tr.size)
    fit_m_s, fit_m = best_of(lambda: fit_mdof(tr, record, column=column, height_m=0.40), repeat=3)
    fit_s_s, _ = best_of(lambda: fit_sdof(tr, record, column=column), repeat=3)

    from orchestrator.studies.synthetic import run_variant

    _, study_s = run_variant("rigid", n_records=22, seed=2019, workers=2)

    rows = [
        ("MDOF column model build (160 elements, matrices + eigenpairs, once per column)", f"{1e3 * build_s:.1f} ms", "-"),
        ("one MDOF response, modal (160 el., 50 ms record)", f"{1e3 * modal_s:.2f} ms", "< 20 ms"),
        ("one MDOF response, direct Newmark, dt = 1e-6 s (the study's settings)", f"{newmark_s:.2f} s", "baseline"),
        ("speed-up modal / Newmark", f"{newmark_s / modal_s:.0f}x", "-"),
        ("peak base shear: modal vs Newmark dt = 1e-6 s", f"{modal.peak_N:.4f} N vs {newmark.peak_N:.4f} N (relative {diff:.1e})", "< 0.1 %"),
        ("one column pulse (container law, 1.4 m/s at 0.088 m): contact integration + base shear",
         f"{1e3 * impact_s:.1f} ms ({strike.force.time_s.size} samples)", "-"),
        ("the same pulse, steps phased to the column's modes to 4 kHz, base shear by Newmark",
         f"{1e3 * fine_s:.0f} ms ({fine.force.time_s.size} samples)", "baseline"),
        ("speed-up, column pulse", f"{fine_s / impact_s:.0f}x", "-"),
        ("column pulse: peak force and peak base shear against the baseline",
         f"{strike.peak_force_N:.2f} N, {strike.base_shear.peak_N:.2f} N (largest relative difference {impact_diff:.1e})",
         "< 1e-4"),
        ("one MDOF fit (60 ms noisy record)", f"{fit_m_s:.2f} s (magnitude {fit_m.magnitude_N:.1f} N, true 171.0)", "< 1 s"),
        ("one SDOF fit (same record)", f"{fit_s_s:.2f} s", "-"),
        ("22-record synthetic study, 2 cores", f"{study_s:.1f} s", "< 30 s"),
    ]
    lines = [
        "# Analytical benchmark",
        "",
        f"Machine: {platform.processor() or platform.machine()}, Python {platform.python_version()}; "
        "`make bench` regenerates this file.",
        "",
        "| what | measured | target |",
        "|---|---|---|",
        *[f"| {a} | {b} | {c} |" for a, b, c in rows],
        "",
    ]
    text = "\n".join(lines)
    print(text)
    (ROOT / "benchmarks" / "analytical.md").write_text(text)


if __name__ == "__main__":
    main()
