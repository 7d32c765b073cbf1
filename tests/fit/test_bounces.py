"""Bounce timings to (v, e): the drag ODE integrated independently reduces back to the true
points, glitches are named and left out, the file formats read, bad files get one error."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from viscontact.fit.bounces import (drag_constant, flight_time, landing_speed, launch_speed,
                                    read_bounces, reduce_bounces)
from viscontact.fit.recording import RecordingError
from viscontact.fit.restitution import model_e

G = 9.81


def flight_ode(u: float, k: float) -> tuple[float, float]:
    """(duration, landing speed) of a vertical flight with drag m k v|v|, integrated."""
    def rhs(t, y):
        return [y[1], -G - k * y[1] * abs(y[1])]

    def ground(t, y):
        return y[0]
    ground.terminal, ground.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 10.0), [0.0, u], method="DOP853", rtol=1e-13, atol=1e-16,
                    events=ground, first_step=1e-9)
    # the event at t = 0 (y = 0 rising) is not a crossing downwards, so the first event lands
    return float(sol.t_events[0][0]), float(-sol.y_events[0][0][1])




@pytest.mark.parametrize("k", [0.0, 0.05])
def test_drag_ode_timings_reduce_to_true_points(k):
    """A ping-pong-like ball (k = 0.05 1/m) bouncing with KK's e(v); contact times of
    0.4 ms * (v / 1 m/s)^(-1/5) (Hertz) are added to every interval and taken off again."""
    def e_of_v(v):
        return model_e("KK", v, 1.0, 0.25)

    def tc(v):
        return 4e-4 * v ** -0.2

    t, u, times, truth = 0.0, 2.5, [0.0], []
    v_imp = None
    for _ in range(9):
        dur, w = flight_ode(u, k)
        # interval = contact of the impact that starts it + the flight
        t += (tc(v_imp) if v_imp is not None else tc(2.5)) + dur
        times.append(t)
        e = float(e_of_v(w))
        truth.append((w, e))
        v_imp, u = w, e * w
    red = reduce_bounces([np.array(times)], k_drag=k, contact_time=tc)
    assert not red.rejected
    v_true = np.array([p[0] for p in truth[:-1]])
    e_true = np.array([p[1] for p in truth[:-1]])
    assert red.data.n == len(times) - 2
    # the first impact's speed is unknown (taken as u_0): its contact time is off by
    # (2.5/u0)^0.2, which moves only the first interval: compare from the second point on
    np.testing.assert_allclose(red.data.v[1:], v_true[1:], rtol=0, atol=1e-6)
    np.testing.assert_allclose(red.data.e[1:], e_true[1:], rtol=0, atol=1e-6)


@pytest.mark.parametrize("k", [0.0, 0.05])
def test_constant_contact_time_reduces_every_point(k):
    t, u, times, truth = 0.0, 2.0, [0.0], []
    for _ in range(7):
        dur, w = flight_ode(u, k)
        t += 5e-4 + dur
        times.append(t)
        e = 0.9 - 0.05 * w
        truth.append((w, e))
        u = e * w
    red = reduce_bounces([np.array(times)], k_drag=k, contact_time=5e-4)
    np.testing.assert_allclose(red.data.v, [p[0] for p in truth[:-1]], atol=1e-6, rtol=0)
    np.testing.assert_allclose(red.data.e, [p[1] for p in truth[:-1]], atol=1e-6, rtol=0)


def test_closed_forms_against_the_ode():
    k = drag_constant(2.7e-3, 0.02)
    assert k == pytest.approx(1.2 * 0.47 * math.pi * 0.02 ** 2 / (2 * 2.7e-3))
    for u in (0.3, 1.0, 4.0):
        dur, _ = flight_ode(u, k)
        assert flight_time(u, k) == pytest.approx(dur, rel=1e-11)
        assert launch_speed(dur, k) == pytest.approx(u, rel=1e-11)


def test_drag_raises_e_of_a_ping_pong_ball():
    """With drag a flight is shorter than 2u/g: the drag-free reduction underestimates e."""
    k = drag_constant(2.7e-3, 0.02)
    times, u = [0.0], 1.2
    for _ in range(5):
        dur, w = flight_ode(u, k)
        times.append(times[-1] + dur)
        u = 0.85 * w
    with_drag = reduce_bounces([times], k_drag=k).data.e
    without = reduce_bounces([times], k_drag=0.0).data.e
    np.testing.assert_allclose(with_drag, 0.85, atol=1e-9)
    assert with_drag[0] - without[0] > 0.005 and np.all(with_drag - without > 0.002)


def geometric(n=8, t0=0.6, e=0.8):
    return np.concatenate([[0.0], np.cumsum(t0 * e ** np.arange(n - 1))])


def test_missed_click_spurious_click_and_repeat_are_named():
    t = geometric(10)
    missed = np.delete(t, 5)
    red = reduce_bounces([missed])
    assert red.rejected and all("missed click" in r["reason"] for r in red.rejected)
    np.testing.assert_allclose(red.data.e, 0.8, atol=1e-12)
    spurious = np.sort(np.append(t, t[4] + 0.3 * (t[5] - t[4])))
    red = reduce_bounces([spurious])
    assert any("spurious click" in r["reason"] for r in red.rejected)
    np.testing.assert_allclose(red.data.e, 0.8, atol=1e-12)
    gaps = np.diff(t)
    repeat = np.concatenate([[0.0], np.cumsum(np.insert(gaps, 6, gaps[5]))])
    red = reduce_bounces([repeat])
    assert {r["impact"] for r in red.rejected} == {7, 8}
    assert all("a repeated reading" in r["reason"] for r in red.rejected)
    np.testing.assert_allclose(red.data.e, 0.8, atol=1e-12)


def test_plain_column_and_phyphox_export(tmp_path):
    t = geometric(6)
    col = tmp_path / "drop.txt"
    col.write_text("time (s)\n" + "\n".join(f"{x:.6f}" for x in t) + "\n")
    np.testing.assert_allclose(read_bounces(col), t, atol=1e-6)
    gaps = np.diff(t)
    head = ",".join([f'"Bounce {i} (s)"' for i in range(1, 6)]
                    + ['"Height 0 (m)"'] + [f'"Height {i} (m)"' for i in range(1, 6)])
    row = ",".join([f"{g:.9f}" for g in gaps] + ["0.5"] + [f"{G * g * g / 8:.6f}" for g in gaps])
    ph = tmp_path / "phyphox.csv"
    ph.write_text(head + "\n" + row + "\n")
    np.testing.assert_allclose(read_bounces(ph), t, atol=1e-8)
    red = reduce_bounces([read_bounces(ph)])
    assert red.data.n == 4  # six impacts: four points


@pytest.mark.parametrize("text, msg", [
    ("", "empty"),
    ("0.0\n0.5\n", "2 impact times"),
    ("0.0\n0.5\n0.4\n0.9\n", "not increasing"),
    ("0.0\n0.5\nnan\n", "finite"),
    ("0.0\n-0.5\n0.8\n", "finite and >= 0"),
    ("0.0\n0.5\nabc\n", "not an impact time"),
])
def test_bad_timing_files(tmp_path, text, msg):
    f = tmp_path / "bad.txt"
    f.write_text(text)
    with pytest.raises(RecordingError, match=msg):
        read_bounces(f)


def test_flight_limits_with_drag():
    """With drag a fast ball lands at the terminal speed sqrt(g/k) (no overflow of u^2); a
    flight longer than any finite launch speed gives is refused, not answered with NaN."""
    k, g = 0.05, 9.81
    assert landing_speed(1e300, k, g) == pytest.approx(math.sqrt(g / k), rel=1e-12)
    T = flight_time(1e6, k, g)
    assert launch_speed(T, k, g) == pytest.approx(1e6, rel=1e-9)
    with pytest.raises(ValueError, match="no flight lasts longer"):
        launch_speed(1e6, k, g)
    with pytest.raises(ValueError, match="k .* must be in"):
        flight_time(1.0, math.nan, g)
