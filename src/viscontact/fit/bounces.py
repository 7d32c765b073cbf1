"""Bounce timings (the impacts of a ball bouncing on a plate) reduced to (v, e) points.

Impact times t_0 < t_1 < ... give intervals I_j = t_{j+1} - t_j, each the contact that starts
it plus a flight: T_j = I_j - t_c(j).  Without air drag the ball leaves impact j at
u_j = g T_j / 2 and lands with the same speed, so impact j+1 has v = g T_j / 2 and
e = T_{j+1} / T_j.  With quadratic drag, k = rho_air C_d A / (2 m) (A = pi R^2), a flight
launched at u lasts (the closed forms of the drag ODE; e.g. Timmerman & van der Weele,
Am. J. Phys. 67 (1999) 538; docs/fit-restitution.md)

    T(u) = (atan z + asinh z) / sqrt(g k),   z = u sqrt(k / g)

(rise atan z / sqrt(g k), fall from the apex asinh z / sqrt(g k)), and lands at
w = u / sqrt(1 + z^2); T(u) = T_j is solved for u_j (monotone Newton from g T_j / 2), and impact
j+1 has v = w_j, e = u_{j+1} / w_j.  n timed impacts give n - 2 points.

Real timings contain glitches; a point whose flight does not shrink (e >= 1: a repeated
reading), that touches an interval about the sum of two (a missed click) or one far too short
(a spurious click) is reported with the reason and left out of the fit.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..physics import domain
from ..physics.pair import STANDARD_GRAVITY, check_positive
from .recording import RecordingError, check_path, float_array
from .restitution import RestitutionData, restitution_data

__all__ = ["read_bounces", "read_drops", "drag_constant", "flight_time", "landing_speed", "launch_speed",
           "Reduction", "reduce_bounces", "DRAG_COEFFICIENT", "AIR_DENSITY"]

#: drag coefficient of a smooth sphere at the Reynolds numbers of a bouncing ball
DRAG_COEFFICIENT = 0.47
#: density of air at room conditions [kg/m^3]
AIR_DENSITY = 1.2

_BOUNCE_COL = re.compile(r"^\s*\"?\s*(?:bounce|time)\s*(\d+)\s*\(s\)\s*\"?\s*$", re.IGNORECASE)


def _lines(path: str | Path) -> list[str]:
    """The file's non-empty lines, '#' comments removed."""
    try:
        text = check_path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise RecordingError(f"{path}: cannot read the file ({exc})") from None
    lines = [ln.split("#", 1)[0].strip() for ln in text.splitlines()]
    return [ln for ln in lines if ln]


def read_bounces(path: str | Path) -> np.ndarray:
    """Impact times [s] from one drop's file.

    Either a plain column of impact times (a header line optional, '#' comments), or
    phyphox's "(In)elastic collision" export as it comes: one row of columns
    "Bounce k (s)" (the time between impacts k-1 and k) and "Height k (m)"; its intervals are
    turned into impact times from 0.  RecordingError names what is wrong (too few impacts,
    times not increasing, non-finite values).
    """
    lines = _lines(path)
    if not lines:
        raise RecordingError(f"{path}: empty; give one impact time [s] per line, or phyphox's "
                             "(In)elastic collision export")
    head = [c.strip().strip('"') for c in re.split(r"[,;\t]", lines[0])]
    cols = [(int(m.group(1)), i) for i, c in enumerate(head) if (m := _BOUNCE_COL.match(c))]
    if cols:
        times = _phyphox(path, lines, sorted(cols), len(head))
    else:
        values = []
        for k, ln in enumerate(lines):
            cell = re.split(r"[,;\s]+", ln)[0]
            try:
                values.append(float(cell))
            except ValueError:
                if k == 0:
                    continue  # a header
                raise RecordingError(f"{path}: {ln!r} is not an impact time in seconds") from None
        times = np.array(values, dtype=float)
    _check_times(path, times)
    return times


def read_drops(path: str | Path) -> list[np.ndarray]:
    """The impact times of every drop in a file: a table of intervals with a ``drop`` column
    (header ``drop,...,interval [s]``: one row per interval, drops in order; impact times from
    0 for each drop), else the one drop of :func:`read_bounces`."""
    lines = _lines(path)
    head = [c.strip().lower() for c in re.split(r"[,;\t]", lines[0])] if lines else []
    if not head or head[0] != "drop":
        return [read_bounces(path)]
    col = next((i for i, c in enumerate(head) if c.startswith("interval")), None)
    if col is None:
        raise RecordingError(f"{path}: a table with a drop column needs an 'interval [s]' column")
    drops: dict[str, list[float]] = {}
    for ln in lines[1:]:
        cells = [c.strip() for c in re.split(r"[,;\t]", ln)]
        try:
            drops.setdefault(cells[0], []).append(float(cells[col]))
        except (ValueError, IndexError):
            raise RecordingError(f"{path}: {ln!r} is not a row of drop and interval [s]") from None
    out = []
    for key, gaps in drops.items():
        g = np.array(gaps)
        if not np.all(np.isfinite(g) & (g > 0)):
            raise RecordingError(f"{path}: drop {key}: intervals must be finite and > 0")
        t = np.concatenate([[0.0], np.cumsum(g)])
        _check_times(f"{path}, drop {key}", t)
        out.append(t)
    return out


