"""``viscontact fit --restitution/--bounces/--audio``: the JSON object, the outputs and their
protection, the DEM lines, the force fit beside it, and one-line errors for bad input."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.io import wavfile

from viscontact.cli import main
from viscontact.fit.restitution import model_e

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fit"))
from test_audio import RATE, bounce_times, synthetic_recording  # noqa: E402

V = np.array([0.4, 0.6, 0.9, 1.3, 2.0, 3.0])


def table(path, law="KK", noise=2e-3):
    e = model_e(law, V, 1.0, 0.3) + noise * np.sin(5 * V)
    path.write_text("v [cm/s],e\n" + "".join(f"{v * 100:.6g},{x:.8f}\n" for v, x in zip(V, e)))
    return e


def bounce_file(path, e=0.8, n=8, t0=0.6):
    t = np.concatenate([[0.0], np.cumsum(t0 * e ** np.arange(n - 1))])
    path.write_text("\n".join(f"{x:.9f}" for x in t) + "\n")
    return t


def test_json_restitution_object(tmp_path, capsys):
    f = tmp_path / "e.csv"
    e = table(f)
    assert main(["fit", "--restitution", str(f), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)["restitution"]
    np.testing.assert_allclose(d["data"]["v"], V)
    np.testing.assert_allclose(d["data"]["e"], e, atol=1e-8)
    assert d["rejected"] == [] and d["impacts"] == []
    assert set(d["laws"]) == {"LH", "Ts", "KK", "Li", "Hunt", "Jian", "power"}
    for law in d["laws"].values():
        for key in ("rms", "e_fit", "alpha", "alpha_err", "aicc", "loo"):
            assert key in law
        assert len(law["e_fit"]) == V.size
        rms = np.sqrt(np.mean((np.array(law["e_fit"]) - np.array(d["data"]["e"])) ** 2))
        assert law["rms"] == pytest.approx(rms, rel=1e-9)
    aicc = [d["laws"][k]["aicc"] for k in d["ranking"]]
    assert aicc == sorted(aicc) and d["ranking"][0] in ("KK", "Jian", "power")
    assert d["dem"]["law"] == d["ranking"][0]


def test_terminal_table_and_dem_lines(tmp_path, capsys):
    f = tmp_path / "e.csv"
    table(f)
    assert main(["fit", "--restitution", str(f), "--dem-law", "KK", "--mass", "0.05",
                 "--radius", "0.02", "--E", "1e7", "--nu", "0.4"]) == 0
    out = capsys.readouterr().out
    assert "e(v): 6 points" in out and "DEM input for KK" in out
    pair = next(ln for ln in out.splitlines() if "pair_coeff * *" in ln)
    assert "damping KK alpha" in pair and "vref" in pair and "hertz/material" in pair
    assert "sphere-sphere contacts inherit" in out
    assert "N s/m^1.5" in out  # c with the pair known


def test_bounces_out_dir_and_overwrite(tmp_path, capsys):
    a, b = tmp_path / "drop1.txt", tmp_path / "drop2.txt"
    bounce_file(a)
    bounce_file(b, e=0.78, t0=0.55)
    out = tmp_path / "out"
    argv = ["fit", "--bounces", str(a), str(b), "--no-drag", "--laws", "KK", "Ts", "--out",
            str(out), "--quiet"]
    assert main(argv) == 0
    d = json.loads((out / "fit.json").read_text())["restitution"]
    assert len(d["impacts"]) == 2 and len(d["data"]["v"]) == 12
    for name in ("restitution.png", "bounces.png"):
        assert (out / name).stat().st_size > 10_000
    capsys.readouterr()
    assert main(argv) == 2  # no overwrite without --force
    assert "--force" in capsys.readouterr().err
    assert main(argv + ["--force"]) == 0


def test_audio_impacts_printed_and_plotted(tmp_path, capsys):
    times = bounce_times()
    x = synthetic_recording(times, click_at=times[3] + 0.4 * (times[4] - times[3]))
    wav = tmp_path / "drop.wav"
    wavfile.write(wav, int(RATE), (x / np.max(np.abs(x)) * 30000).astype(np.int16))
    out = tmp_path / "out"
    assert main(["fit", "--audio", str(wav), "--no-drag", "--laws", "KK", "--out", str(out),
                 "--quiet"]) == 0
    text = capsys.readouterr().out
    assert f"{times.size} impacts found" in text
    d = json.loads((out / "fit.json").read_text())["restitution"]
    np.testing.assert_allclose(d["impacts"][0], times, atol=1e-4)
    assert (out / "audio_1_drop.png").stat().st_size > 10_000


def test_force_recording_and_restitution_together(tmp_path, capsys):
    f = tmp_path / "e.csv"
    table(f)
    assert main(["fit", "--example", "--mass", "0.1547", "--radius", "0.03175",
                 "--drop-height", "0.15", "--laws", "KK", "--restitution", str(f), "--json",
                 "--quiet"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert "measured" in d and d["laws"][0]["law"] == "KK"  # the force fit's keys as before
    assert list(d["restitution"]["laws"]) == ["KK"]


@pytest.mark.parametrize("setup, expected", [
    (lambda p: p.write_text(""), "no rows of numbers"),
    (lambda p: p.write_text("v,e\n1,0.8\n"), "1 point"),
    (lambda p: p.write_text("v,e\n1,0.8\n2,1.5\n"), "e must lie in (0, 1]"),
    (lambda p: p.write_text("v,e\n1,0.8\n-2,0.5\n"), "finite number > 0"),
])
def test_bad_restitution_one_line(tmp_path, capsys, setup, expected):
    p = tmp_path / "bad.csv"
    setup(p)
    assert main(["fit", "--restitution", str(p), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and expected in err, err


def test_bad_options_one_line(tmp_path, capsys):
    drop = tmp_path / "d.txt"
    bounce_file(drop)
    bad_times = tmp_path / "t.txt"
    bad_times.write_text("0\n0.5\n0.4\n0.8\n")
    silent = tmp_path / "silent.wav"
    wavfile.write(silent, 8000, (np.random.default_rng(0).standard_normal(8000) * 50
                                 ).astype(np.int16))
    f = tmp_path / "e.csv"
    table(f)
    for argv, expected in (
        (["--bounces", str(drop)], "needs the ball's --mass and --radius (or --no-drag"),
        (["--bounces", str(bad_times), "--no-drag"], "not increasing"),
        (["--audio", str(silent), "--no-drag"], "found; a (v, e) point needs three"),
        (["--restitution", str(f), "--E", "1e7", "--nu", "0.3"], "need the ball's --mass"),
        (["--restitution", str(f), "--dem-law", "Foo"], "unknown model 'Foo'"),
        (["--restitution", str(f), "--laws", "KK", "--dem-law", "Ts"], "was not fitted"),
        ([], "give one or more recordings"),
        (["--example", "--drop-height", "0.15"], "force recordings need the ball's --mass"),
    ):
        assert main(["fit", *argv, "--quiet"]) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and expected in err, (argv, err)


def test_m4a_without_a_decoder(tmp_path, capsys, monkeypatch):
    m4a = tmp_path / "drop.m4a"
    m4a.write_bytes(b"\x00\x00\x00\x18ftypM4A ")
    monkeypatch.setattr("shutil.which", lambda name: None)
    assert main(["fit", "--audio", str(m4a), "--no-drag", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "convert it to WAV first" in err


def test_bounces_with_the_laws_own_contact_time(tmp_path, capsys):
    """A soft ball (KK, fixed c) bouncing without drag: each interval is the exact contact
    (viscontact.impact) plus the flight 2u/g.  With E and nu the reduction takes off the
    best law's own t_c(v) and gives the true (v, e) back (from the second point: the first
    impact's speed, so its contact time, is unknown)."""
    import viscontact as vc
    from viscontact.physics.pair import contact_pair

    m, r, E, nu, c = 0.05, 0.02, 1e6, 0.3, 20.0
    k = contact_pair(m, radius=r, modulus=E, poisson=nu).k_hertz
    v, t, times, truth = 3.0, 0.0, [0.0], []  # impact 0 at t = 0 with speed v
    for _ in range(9):
        hit = vc.impact("KK", m_eff=m, k_hertz=k, v=v, c=c, history=False)
        truth.append((v, hit.e))
        u = hit.e * v
        t += hit.tc + 2 * u / 9.81  # this impact's contact, then the flight
        times.append(t)
        v = u
    f = tmp_path / "drop.txt"
    f.write_text("\n".join(f"{x:.15f}" for x in times) + "\n")
    assert main(["fit", "--bounces", str(f), "--no-drag", "--mass", str(m), "--radius", str(r),
                 "--E", str(E), "--nu", str(nu), "--laws", "KK", "Ts", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)["restitution"]
    assert any("its own t_c(v)" in n for n in d["notes"])
    # point j is impact j + 1; the first uses impact 0's contact time, taken at a guessed speed
    np.testing.assert_allclose(d["data"]["v"][1:], [p[0] for p in truth[2:]], atol=1e-6)
    np.testing.assert_allclose(d["data"]["e"][1:], [p[1] for p in truth[2:]], atol=1e-6)
