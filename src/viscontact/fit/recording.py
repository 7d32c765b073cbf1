"""Force-plate recordings: reading them, and what they say before any fit.

A recording is a table of time and contact force (CSV or whitespace-separated text).  As in
the drop tests of Jian et al. 2019 (lacrosse balls on a force plate) the ball's overlap obeys m* delta'' = -F (no gravity during
the contact), so with the impact speed v_i known

    delta'(t) = v_i - (1/m*) int_{t_s}^t F dt,      delta(t) = int_{t_s}^t delta' dt

from the contact start t_s.  e = -delta'(t_e) / v_i; at maximum overlap delta' = 0, so the
damping force vanishes there and k_Hertz = F(t_dmax) / delta_max^(3/2) (Jian et al. 2019).

Units inside are SI (s, N, m, kg); the file's units come from its header (``time [ms]``,
``force_kN``) or from the caller.  Every problem with a file raises :class:`RecordingError`
(a ValueError) whose one-line message names the file and, where it applies, the line.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

# scipy is imported in the functions that use it: the command line loads this module for
# its --help, which should not pay for scipy.
from ..physics import domain
from ..physics.pair import _mass

__all__ = [
    "Recording", "Measured", "RecordingError", "read_recording", "measure", "TIME_UNITS",
    "FORCE_UNITS", "MIN_CONTACT_SAMPLES",
]

#: accepted time units and their size in seconds
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6}
#: accepted force units and their size in newtons
FORCE_UNITS = {"N": 1.0, "kN": 1e3}
#: fewer samples than this above the noise cannot resolve the contact
MIN_CONTACT_SAMPLES = 10
#: this many equal samples at the peak mean the plate (or its amplifier) clipped
_SATURATED_RUN = 3


class RecordingError(ValueError):
    """A recording that cannot be used; the message names the file (and line)."""


@dataclass(frozen=True)
class Recording:
    """Time and force samples as read from a file (SI units, time strictly increasing).

    Attributes:
        path: the file; t [s]; force [N] as recorded (baseline included);
        lines: the file's line number of each sample (for messages).
    """

    path: str
    t: np.ndarray = field(repr=False)
    force: np.ndarray = field(repr=False)
    lines: np.ndarray = field(repr=False)

    @property
    def rate(self) -> float:
        """Sampling rate [Hz] (median spacing)."""
        return 1.0 / float(np.median(np.diff(self.t)))


def _split(line: str) -> list[str]:
    for sep in (",", ";", "\t"):
        if sep in line:
            return [s.strip() for s in line.split(sep)]
    return line.split()


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


_UNIT_RE = re.compile(r"[\[(]\s*([^\])]+?)\s*[\])]\s*$|_([A-Za-zµ]+)$")


def _header_unit(name: str) -> str | None:
    m = _UNIT_RE.search(name.strip())
    if m is None:
        return None
    if m.group(1):  # a unit in brackets is meant as one: an unknown one is an error later
        return m.group(1)
    return m.group(2) if m.group(2) in TIME_UNITS or m.group(2) in FORCE_UNITS else None


def _unit(where: str, kind: str, header: str | None, option: str | None, table: dict) -> float:
    """Size of the unit: the option's, else the header's, else SI; ValueError on a clash."""
    for u in (option, header):
        if u is not None and u not in table:
            raise RecordingError(f"{where}: unknown {kind} unit {u!r}; allowed: {', '.join(table)}")
    if option is not None and header is not None and table[option] != table[header]:
        raise RecordingError(f"{where}: the header gives {kind} in {header} but {option} was asked")
    return table[option or header or next(iter(table))]


def _columns(path: str, lineno: int, names: list[str]) -> tuple[int, int]:
    """Indices of the time and force columns from header names (else the first two)."""
    low = [n.lower() for n in names]
    t_col = next((i for i, n in enumerate(low) if n.startswith(("time", "t ", "t[", "t(", "t_"))
                  or n == "t"), None)
    f_col = next((i for i, n in enumerate(low) if n.startswith(("force", "f ", "f[", "f(", "f_"))
                  or n == "f" or "force" in n), None)
    if t_col is None and f_col is None and len(names) >= 2:
        return 0, 1
    if t_col is None or f_col is None:
        missing = "time" if t_col is None else "force"
        raise RecordingError(f"{path}: line {lineno}: no {missing} column in the header "
                             f"({', '.join(names)}); name them e.g. 'time [ms]' and 'force [N]'")
    return t_col, f_col


def check_path(path: Any) -> Path:
    """``path`` as a Path if it is a str or os.PathLike, else RecordingError."""
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise RecordingError(f"a file is named by a path (str or pathlib.Path), got {path!r:.60}")
    return Path(path)


def float_array(name: str, x: Any, *, lo: float | None = None, lo_open: bool = False
                ) -> np.ndarray:
    """``x`` as a float array of finite real numbers (>= lo, or > lo with ``lo_open``), else
    ValueError naming ``name`` and what is allowed."""
    allowed = "finite real numbers" + ("" if lo is None else f" {'>' if lo_open else '>='} {lo:g}")
    if isinstance(x, (str, bytes, dict, set)) or x is None:
        raise ValueError(f"{name} must be {allowed}, got {x!r:.60}")
    try:
        raw = np.asarray(x)
        if raw.dtype.kind not in "iufO":  # complex, bool, strings: not real numbers
            raise TypeError
        a = raw.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be {allowed}, got {x!r:.60}") from None
    bad = ~np.isfinite(a)
    if lo is not None:
        bad |= (a <= lo) if lo_open else (a < lo)
    if bad.any():
        raise ValueError(f"{name} must be {allowed}, got {a[bad].ravel()[0]!r}")
    return a


def read_recording(path: str | Path, *, time_unit: str | None = None,
                   force_unit: str | None = None) -> Recording:
    """Read time and force columns from a CSV or whitespace-separated text file.

    Lines starting with ``#`` are comments.  An optional header line names the columns
    (``time``/``t`` and ``force``/``F``; otherwise the first two columns are time and force)
    and may carry units: ``time [ms]``, ``force (kN)``, ``t_us``.  ``time_unit`` (s, ms, us)
    and ``force_unit`` (N, kN) apply where the header gives none; SI otherwise.
    """
    if not isinstance(path, (str, Path)):
        raise RecordingError(f"a recording is named by a path (str or pathlib.Path), got {path!r}")
    for label, unit, table in (("time_unit", time_unit, TIME_UNITS),
                               ("force_unit", force_unit, FORCE_UNITS)):
        if unit is not None:
            domain.check_choice(label, unit, tuple(table))
    path = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise RecordingError(f"{path}: not a text file (CSV or whitespace-separated)") from None
    except (OSError, ValueError) as exc:  # missing, a directory, unreadable, NUL in the name
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise RecordingError(f"{path}: cannot read the recording: {reason}") from None
    cols: tuple[int, int] | None = None
    units: tuple[str | None, str | None] = (None, None)
    ts: list[float] = []
    fs: list[float] = []
    lines: list[int] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        fields = _split(line)
        if cols is None:
            if not all(_is_number(f) for f in fields[:2]):
                cols = _columns(path, lineno, fields)
                units = (_header_unit(fields[cols[0]]), _header_unit(fields[cols[1]]))
                continue
            cols = (0, 1)
        need = max(cols) + 1
        if len(fields) < need:
            raise RecordingError(f"{path}: line {lineno}: {len(fields)} column(s), need {need} "
                                 "(time and force)")
        try:
            t, f = float(fields[cols[0]]), float(fields[cols[1]])
        except ValueError:
            bad = next(x for x in (fields[cols[0]], fields[cols[1]]) if not _is_number(x))
            raise RecordingError(f"{path}: line {lineno}: non-numeric value {bad!r}") from None
        if not (math.isfinite(t) and math.isfinite(f)):
            raise RecordingError(f"{path}: line {lineno}: time and force must be finite numbers")
        if ts and t <= ts[-1]:
            raise RecordingError(f"{path}: line {lineno}: time {fields[cols[0]]} does not increase "
                                 f"(previous sample: line {lines[-1]})")
        ts.append(t)
        fs.append(f)
        lines.append(lineno)
    if len(ts) < MIN_CONTACT_SAMPLES:
        raise RecordingError(f"{path}: {len(ts)} samples; a recording needs the contact and a "
                             "baseline before and after it")
    t_scale = _unit(path, "time", units[0], time_unit, TIME_UNITS)
    f_scale = _unit(path, "force", units[1], force_unit, FORCE_UNITS)
    return Recording(path=path, t=np.array(ts) * t_scale, force=np.array(fs) * f_scale,
                     lines=np.array(lines))


@dataclass
class Measured:
    """What a recording says before any fit (SI units).

    Attributes:
        path: the recording; mass m* [kg]; v [m/s] the impact speed given; radius R* [m] or None.
        rate [Hz] sampling rate; baseline [N] the offset removed; noise [N] its standard
        deviation (robust estimate from the samples outside the contact).
        t_start, t_end [s] contact start and end (edges extrapolated to zero force);
        n_contact: samples in contact.
        e = -delta'(t_end) / v; tc = t_end - t_start [s]; fmax [N] at t_fmax [s];
        dmax [m] at t_dmax [s]; k_hertz = F(t_dmax) / dmax^1.5 [N/m^1.5]; residual [m] = delta(t_end);
        e_modulus [Pa] E* = 3 k_Hertz / (4 sqrt(R*)) when the radius is known.
        t [s], force [N] (baseline removed), velocity [m/s] and overlap [m] (integrated from
        t_start) on the samples of the fit window (the contact and a margin either side).
    """

    path: str
    mass: float
    v: float
    radius: float | None
    rate: float
    baseline: float
    noise: float
    t_start: float
    t_end: float
    n_contact: int
    e: float
    tc: float
    fmax: float
    t_fmax: float
    dmax: float
    t_dmax: float
    k_hertz: float
    residual: float
    e_modulus: float | None
    t: np.ndarray = field(repr=False)
    force: np.ndarray = field(repr=False)
    velocity: np.ndarray = field(repr=False)
    overlap: np.ndarray = field(repr=False)

    def overlap_from(self, t0: float) -> np.ndarray:
        """Overlap on the window samples counted from a contact start t0 (negative before it)."""
        d0 = self.v * (t0 - self.t_start) if t0 <= self.t_start else float(
            np.interp(t0, self.t, self.overlap))
        return self.overlap - d0

    def to_dict(self) -> dict[str, Any]:
        """The measured quantities, JSON-ready (no sample arrays)."""
        keys = ("path", "mass", "v", "radius", "rate", "baseline", "noise", "t_start", "t_end",
                "n_contact", "e", "tc", "fmax", "t_fmax", "dmax", "t_dmax", "k_hertz",
                "residual", "e_modulus")
        return {k: getattr(self, k) for k in keys}


def _outside(f: np.ndarray, level: float) -> np.ndarray:
    """Mask of the samples away from the contact: outside the run around the peak where
    f > level, with a guard of a tenth of that run (at least 3 samples) on either side."""
    i_pk = int(np.argmax(f))
    lo, hi = i_pk, i_pk
    while lo > 0 and f[lo - 1] > level:
        lo -= 1
    while hi < f.size - 1 and f[hi + 1] > level:
        hi += 1
    guard = max(3, (hi - lo) // 10)
    mask = np.ones(f.size, dtype=bool)
    mask[max(lo - guard, 0): hi + guard + 1] = False
    return mask


def _baseline(rec: Recording) -> tuple[float, float]:
    """(offset, noise sigma) from the samples away from the contact.

    Two passes: the median and the scaled median absolute deviation outside a rough contact
    (5 % of the peak), then again outside the run where a 5-sample running mean stands
    4 standard errors above that baseline (so a long, weak tail does not bias the offset).
    """
    f = rec.force
    b0 = float(np.median(f))
    rough = _outside(f - b0, 0.05 * float(np.max(f - b0)))
    if np.count_nonzero(rough) < 5:
        raise RecordingError(f"{rec.path}: no baseline: the recording needs samples before and "
                             "after the contact (at least a quarter of the contact time each side)")
    base = float(np.median(f[rough]))
    noise = 1.4826 * float(np.median(np.abs(f[rough] - base)))
    if noise > 0:
        smooth = np.convolve(f - base, np.ones(5) / 5, mode="same")
        quiet = _outside(smooth, 4.0 * noise / math.sqrt(5))
        if np.count_nonzero(quiet) >= 5:
            base = float(np.median(f[quiet]))
            noise = 1.4826 * float(np.median(np.abs(f[quiet] - base)))
    return base, noise


def _edge(t: np.ndarray, f: np.ndarray, rising: bool) -> float | None:
    """Where a force edge meets zero: fit F = A u^(3/2) + B u^q, u = |t - t0| (0 outside).

    Near the start every law is a Hertz term plus a damping term of its own power,
    k (v u)^(3/2) + c v^(1+p) u^p (LH p = 0: a jump; Jian: p = 3/2 after the switch-on), so
    this two-term form extrapolates each law's edge to zero without knowing the law; at the
    end it covers a simple zero (q = 1) and the tangential (q = 3/2) return to zero.
    Where the foot of the edge hides in the noise (a Hertz-like u^(3/2) start, light
    damping) the start is uncertain by a few samples: see the tolerances in tests/fit/test_fit.py.
    """
    from scipy.optimize import least_squares

    if t.size < 6:
        return None
    s = 1.0 if rising else -1.0
    span = float(t[-1] - t[0])
    fmax = float(np.max(f))

    def resid(x):
        a, b, q, t0 = x
        u = np.maximum(s * (t - t0), 0.0) / span
        return np.where(u > 0, a * u ** 1.5 + b * u ** q, 0.0) - f / fmax

    i0 = int(np.argmax(f > 0.1 * fmax)) if rising else int(f.size - 1 - np.argmax(f[::-1] > 0.1 * fmax))
    lo, hi = (t[0] - span, t[-1]) if rising else (t[0], t[-1] + span)
    best = None
    for q0 in (0.0, 0.5, 1.0):  # starts: a jump (LH), a steep and a smooth edge
        try:
            sol = least_squares(resid, [1.0, 0.5, q0, min(max(float(t[i0]), lo), hi)],
                                bounds=([0.0, 0.0, 0.0, lo], [1e3, 1e3, 1.5, hi]),
                                x_scale=[1.0, 1.0, 1.0, span / t.size])
        except (ValueError, FloatingPointError):  # pragma: no cover - degenerate edge
            continue
        if best is None or sol.cost < best.cost:
            best = sol
    return None if best is None else float(best.x[3])


def _parabola_peak(t: np.ndarray, y: np.ndarray, i: int, half: int) -> tuple[float, float]:
    """Vertex (t, y) of a least-squares parabola through y[i-half : i+half+1] (noise averaging)."""
    a, b = max(i - half, 0), min(i + half + 1, y.size)
    if b - a < 3:
        return float(t[i]), float(y[i])
    tt = t[a:b] - t[i]
    c2, c1, c0 = np.polyfit(tt, y[a:b], 2)
    if c2 >= 0:  # not a maximum: keep the sample
        return float(t[i]), float(y[i])
    tv = float(np.clip(-c1 / (2 * c2), tt[0], tt[-1]))
    return float(t[i] + tv), float(c0 + c1 * tv + c2 * tv * tv)


def _value_at(t: np.ndarray, y: np.ndarray, t_at: float, half_width: float) -> float:
    """y at t_at from a least-squares parabola over |t - t_at| <= half_width (noise averaging)."""
    sel = np.abs(t - t_at) <= half_width
    if np.count_nonzero(sel) < 5:
        return float(np.interp(t_at, t, y))
    return float(np.polyval(np.polyfit(t[sel] - t_at, y[sel], 2), 0.0))


#: how far above 1 a measured e may come from noise before the recording is refused as
#: inconsistent (e = 1465 for a recording in ms read as seconds)
_E_SLACK = 0.05


def measure(rec: Recording, *, mass: float, v: float, radius: float | None = None,
            margin: float = 0.3) -> Measured:
    """e, t_c, F_max, delta_max, k_Hertz and the residual overlap read from a recording.

    ``mass`` m* [kg], ``v`` impact speed [m/s], ``radius`` R* [m] (optional: only for E*).
    The fit window keeps ``margin`` t_c of samples before and after the contact.
    Raises :class:`RecordingError` when no contact stands out of the noise, too few samples
    fall in the contact, or the plate saturated.
    """
    if not isinstance(rec, Recording):
        raise ValueError(f"measure needs a Recording (read_recording(...)), got {rec!r}")
    mass = _mass(mass, "mass")
    v = domain.check("v", v, label="impact speed")
    if radius is not None:
        radius = domain.check("radius", radius)
    margin = domain.check("margin", margin)
    base, noise = _baseline(rec)
    f = rec.force - base
    t = rec.t
    i_pk = int(np.argmax(f))
    peak = float(f[i_pk])
    if peak <= 10.0 * noise or peak <= 0:
        hint = ("; the force dips below the baseline instead: give compression as positive"
                if -float(np.min(f)) > 2.0 * peak else "")
        raise RecordingError(f"{rec.path}: no contact found: the largest force above the baseline "
                             f"({peak:.3g} N) is within the noise (sigma {noise:.3g} N){hint}")
    # saturation: several equal samples at the maximum of the raw signal
    top = rec.force[i_pk]
    run_lo, run_hi = i_pk, i_pk
    while run_lo > 0 and rec.force[run_lo - 1] == top:
        run_lo -= 1
    while run_hi < f.size - 1 and rec.force[run_hi + 1] == top:
        run_hi += 1
    if run_hi - run_lo + 1 >= _SATURATED_RUN:
        raise RecordingError(
            f"{rec.path}: lines {rec.lines[run_lo]}-{rec.lines[run_hi]}: the force plate saturates "
            f"({run_hi - run_lo + 1} samples stuck at {top:g}); the peak is clipped, so the impulse, "
            "e, F_max and any fit would be wrong")
    thr = max(6.0 * noise, 0.02 * peak)
    lo, hi = i_pk, i_pk
    while lo > 0 and f[lo - 1] > thr:
        lo -= 1
    while hi < f.size - 1 and f[hi + 1] > thr:
        hi += 1
    n_contact = hi - lo + 1
    if n_contact < MIN_CONTACT_SAMPLES:
        raise RecordingError(f"{rec.path}: only {n_contact} samples in contact (need at least "
                             f"{MIN_CONTACT_SAMPLES}); record at a higher sampling rate")
    if lo == 0 or hi == f.size - 1:
        raise RecordingError(f"{rec.path}: the contact touches the "
                             f"{'start' if lo == 0 else 'end'} of the recording; keep samples "
                             "before and after the impact")
    # edges: extrapolate each edge to zero force (the threshold crossing is late/early)
    i_rise = lo + int(np.argmax(f[lo: i_pk + 1] > 0.5 * peak))
    i_fall = hi - int(np.argmax(f[i_pk: hi + 1][::-1] > 0.3 * peak))
    # each edge fit sees as many samples again beyond the threshold crossing (mostly zeros)
    a = max(lo - max(3, 2 * (i_rise - lo + 1)), 0)
    b = min(hi + max(3, 2 * (hi - i_fall + 1)), f.size - 1)
    t_start = _edge(t[a: i_rise + 1], f[a: i_rise + 1], rising=True)
    t_end = _edge(t[i_fall: b + 1], f[i_fall: b + 1], rising=False)
    # an edge fit outside the samples bounding it is not believed: fall back to the crossing
    if t_start is None or not (t[a] <= t_start <= t[lo]):
        t_start = float(t[lo - 1])
    if t_end is None or not (t[hi] <= t_end <= t[b]):
        t_end = float(t[hi + 1])
    tc = t_end - t_start
    win = (t >= t_start - margin * tc) & (t <= t_end + margin * tc)
    tw, fw = t[win], f[win]

    def integrate(t0: float):
        """Velocity and overlap from a start t0 over the window (ballistic before t0), and the
        maximum overlap (t_dmax, dmax) where the velocity crosses zero.  Past t_end the
        baseline-free force averages out, and a tail hidden in the noise still counts in e."""
        after = tw > t0
        tg = np.r_[t0, tw[after]]
        fg = np.r_[0.0, fw[after]]
        vel = v - np.r_[0.0, np.cumsum(0.5 * (fg[1:] + fg[:-1]) * np.diff(tg))] / mass
        dis = np.r_[0.0, np.cumsum(0.5 * (vel[1:] + vel[:-1]) * np.diff(tg))]
        j = int(np.argmax(vel <= 0))
        if j == 0:
            raise RecordingError(f"{rec.path}: the integrated velocity never reverses: the impulse "
                                 f"is too small for m* = {mass:g} kg and v = {v:g} m/s (check units)")
        w = vel[j - 1] / (vel[j - 1] - vel[j])
        t_dm = float(tg[j - 1] + w * (tg[j] - tg[j - 1]))
        d_m = float(dis[j - 1] + 0.5 * (tg[j] - tg[j - 1]) * w * vel[j - 1])
        k_h = _value_at(t, f, t_dm, 0.05 * tc) / d_m ** 1.5
        vel_w = np.r_[np.full(np.count_nonzero(~after), v), vel[1:]]
        dis_w = np.r_[v * (tw[~after] - t0), dis[1:]]
        return tg, vel, dis, t_dm, d_m, k_h, vel_w, dis_w

    tg, vel_g, del_g, t_dmax, dmax, k_hertz, vel_w, del_w = integrate(t_start)
    e = -float(vel_g[-1]) / v
    residual = float(np.interp(t_end, tg, del_g))
    # a rebound faster than the impact beyond what noise explains: the numbers do not
    # describe this recording (units, mass or speed wrong)
    if e > 1.0 + _E_SLACK:
        raise RecordingError(
            f"{rec.path}: the recording gives e = {e:.4g} and a residual overlap of "
            f"{residual:.3g} m for m* = {mass:g} kg and v = {v:g} m/s, impossible for an impact "
            "(e must be <= 1, the overlap >= 0): check the time and force units (a header such "
            "as 'time [ms]', or --time-unit/--force-unit), the mass and the impact speed")
    e = min(e, 1.0)  # within the noise of 1
    residual = max(residual, 0.0)  # an overlap cannot be negative: noise around 0 (Hunt)
    half = 0.05 * tc
    t_fmax, fmax = _parabola_peak(t, f, i_pk, max(2, int(round(half * rec.rate))))
    e_mod = None if radius is None else 0.75 * k_hertz / math.sqrt(radius)
    return Measured(
        path=rec.path, mass=mass, v=v, radius=radius, rate=rec.rate, baseline=base, noise=noise,
        t_start=t_start, t_end=t_end, n_contact=n_contact, e=e, tc=tc, fmax=fmax, t_fmax=t_fmax,
        dmax=dmax, t_dmax=t_dmax, k_hertz=k_hertz, residual=residual, e_modulus=e_mod,
        t=tw, force=fw, velocity=vel_w, overlap=del_w,
    )