def _phyphox(path: Any, lines: list[str], cols: list[tuple[int, int]], width: int) -> np.ndarray:
    if len(lines) < 2:
        raise RecordingError(f"{path}: a phyphox export needs a row of values under its header")
    cells = [c.strip().strip('"') for c in re.split(r"[,;\t]", lines[1])]
    gaps = []
    for _, i in cols:
        if i >= len(cells) or not cells[i]:
            break  # fewer impacts than columns
        try:
            gaps.append(float(cells[i]))
        except ValueError:
            raise RecordingError(f"{path}: {cells[i]!r} in column {i + 1} is not a time in "
                                 "seconds") from None
    gaps_a = np.array(gaps, dtype=float)
    bad = np.flatnonzero(~np.isfinite(gaps_a) | (gaps_a <= 0))
    if bad.size:
        raise RecordingError(f"{path}: bounce interval {float(gaps_a[bad[0]])!r} s; intervals must be "
                             "finite and > 0")
    return np.concatenate([[0.0], np.cumsum(gaps_a)])


def _check_times(path: Any, t: np.ndarray) -> None:
    if t.size < 3:
        raise RecordingError(f"{path}: {t.size} impact time{'s' if t.size != 1 else ''}; a "
                             "(v, e) point needs three impacts (n impacts give n - 2 points)")
    bad = np.flatnonzero(~np.isfinite(t) | (t < 0))
    if bad.size:
        raise RecordingError(f"{path}: impact time {float(t[bad[0]])!r}; times must be finite and >= 0")
    step = np.flatnonzero(np.diff(t) <= 0)
    if step.size:
        i = step[0]
        raise RecordingError(f"{path}: impact times not increasing ({t[i]:g} s then "
                             f"{t[i + 1]:g} s at impacts {i + 1} and {i + 2})")


def drag_constant(mass: float, radius: float, *, drag_coefficient: float = DRAG_COEFFICIENT,
                  air_density: float = AIR_DENSITY) -> float:
    """k = rho_air C_d pi R^2 / (2 m) [1/m] of the quadratic drag force m k v^2."""
    mass, radius = domain.check("mass", mass), domain.check("radius", radius)
    drag_coefficient = check_positive("drag_coefficient", drag_coefficient)
    air_density = check_positive("air_density", air_density)
    return air_density * drag_coefficient * math.pi * radius ** 2 / (2.0 * mass)


def flight_time(u: Any, k: float, g: float = STANDARD_GRAVITY) -> np.ndarray:
    """Time of a vertical flight launched at speed u [m/s] back to the launch height:
    (atan z + asinh z) / sqrt(g k), z = u sqrt(k/g); 2 u / g at k = 0."""
    u, k, g = _flight_args("u", u, k, g)
    if k == 0:
        return 2.0 * u / g
    z = u * math.sqrt(k / g)
    return (np.arctan(z) + np.arcsinh(z)) / math.sqrt(g * k)


def landing_speed(u: Any, k: float, g: float = STANDARD_GRAVITY) -> np.ndarray:
    """Speed at the launch height after a vertical flight launched at u: u / sqrt(1 + k u^2/g)."""
    u, k, g = _flight_args("u", u, k, g)
    return u / np.hypot(1.0, u * math.sqrt(k / g))  # hypot: no overflow of u^2


def _flight_args(name: str, x: Any, k: Any, g: Any) -> tuple[np.ndarray, float, float]:
    """Speeds or times ``x`` (finite, >= 0), drag constant k (finite, >= 0 [1/m]), gravity g
    (the domain's range [m/s^2]); ValueError names the bad one."""
    k = domain.check_number("k", k)
    if not (math.isfinite(k) and 0.0 <= k <= 1e6):
        raise ValueError(f"k (the drag constant) must be in [0, 1e6] 1/m, got {k!r}")
    return float_array(name, x, lo=0.0), k, domain.check("gravity", g, label="g")


