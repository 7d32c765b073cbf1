"""What the API fuzz tests call and how a result is judged (issue 13).

Shared by ``tests/physics/test_domain_fuzz.py`` (hypothesis, in the suite) and
``scripts/fuzz_api.py`` (a bigger campaign with counts).  Each target is a public function with
a valid call; a fuzz case replaces one or two of its arguments by a value from :data:`VALUES`
(subnormal to 1e308, NaN, inf, wrong types, odd shapes) or a random float.  The rule: the call
either returns a valid result (:func:`check_result`: e in [0, 1], t_c > 0 or inf with
``separated=False``, no NaN, energy balance closing) or raises ``ValueError`` with a message;
never another exception, and promptly.
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
import wave
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import viscontact as vc
from viscontact import audit, fit

#: unusual values for any argument: magnitudes, specials, wrong types, odd shapes
VALUES: tuple[Any, ...] = (
    0, 0.0, -0.0, 5e-324, 1e-320, 1e-300, 1e-30, 1e-12, 1e-6, 1e-3, 0.3, 0.463, 1, 1.0, 2.0,
    10, 100.0, 999.0, 1000.0, 1000.0001, 1e4, 1e6, 1e30, 1e200, 1e308, 1.7976931348623157e308,
    -1, -1e-300, -0.3, -1e308, math.nan, math.inf, -math.inf, 10**400, -(10**400),
    True, False, None, "0.3", "", "nan", "KK", b"1", 1 + 2j, [0.3], [], [[0.3], [1.0]],
    [[0.3], [1.0, 2.0]], (0.3, 0.5), {"a": 1}, {0.3}, object(),
    np.float32(0.3), np.float64(1e-310), np.int64(3), np.bool_(True), np.array(0.3),
    np.array([0.3, 0.7]), np.array([[0.3, 0.5], [0.1, 0.9]]), np.array([]),
    np.zeros((0, 3)), np.array(["a"]), np.array([1 + 1j]), np.array([0.3, np.nan]),
    np.array([0.3], dtype=object), np.ones((2, 1, 2)) * 0.4,
)

_EXAMPLE = None
_MEASURED = None
_FITS: dict[str, Any] = {}


def example_recording() -> fit.Recording:
    global _EXAMPLE
    if _EXAMPLE is None:
        _EXAMPLE = fit.read_recording(fit.example_recording())
    return _EXAMPLE


def example_measured() -> fit.Measured:
    global _MEASURED
    if _MEASURED is None:
        _MEASURED = fit.measure(example_recording(), mass=0.1547, v=1.716)
    return _MEASURED


def example_fit(law: str = "KK") -> fit.LawFit:
    if law not in _FITS:
        _FITS[law] = fit.fit_law(example_measured(), law)
    return _FITS[law]


_PHYS = dict(m_eff=0.1547, k_hertz=1.688e6, v=1.716)

# small synthetic e(v) data: KK at alpha_ref 0.3 (vref 1 m/s), a ball dropped from ~0.1 m
_V = np.array([0.5, 1.0, 1.5, 2.0])
_E = fit.model_e("KK", _V, 1.0, 0.3)
_E_SETS = np.stack([_E, _E * 0.99, np.minimum(_E * 1.01, 1.0)])
# impact times of one drop: flights 2 u_k / g with u_k = 1.4 * 0.8^k m/s (no drag)
_TIMES = np.concatenate([[0.0], np.cumsum(2.0 * 1.4 * 0.8 ** np.arange(5) / 9.80665)])
_RATE = 8000.0
_FILES: dict[str, str] = {}


def _audio() -> np.ndarray:
    """Clicks (decaying 2 kHz bursts) at the first four impact times, in quiet noise."""
    n = int((_TIMES[3] + 0.05) * _RATE)
    x = 1e-3 * np.random.default_rng(0).standard_normal(n)
    t = np.arange(n) / _RATE
    for t0 in _TIMES[:4]:
        s = t - t0 - 0.01
        x += np.where(s >= 0, 0.5 * np.sin(2 * np.pi * 2000 * s) * np.exp(-s / 2e-3), 0.0)
    return x


def data_file(kind: str) -> str:
    """A small file of ``kind`` (restitution, bounces, drops, wav), written once to a temp dir."""
    if not _FILES:
        d = Path(tempfile.mkdtemp(prefix="viscontact-fuzz-"))
        (d / "e.csv").write_text("v [m/s], e\n" + "".join(f"{v}, {e}\n" for v, e in zip(_V, _E)))
        (d / "bounces.txt").write_text("".join(f"{t:.6f}\n" for t in _TIMES))
        gaps = np.diff(_TIMES)
        (d / "drops.csv").write_text("drop,interval [s]\n" + "".join(
            f"{k},{g:.6f}\n" for k in (1, 2) for g in gaps))
        with wave.open(str(d / "drop.wav"), "wb") as w:
            w.setnchannels(1)
            w.setsampwidth(2)
            w.setframerate(int(_RATE))
            w.writeframes((np.clip(_audio(), -1, 1) * 32767).astype("<i2").tobytes())
        _FILES.update(restitution=str(d / "e.csv"), bounces=str(d / "bounces.txt"),
                      drops=str(d / "drops.csv"), wav=str(d / "drop.wav"))
    return _FILES[kind]


@dataclasses.dataclass(frozen=True)
class Target:
    """A public function, its valid positional and keyword arguments, and which ones to fuzz."""

    name: str
    func: Callable[..., Any]
    args: tuple[Any, ...] = ()
    kwargs: dict[str, Any] = dataclasses.field(default_factory=dict)
    # heavy targets (fits) are fuzzed only in arguments that are rejected before any work
    fuzz_kwargs: tuple[str, ...] | None = None
    # what a bare number or array result is: "e" (in [0, 1]) or "alpha" (in [0, 1000])
    returns: str | None = None
    heavy: bool = False  # a valid call runs least-squares fits (seconds)

    def slots(self) -> list[int | str]:
        """Positions and keyword names that a case may replace."""
        keys = list(self.kwargs) if self.fuzz_kwargs is None else list(self.fuzz_kwargs)
        return [*range(len(self.args)), *keys]

    def rtol(self, replace: dict[int | str, Any]) -> float | None:
        """The integrator tolerance of this call, if it gives one."""
        r = replace.get("rtol", self.kwargs.get("rtol"))
        return float(r) if isinstance(r, (int, float)) and not isinstance(r, bool) else None

    def call(self, replace: dict[int | str, Any]) -> Any:
        args = [replace.get(i, a) for i, a in enumerate(self.args)]
        kwargs = dict(self.kwargs)
        for k, v in replace.items():
            if isinstance(k, str):
                kwargs[k] = v
        return self.func(*args, **kwargs)


def _targets() -> list[Target]:
    t = [
        Target("collide", vc.collide, ("KK", 0.3), {"end": "force", "history": True}),
        Target("collide Jian", vc.collide, ("Jian", 0.3), {"beta": 0.5, "end": "overlap",
                                                           "history": False}),
        Target("collide power", vc.collide, ("power", 0.3), {"p": 0.75, "rtol": 1e-10}),
        Target("restitution", vc.restitution, ("LH", [0.1, 0.3]), {"end": "force",
                                                                  "exact": False},
               returns="e"),
        Target("restitution Jian", vc.restitution, ("Jian", 0.3), {"beta": [0.1, 0.5],
                                                                  "end": "overlap"},
               returns="e"),
        Target("restitution power", vc.restitution, ("power", 0.3), {"p": 0.6, "exact": True},
               returns="e"),
        Target("alpha_from_e", vc.alpha_from_e, ("Hunt", 0.463), {"end": "force"},
               returns="alpha"),
        Target("alpha_from_e Jian", vc.alpha_from_e, ("Jian", [0.3, 0.8]),
               {"beta": 0.1, "end": "overlap", "exact": False}, returns="alpha"),
        Target("alpha_from_e power", vc.alpha_from_e, ("power", 0.5), {"p": 1.2},
               returns="alpha"),
        Target("time_scale", vc.time_scale, (0.1547, 1.688e6, 1.716)),
        Target("effective_mass", vc.effective_mass, (0.1, 0.2)),
        Target("effective_radius", vc.effective_radius, (0.01, 0.02)),
        Target("effective_modulus", vc.effective_modulus, (7e10, 0.3, 2e11, 0.25)),
        Target("hertz_stiffness", vc.hertz_stiffness, (1e7, 0.03)),
        Target("drop_speed", vc.drop_speed, (0.15,), {"g": 9.81}),
        Target("contact_pair", vc.contact_pair, (0.1,), {"radius": 0.01, "modulus": 1e7,
                                                         "poisson": 0.3, "mass2": 0.2}),
        Target("contact_pair k", vc.contact_pair, (0.1,), {"k_hertz": 1e6}),
        Target("damping_coefficient", vc.damping_coefficient, ("KK", 0.3), dict(_PHYS)),
        Target("damping_constants", vc.damping_constants, ("Jian", 2253.4),
               {**_PHYS, "tau": 6.87e-4}),
        Target("impact", vc.impact, ("Jian",), {**_PHYS, "c": 2253.4, "tau": 6.87e-4,
                                                "end": "force", "history": True}),
        Target("impact power", vc.impact, ("power",), {**_PHYS, "c": 1e4, "p": 0.8,
                                                       "history": False}),
        Target("calibrate_physical", vc.calibrate_physical, ("KK", 0.463),
               {**_PHYS, "end": "force"}),
        Target("calibrate_physical Jian", vc.calibrate_physical, ("Jian", 0.864),
               {**_PHYS, "beta": 2.0}),
        Target("calibrate_ball", vc.calibrate_ball, ("ILB", ("KK", "Hunt")), {"end": "force"}),
        Target("velocity_sweep", vc.velocity_sweep, ("KK", [0.5, 2.0]),
               {"m_eff": 0.1472, "k_hertz": 1.724e6, "c": 500.0, "end": "force"}),
        Target("velocity_sweep Jian", vc.velocity_sweep, ("Jian", [1.0]),
               {"m_eff": 0.1547, "k_hertz": 1.688e6, "c": 2253.4, "tau": 6.87e-4}),
        Target("read_recording", fit.read_recording, (str(fit.example_recording()),),
               {"time_unit": None, "force_unit": None}),
        Target("measure", fit.measure, (example_recording(),), {"mass": 0.1547, "v": 1.716,
                                                                "radius": 0.03175,
                                                                "margin": 0.3}),
        Target("fit_laws", fit.fit_laws, (example_measured(), ["KK"]),
               {"fit_k": True, "weights": fit.Weights()}, heavy=True),
        Target("fit_law", fit.fit_law, (example_measured(), "LH"),
               {"fit_k": False, "k_hertz": 1.7e6}, fuzz_kwargs=("fit_k", "k_hertz"),
               heavy=True),
        Target("fit_global", fit.fit_global, ([example_measured()], "KK"),
               {"fit_k": True, "sweep_points": 3}, fuzz_kwargs=("fit_k", "sweep_points"),
               heavy=True),
        Target("Weights", fit.Weights, (1.0, 0.5, 0.0)),
        *_restitution_targets(),
        Target("audit_formula", audit.audit_formula, ("flores", 0.5, "force")),
        Target("audit_engine", audit.audit_engine, ("lammps", "tsuji", 0.7),
               {"clamp": None, "value": 0.7}),
        Target("audit_engine physical", audit.audit_engine, ("lammps", "velocity", 0.7),
               {"physical": vc.ContactPair.from_effective(m_eff=0.1, r_eff=0.01, v=1.0,
                                                          e_eff=1e7),
                "value": 5.0}),
        Target("ContactPair.from_effective", vc.ContactPair.from_effective, (),
               {"m_eff": 0.1, "r_eff": 0.01, "v": 1.0, "e_eff": 1e7}),
        Target("get_formula", audit.get_formula, ("first-order",), {"model": "power", "p": 0.5}),
        Target("get_preset", audit.get_preset, ("lammps", "coeff_restitution")),
    ]
    return t


def _restitution_targets() -> list[Target]:
    """e(v) from a table, bounce timings and sound (viscontact.fit.restitution/bounces/audio)."""
    data = fit.restitution_data(_V, _E)
    return [
        Target("model_e", fit.model_e, ("KK", _V, 1.0, 0.3), {"end": "force"}, returns="e"),
        Target("model_e Jian", fit.model_e, ("Jian", 1.0, 1.0, 0.3), {"beta": 0.5},
               returns="e"),
        Target("model_e power", fit.model_e, ("power", _V, 1.0, 0.3), {"p": 0.8}, returns="e"),
        Target("restitution_data", fit.restitution_data, (_V, _E),
               {"sigma": np.full(4, 0.01), "tc": np.full(4, 1e-3), "source": "x"}),
        Target("read_restitution", fit.read_restitution, (data_file("restitution"),)),
        Target("fit_restitution", fit.fit_restitution, (data, ("KK",)),
               {"end": "force", "vref": 1.0, "mass": 0.1, "k_hertz": 1e6}, heavy=True),
        Target("fit_restitution_sets", fit.fit_restitution_sets, (_V, _E_SETS),
               {"law": "Jian", "sigma": np.full(4, 0.01), "vref": 1.0, "end": "force"},
               heavy=True),
        Target("read_bounces", fit.read_bounces, (data_file("bounces"),)),
        Target("read_drops", fit.read_drops, (data_file("drops"),)),
        Target("reduce_bounces", fit.reduce_bounces, ([_TIMES, _TIMES * 1.01],),
               {"k_drag": 0.01, "contact_time": 1e-4, "g": 9.81, "sources": ["a", "b"]}),
        Target("drag_constant", fit.drag_constant, (2.7e-3, 0.02),
               {"drag_coefficient": 0.47, "air_density": 1.2}),
        Target("flight_time", fit.flight_time, ([0.5, 1.0], 0.05), {"g": 9.81}),
        Target("landing_speed", fit.landing_speed, ([0.5, 1.0], 0.05), {"g": 9.81}),
        Target("launch_speed", fit.launch_speed, ([0.1, 0.2], 0.05), {"g": 9.81}),
        Target("read_audio", fit.read_audio, (data_file("wav"),)),
        Target("detect_impacts", fit.detect_impacts, (_audio(), _RATE),
               {"ratio": 4.0, "min_spacing": 0.01, "physics": True}),
    ]


TARGETS: list[Target] = []


def targets() -> list[Target]:
    """Every target (built on first use: the fit targets read and fit the example recording)."""
    if not TARGETS:
        TARGETS.extend(_targets())
        example_fit("KK")
    return TARGETS


# --------------------------------------------------------------------------- the judge
#: fields that are a restitution coefficient
_E_FIELDS = {"e", "delivered_e", "target_e"}


class Invalid(AssertionError):
    """A result outside its range: NaN, e outside [0, 1], a bad contact time."""


def _walk(value: Any, where: str, seen: set[int], energy_tol: float) -> None:
    if id(value) in seen:
        return
    if isinstance(value, (np.ndarray, float, np.floating)) and not isinstance(value, bool):
        arr = np.asarray(value)
        if arr.dtype.kind == "f":
            field = where.rsplit(".", 1)[-1]
            if np.isnan(arr).any():
                raise Invalid(f"NaN in {where}")
            if field in _E_FIELDS:
                if arr.size and not ((arr >= 0).all() and (arr <= 1).all()):
                    raise Invalid(f"{where} = {value!r} outside [0, 1]")
        return
    if isinstance(value, (Path, str, bytes, int, bool)) or value is None:
        return
    seen.add(id(value))
    if where.endswith((".rejected", ".points")):
        return  # the raw (v, e) of points left out (e >= 1, NaN: the reason says why)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        _check_contact(value, where, energy_tol)
        for f in dataclasses.fields(value):
            _walk(getattr(value, f.name), f"{where}.{f.name}", seen, energy_tol)
    elif isinstance(value, dict):
        for k, v in value.items():
            _walk(v, f"{where}[{k!r}]".replace("[", ".").replace("]", "").replace("'", ""),
                  seen, energy_tol)
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            _walk(v, f"{where}[{i}]", seen, energy_tol)


def _check_contact(r: Any, where: str, energy_tol: float) -> None:
    """t_c > 0 or inf with separated False; the energy balance of a non-dimensional result."""
    if hasattr(r, "separated") and hasattr(r, "tc") and hasattr(r, "e"):
        tc, e, sep = r.tc, r.e, bool(r.separated)
        if sep and not (math.isfinite(tc) and tc > 0 and 0 <= e <= 1):
            raise Invalid(f"{where}: separated with tc = {tc!r}, e = {e!r}")
        if not sep and not (math.isinf(tc) and e == 0):
            raise Invalid(f"{where}: not separated but tc = {tc!r}, e = {e!r}")
    if isinstance(r, vc.CollisionResult) and abs(r.energy_error) > energy_tol:
        raise Invalid(f"{where}: energy balance off by {r.energy_error:.3g}")


_RANGES = {"e": (0.0, 1.0), "alpha": (0.0, 1000.0)}


def check_result(result: Any, returns: str | None = None, rtol: float | None = None) -> None:
    """Raise :class:`Invalid` unless ``result`` is valid (see module docstring); ``returns``
    says what a bare number or array result is (:attr:`Target.returns`); ``rtol`` the
    integrator tolerance asked for (the energy balance closes to ~100 rtol, else to 1e-6)."""
    energy_tol = 1e-6 if rtol is None else max(1e-6, 100.0 * rtol)
    _walk(result, "result", set(), energy_tol)
    if isinstance(result, (float, np.floating, np.ndarray)) and not isinstance(result, bool):
        arr = np.asarray(result, dtype=float)
        if np.isnan(arr).any():
            raise Invalid("NaN in the result")
        if returns is not None and arr.size:
            lo, hi = _RANGES[returns]
            if not ((arr >= lo).all() and (arr <= hi).all()):
                raise Invalid(f"{returns} = {result!r} outside [{lo:g}, {hi:g}]")


def describe(replace: dict[int | str, Any]) -> str:
    return ", ".join(f"{k}={v!r:.60}" for k, v in replace.items())
