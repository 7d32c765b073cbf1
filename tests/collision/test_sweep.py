"""Velocity sweeps with physical constants held fixed (docs/reproduce.md, "Velocity sweeps")."""

import csv
import io
import json

import numpy as np
import pytest

import viscontact as vc
from viscontact.cli import main
from viscontact.paper.experiment import calibrate_ball, load_balls
from viscontact.collision.sweep import study_speeds, velocity_sweep

from conftest import run_cli

M, K = 0.1472, 1.724e6


def test_study_speeds():
    v = study_speeds()
    assert v[0] == pytest.approx(0.30) and v[-1] == pytest.approx(2.60) and v.size == 24
    assert np.allclose(np.diff(v), 0.10)


def test_sweep_reproduces_the_calibration_point():
    ball = load_balls()["OLB"]
    for m, cal in calibrate_ball(ball).items():
        s = velocity_sweep(m, [ball.v_in], m_eff=cal.m_eff, k_hertz=cal.k_hertz, c=cal.c,
                           tau=cal.tau)
        assert s.e[0] == pytest.approx(ball.e, abs=1e-9), m
        assert s.alpha[0] == pytest.approx(cal.alpha, rel=1e-12)


def test_alpha_follows_its_velocity_exponent():
    v = np.array([0.3, 1.0, 2.6])
    for model, p in (("LH", 0.0), ("KK", 0.5), ("Li", 1.0), ("Hunt", 1.5)):
        s = velocity_sweep(model, v, m_eff=M, k_hertz=K, c=1.0)
        # alpha = c / (m^((3-2p)/5) v^((1-4p)/5) k^((2+2p)/5)) ~ v^((4p-1)/5)
        assert np.allclose(s.alpha / s.alpha[0], (v / v[0]) ** ((4 * p - 1) / 5), rtol=1e-12)


def test_tsuji_restitution_does_not_depend_on_speed():
    s = velocity_sweep("Ts", [0.3, 1.0, 2.6], m_eff=M, k_hertz=K, c=50.0)
    assert np.ptp(s.e) < 1e-9
    assert np.all(np.diff(s.tc) < 0) and np.all(np.diff(s.fmax) > 0)


def test_trends_with_speed():
    v = [0.3, 1.0, 2.6]
    lh = velocity_sweep("LH", v, m_eff=M, k_hertz=K, c=10.0)
    hunt = velocity_sweep("Hunt", v, m_eff=M, k_hertz=K, c=2e5)
    assert np.all(np.diff(lh.e) > 0)  # linear dashpot: faster impacts bounce better
    assert np.all(np.diff(hunt.e) < 0)  # Hunt-Crossley: e falls with speed
    assert np.all(hunt.residual < 1e-12)


def test_jian_beta_is_tau_over_T():
    v = np.array([0.5, 2.0])
    s = velocity_sweep("Jian", v, m_eff=M, k_hertz=K, c=600.0, tau=2.7e-3)
    T = np.array([vc.time_scale(M, K, x) for x in v])
    assert np.allclose(s.beta, 2.7e-3 / T, rtol=1e-14)
    assert np.allclose(s.T, T)


@pytest.mark.parametrize("kwargs", [
    dict(speeds=[1.0, -1.0]), dict(speeds=[]), dict(speeds=[1.0], c=-1.0),
    dict(speeds=[1.0], m_eff=0.0), dict(speeds=[1.0], model="Jian"),
])
def test_bad_sweep_input(kwargs):
    args = dict(model="KK", speeds=[1.0], m_eff=M, k_hertz=K, c=100.0) | kwargs
    with pytest.raises(ValueError):
        velocity_sweep(args.pop("model"), args.pop("speeds"), **args)


def test_cli_sweep_csv_json_plot(tmp_path):
    proc = run_cli("sweep", "--ball", "ILB", "--num", "3", "--csv", tmp_path / "s.csv",
                   "--json-out", tmp_path / "s.json", "--plot", tmp_path / "s.png")
    assert proc.returncode == 0, proc.stderr
    marker, text = (tmp_path / "s.csv").read_text().split("\n", 1)
    assert marker.startswith("# written by viscontact sweep ")  # the file rule's marker
    rows = list(csv.DictReader(io.StringIO(text)))
    assert len(rows) == 6 * 3
    assert {r["model"] for r in rows} == set(vc.STUDY_MODELS)
    assert float(rows[0]["v [m/s]"]) == pytest.approx(0.30)
    data = json.loads((tmp_path / "s.json").read_text())
    assert len(data["sweeps"]) == 6 and data["sweeps"][0]["units"]["tc"] == "s"
    assert (tmp_path / "s.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_sweep_given_c_to_stdout(capsys):
    assert main(["sweep", "--law", "Jian", "--c", "600", "--tau", "2.7e-3", "--mass", str(M),
                 "--k-hertz", str(K), "--speeds", "0.5", "1.5"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert [r["model"] for r in rows] == ["Jian", "Jian"]


@pytest.mark.parametrize("args", [
    ["--ball", "ILB", "--v-min", "-1"],
    ["--ball", "ILB", "--speeds", "0"],
    ["--law", "KK", "--c", "10", "--mass", "0", "--k-hertz", "1e6"],
    ["--law", "KK", "--c", "10", "--mass", "1"],
    ["--c", "10", "--mass", "1", "--k-hertz", "1e6"],
    ["--mass", "1", "--k-hertz", "1e6", "--v", "1"],
    ["--ball", "ILB", "--csv", "/nonexistent-dir/s.csv"],
])
def test_cli_sweep_bad_input(args, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["sweep", *args]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and err.startswith("viscontact sweep: error:"), err
    assert list(tmp_path.iterdir()) == []


def test_cli_sweep_json_prints_one_object_and_old_file_form_still_writes(tmp_path, capsys,
                                                                         monkeypatch):
    """``--json`` alone: one JSON object on stdout, nothing else there; ``--json FILE`` (the old
    form) still writes FILE, with a deprecation note on stderr."""
    monkeypatch.chdir(tmp_path)
    argv = ["sweep", "--ball", "ILB", "--law", "KK", "--num", "2"]
    assert main([*argv, "--json"]) == 0
    out, err = capsys.readouterr()
    assert [s["model"] for s in json.loads(out)["sweeps"]] == ["KK"] and err == ""
    assert main([*argv, "--json", "old.json"]) == 0
    out, err = capsys.readouterr()
    assert out == "" and "--json-out" in err and len(err.strip().splitlines()) == 2
    assert json.loads((tmp_path / "old.json").read_text())["sweeps"][0]["model"] == "KK"