def launch_speed(T: Any, k: float, g: float = STANDARD_GRAVITY) -> np.ndarray:
    """The launch speed u whose flight lasts T [s] (inverse of :func:`flight_time`).

    T(u) is increasing and concave, so Newton from g T / 2 (below the root) climbs to it
    monotonically; dT/du = (1/(1 + z^2) + 1/sqrt(1 + z^2)) / g."""
    T, k, g = _flight_args("T", T, k, g)
    u = g * T / 2.0
    if k == 0:
        return u
    # T(u) -> (pi/2 + ln 2z) / sqrt(g k) at large z: a longer flight needs u beyond any float
    t_max = (math.pi / 2 + math.log(2 * 1e300 * math.sqrt(k / g))) / math.sqrt(g * k)
    if np.any(T > t_max):
        raise ValueError(f"T = {float(np.max(T)):g} s: with drag k = {k:g} 1/m no flight lasts "
                         f"longer than {t_max:.4g} s (give a shorter flight or a smaller k)")
    for _ in range(200):
        h = np.hypot(1.0, u * math.sqrt(k / g))
        du = (flight_time(u, k, g) - T) / ((1.0 / (h * h) + 1.0 / h) / g)
        u = u - du
        if np.all(np.abs(du) <= 1e-15 * np.maximum(u, 1e-300)):
            break
    return u


@dataclass(frozen=True)
class Reduction:
    """Bounce timings of one or more drops reduced to (v, e).

    ``data``: the points kept (in recording order); ``rejected``: one dict per point left out
    (drop, impact, v, e, reason); ``impacts``: the impact times of each drop; ``notes``: what
    the reduction assumed (drag, contact time)."""

    data: RestitutionData
    rejected: list[dict[str, Any]]
    impacts: list[list[float]]
    notes: list[str] = field(default_factory=list)
    #: every point of every drop, kept or not: drop, impact, v, e, kept
    points: list[dict[str, Any]] = field(default_factory=list)


def _glitches(I: np.ndarray) -> list[str | None]:
    """Why each interval is suspect (None: plausible), from the median ratio rho of
    successive intervals and the last plausible interval before it (prev): two intervals
    whose sum is nearer rho prev than the first alone are one flight split by a spurious
    click; one whose ratio to prev is nearer rho (1 + rho) than rho (in log) covers two
    flights (a missed click); one below rho / 2 of prev is far too short."""
    n = I.size
    why: list[str | None] = [None] * n
    r = I[1:] / I[:-1]
    ok = r[(r > 0) & (r < 1)]
    if ok.size == 0:
        return why
    rho = float(np.median(ok))
    short = "is far too short: a spurious click"
    if n > 1 and I[0] < 0.5 * I[1]:
        why[0] = f"interval 1 ({I[0] * 1e3:.4g} ms) {short}"
    prev = I[0] if why[0] is None else I[1] / rho
    j = 1
    while j < n:
        if abs(I[j] - I[j - 1]) <= 1e-9 * I[j]:
            why[j] = (f"interval {j + 1} ({I[j] * 1e3:.6g} ms) repeats the one before exactly: "
                      "a repeated reading")
            prev, j = prev * rho, j + 1
            continue
        q = I[j] / prev
        if j + 1 < n and abs(math.log((I[j] + I[j + 1]) / prev / rho)) < abs(math.log(q / rho)) \
                and abs(math.log((I[j] + I[j + 1]) / prev / rho)) < abs(math.log(I[j + 1] / I[j] / rho)):
            for i in (j, j + 1):
                why[i] = f"interval {i + 1} ({I[i] * 1e3:.4g} ms) {short}"
            prev, j = I[j] + I[j + 1], j + 2
            continue
        if q > 1 and abs(math.log(q / (rho * (1 + rho)))) < abs(math.log(q / rho)):
            why[j] = (f"interval {j + 1} ({I[j] * 1e3:.4g} ms) is about the sum of two: "
                      "a missed click")
            prev = I[j] * rho / (1 + rho)
        elif q < rho / 2:
            why[j] = f"interval {j + 1} ({I[j] * 1e3:.4g} ms) {short}"
            prev = prev * rho
        else:
            prev = I[j]
        j += 1
    return why


