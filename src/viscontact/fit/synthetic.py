"""Synthetic force-plate recordings at known parameters, and the shipped example.

A synthetic recording is a law's exact collision (default solver tolerance) sampled like a
force plate: a sampling rate, Gaussian noise given as a fraction of F_max, a baseline offset,
and samples before and after the contact, with the contact starting at a random point
between two samples.  Tests fit these and compare with the truth.

``python3 scripts/make_example_recording.py`` rewrites the example recording that ships with the
package (:func:`example_recording`): the Jian law at the indoor lacrosse ball's parameters
(Jian et al. 2019, the indoor lacrosse ball: m* = 154.7 g, k_Hertz = 1.688e6 N/m^1.5, a 15 cm drop, e = 0.463 with
beta = 0.5), 50 kHz, 1 % noise, a 3.2 N offset, 1 ms before and after the contact.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from ..calibration.inverse import alpha_from_e
from ..collision.impact import ImpactResult, impact
from ..physics.pair import damping_coefficient, drop_speed, time_scale
from ..paper.experiment import ball
from .model import Trace
from ..physics.laws import Jian

__all__ = ["SyntheticRecording", "synthetic_recording", "write_recording", "example_recording",
           "EXAMPLE_FILE", "EXAMPLE"]

EXAMPLE_FILE = "example_drop.csv"


@dataclass
class SyntheticRecording:
    """Samples t [s], force [N] (offset and noise included) and the true impact behind them.

    ``t0`` [s] is the true contact start; ``truth`` the exact collision (SI).
    """

    t: np.ndarray = field(repr=False)
    force: np.ndarray = field(repr=False)
    t0: float
    truth: ImpactResult


def synthetic_recording(
    model: str, alpha: float, *, m_eff: float, k_hertz: float, v: float,
    beta: float | None = None, p: float | None = None, rate: float = 50e3, noise: float = 0.01,
    offset: float = 0.0, pre: float = 1e-3, post: float = 1e-3, seed: int = 0,
) -> SyntheticRecording:
    """A force-plate recording of one impact of ``model`` at known parameters.

    ``rate`` [Hz]; ``noise``: standard deviation as a fraction of the true F_max; ``offset``
    [N] added to every sample; ``pre``/``post`` [s] of baseline before/after the contact.
    """
    c = damping_coefficient(model, alpha, m_eff=m_eff, k_hertz=k_hertz, v=v, p=p)
    tau = None if beta is None else beta * time_scale(m_eff, k_hertz, v)
    truth = impact(model, m_eff=m_eff, k_hertz=k_hertz, v=v, c=c, tau=tau, p=p)
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    t0 = pre + rng.uniform(0.0, dt)  # the contact starts between two samples
    t = np.arange(0.0, t0 + truth.tc + post, dt)
    force = Trace(truth).sample(t, t0)[0]
    force = force + offset + noise * truth.fmax * rng.standard_normal(t.size)
    return SyntheticRecording(t=t, force=force, t0=t0, truth=truth)


def write_recording(path: str | Path, rec: SyntheticRecording, comments: list[str]) -> Path:
    """Write ``rec`` as CSV: ``#`` comment lines, a ``time [ms],force [N]`` header, the samples."""
    path = Path(path)
    lines = [f"# {c}" for c in comments] + ["time [ms],force [N]"]
    lines += [f"{t * 1e3:.4f},{f:.3f}" for t, f in zip(rec.t, rec.force)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def example_recording() -> Path:
    """Path of the example recording that ships with the package (see module docstring)."""
    return Path(str(resources.files("viscontact").joinpath("data", EXAMPLE_FILE)))


#: how the example was made: law, ball, drop height [m], rate [Hz], noise, offset [N], seed
EXAMPLE = dict(model=Jian.name, ball="ILB", drop_height=0.15, rate=50e3, noise=0.01, offset=3.2,
               seed=2019)


def _make_example(path: Path) -> Path:
    b = ball(EXAMPLE["ball"])
    v = drop_speed(EXAMPLE["drop_height"])
    alpha = float(alpha_from_e(EXAMPLE["model"], b.e, beta=b.beta))
    rec = synthetic_recording(EXAMPLE["model"], alpha, m_eff=b.mass, k_hertz=b.k_hertz, v=v,
                              beta=b.beta, rate=EXAMPLE["rate"], noise=EXAMPLE["noise"],
                              offset=EXAMPLE["offset"], seed=EXAMPLE["seed"])
    tr = rec.truth
    comments = [
        "SYNTHETIC force-plate recording (not a measurement), made by "
        "`python3 scripts/make_example_recording.py`.",
        f"law {EXAMPLE['model']} at the {b.name} parameters of Jian et al. (2019): "
        f"m = {b.mass:g} kg, R = {b.radius:g} m, k_Hertz = {b.k_hertz:g} N/m^1.5,",
        f"drop height {EXAMPLE['drop_height']:g} m (v_i = {v:.4f} m/s), alpha = {alpha:.6f}, "
        f"beta = {b.beta:g} (tau = {tr.tau * 1e3:.5f} ms, c = {tr.c:.6g} N s/m^1.5).",
        f"sampled at {EXAMPLE['rate'] / 1e3:g} kHz; Gaussian noise {EXAMPLE['noise']:.0%} of "
        f"F_max; baseline offset {EXAMPLE['offset']:g} N; seed {EXAMPLE['seed']}.",
        f"truth: e = {tr.e:.4f}, t_c = {tr.tc * 1e3:.4f} ms, F_max = {tr.fmax:.2f} N, "
        f"delta_max = {tr.dmax * 1e3:.4f} mm, contact starts at t = {rec.t0 * 1e3:.4f} ms.",
        f"units: time in ms, force in N. Fit it with: viscontact fit --example --mass {b.mass:g} "
        f"--radius {b.radius:g} --drop-height {EXAMPLE['drop_height']:g}",
    ]
    return write_recording(path, rec, comments)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Rewrite the example recording.")
    parser.add_argument("--out", default=None, help="file (default: the packaged example)")
    args = parser.parse_args(argv)
    out = _make_example(Path(args.out) if args.out else example_recording())
    print(f"wrote {out}")