def reduce_bounces(
    drops: Sequence[Any], *, k_drag: float = 0.0, contact_time: float | Any = None,
    g: float = STANDARD_GRAVITY, sources: Sequence[str] | None = None,
) -> Reduction:
    """(v, e) points from the impact times of each drop (a sequence of arrays, seconds).

    ``k_drag`` [1/m]: the drag constant (:func:`drag_constant`; 0: no drag).
    ``contact_time``: a number [s] taken off every interval, or a function of the impact
    speed v [m/s] giving t_c [s] (then the reduction iterates: t_c depends on v); None takes
    nothing off (the intervals are the flights).  Points that break the physics are left out
    and listed in ``rejected`` with the reason.
    """
    drops, sources = _drops_args(drops, sources)
    k_drag = _flight_args("k_drag", 0.0, k_drag, g)[1]
    g = domain.check("gravity", g, label="g")
    if contact_time is not None and not callable(contact_time):
        if isinstance(contact_time, bool) or np.ndim(contact_time) != 0:
            raise ValueError(f"contact_time must be None, a number >= 0 [s] or a function of v, "
                             f"got {contact_time!r:.60}")
        contact_time = float(float_array("contact_time", contact_time, lo=0.0))
    vs, es, drop_of, rejected, points, impacts = [], [], [], [], [], []
    for d, times in enumerate(drops):
        src = sources[d] if sources else f"drop {d + 1}"
        t = float_array(f"the impact times of {src}", times).reshape(-1)
        _check_times(src, t)
        impacts.append([float(x) for x in t])
        I = np.diff(t)
        why = _glitches(I)
        v, e = _reduce(I, k_drag, contact_time, g)
        for j in range(v.size):  # point j is impact j + 1, between intervals j and j + 1
            reason = why[j] or why[j + 1]
            if reason is None and not (e[j] < 1.0):
                reason = (f"e = {e[j]:.4g} >= 1: the flight after impact {j + 2} does not "
                          "shrink (a repeated reading?)")
            if reason is None and not (v[j] > 0 and e[j] > 0 and np.isfinite(v[j] + e[j])):
                reason = "the flight is shorter than the contact time taken off"
            pt = {"drop": d + 1, "source": src, "impact": j + 2, "v": float(v[j]),
                  "e": float(e[j]), "kept": reason is None}
            points.append(pt)
            if reason is None:
                vs.append(v[j])
                es.append(e[j])
                drop_of.append(d + 1)
            else:
                rejected.append({**{k: pt[k] for k in ("drop", "source", "impact", "v", "e")},
                                 "reason": reason})
    notes = [_drag_note(k_drag), _tc_note(contact_time)]
    if len(vs) < 2:
        raise RecordingError(
            f"{len(vs)} usable (v, e) point{'s' if len(vs) != 1 else ''} from the bounce "
            f"timings ({len(rejected)} left out: "
            + ("; ".join(r["reason"] for r in rejected[:3]) or "too few impacts") + "); a fit needs two")
    data = restitution_data(vs, es, source=", ".join(sources) if sources else "bounces",
                            drop=drop_of)
    return Reduction(data, rejected, impacts, notes, points)


def _drops_args(drops: Any, sources: Any) -> tuple[list[Any], list[str] | None]:
    """The drops as a list (one array of impact times each) and their names, checked."""
    if isinstance(drops, np.ndarray) and drops.ndim == 2:
        drops = list(drops)
    if not isinstance(drops, (list, tuple)) or not drops:
        raise ValueError(f"drops must be a non-empty list of arrays of impact times [s], got "
                         f"{drops!r:.60}")
    if sources is not None and (not isinstance(sources, (list, tuple)) or len(sources) != len(drops)
                                or not all(isinstance(s, str) for s in sources)):
        raise ValueError(f"sources must be None or one name (str) per drop ({len(drops)}), got "
                         f"{sources!r:.60}")
    return list(drops), (list(sources) if sources else None)


def _reduce(I: np.ndarray, k: float, contact_time: Any, g: float) -> tuple[np.ndarray, np.ndarray]:
    """(v, e) of impacts 2 .. n-1 from the intervals I."""
    tc = np.zeros(I.size)
    for _ in range(4 if callable(contact_time) else 1):
        if contact_time is not None:
            if callable(contact_time):
                u0 = launch_speed(np.maximum(I - tc, 1e-12), k, g)
                # impact j has speed w_{j-1}; the first impact's, unknown, is taken as u_0
                v_imp = np.concatenate([[u0[0]], landing_speed(u0[:-1], k, g)])
                tc = np.asarray([float(contact_time(x)) for x in v_imp])
            else:
                tc = np.full(I.size, float(contact_time))
        T = I - tc
        u = launch_speed(np.where(T > 0, T, np.nan), k, g)
    w = landing_speed(u, k, g)
    return w[:-1], u[1:] / w[:-1]


def _drag_note(k: float) -> str:
    if k == 0:
        return "no air drag in the reduction (--no-drag, or no --mass and --radius)"
    return f"quadratic air drag in the reduction, k = rho C_d A / (2 m) = {k:.4g} 1/m"


def _tc_note(contact_time: Any) -> str:
    if contact_time is None:
        return ("no contact time taken off the intervals (give --contact-time, or E and nu): "
                "the intervals are taken as the flights")
    if callable(contact_time):
        return "the Hertz contact time t_c(v) = 3.218 T(v) of E and nu taken off each interval"
    return f"contact time {float(contact_time) * 1e3:.4g} ms taken off each interval"
