"""``viscontact fit``: JSON keys, outputs, the README example, and one-line errors for bad files."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import run_cli

from viscontact.calibration.inverse import alpha_from_e
from viscontact.cli import main
from viscontact.fit.synthetic import synthetic_recording, write_recording

M, K = 0.1547, 1.688e6
BALL = ["--mass", "0.1547", "--radius", "0.03175"]


def synthetic_file(path, law="Jian", v=1.716, **kw):
    beta = 0.5 if law == "Jian" else None
    alpha = float(alpha_from_e(law, 0.463, beta=beta))
    syn = synthetic_recording(law, alpha, beta=beta, m_eff=M, k_hertz=K, v=v, offset=1.5, **kw)
    write_recording(path, syn, ["synthetic test recording"])
    return syn


def test_json_keys_and_order(capsys):
    code = main(["fit", "--example", *BALL, "--drop-height", "0.15", "--laws", "KK", "Jian",
                 "--json"])
    assert code == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("e", "tc", "fmax", "dmax", "k_hertz"):
        assert isinstance(d["measured"][key], float)
    assert 0.4 < d["measured"]["e"] < 0.5 and 3e-3 < d["measured"]["tc"] < 4.5e-3  # SI units
    laws = d["laws"]
    assert [x["law"] for x in laws] == ["Jian", "KK"]  # the example is a Jian impact
    for x in laws:
        for key in ("law", "alpha", "beta", "p", "c", "tau", "rms"):
            assert key in x
        assert x["p"] is None  # fixed exponents are not fitted
    assert laws[1]["beta"] is None and laws[1]["tau"] is None
    assert laws[0]["rms"] < laws[1]["rms"]


def test_several_recordings_global_fit_and_plots(tmp_path, capsys):
    a, b = tmp_path / "low.csv", tmp_path / "high.csv"
    synthetic_file(a, v=1.2, seed=1)
    synthetic_file(b, v=2.2, seed=2)
    out = tmp_path / "out"
    code = main(["fit", str(a), str(b), *BALL, "--velocity", "1.2", "2.2", "--laws", "Jian",
                 "--out", str(out), "--quiet"])
    assert code == 0
    text = capsys.readouterr().out
    assert "global fit over 2 recordings" in text
    d = json.loads((out / "fit.json").read_text())
    assert [r["file"] for r in d["recordings"]] == [str(a), str(b)]
    assert d["global"][0]["law"] == "Jian" and len(d["global"][0]["points"]) == 2
    for name in ("fit_low.png", "fit_high.png", "global.png"):
        assert (out / name).stat().st_size > 10_000


def test_readme_example_runs():
    proc = run_cli("fit", "--example", *BALL, "--drop-height", "0.15")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert "measured: e = 0.46" in proc.stdout
    assert lines[3].split()[:2] == ["1", "Jian"]


def _bad(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def _clipped(tmp_path):
    p = tmp_path / "clipped.csv"
    syn = synthetic_file(p)
    top = 0.8 * syn.truth.fmax
    syn.force = np.minimum(syn.force, top)
    write_recording(p, syn, ["clipped at 80 % of the peak"])
    return p


def _noise_only(tmp_path):
    rng = np.random.default_rng(0)
    return _bad(tmp_path, "quiet.csv", "time [ms],force [N]\n" + "\n".join(
        f"{0.02 * i:.3f},{2 + rng.normal():.3f}" for i in range(300)))


def _negative(tmp_path):
    p = tmp_path / "negative.csv"
    syn = synthetic_file(p)
    syn.force = -syn.force
    write_recording(p, syn, ["compression recorded as negative"])
    return p


def _slow(tmp_path):
    p = tmp_path / "slow.csv"
    synthetic_file(p, rate=2e3, pre=0.01, post=0.01)
    return p


@pytest.mark.parametrize("make,expected", [
    (lambda d: _bad(d, "onecol.csv", "time\n0\n1\n2\n"), "onecol.csv: line 1: no force column"),
    (lambda d: _bad(d, "short.csv", "0,1\n0.1,2\n0.2\n"), "short.csv: line 3: 1 column(s), need 2"),
    (lambda d: _bad(d, "text.csv", "t,F\n0,1\n0.1,abc\n"), "text.csv: line 3: non-numeric value 'abc'"),
    (lambda d: _bad(d, "back.csv", "t,F\n0,1\n0.2,2\n0.1,3\n"),
     "back.csv: line 4: time 0.1 does not increase (previous sample: line 3)"),
    (lambda d: _bad(d, "empty.csv", "# nothing\n"), "empty.csv: 0 samples"),
    (lambda d: _bad(d, "units.csv", "time [min],force [N]\n" + "\n".join(
        f"{i},{i}" for i in range(20))), "units.csv: unknown time unit 'min'"),
    (_noise_only, "quiet.csv: no contact found"),
    (_slow, "slow.csv: only"),
    (_clipped, "the force plate saturates"),
    (_negative, "give compression as positive"),
])
def test_bad_files_exit_2_with_one_line(tmp_path, capsys, make, expected):
    path = make(tmp_path)
    code = main(["fit", str(path), *BALL, "--velocity", "1.716", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("viscontact fit: error: ")
    assert expected in err
    assert path.name in err


def test_bad_options_exit_2(tmp_path, capsys):
    p = tmp_path / "ok.csv"
    synthetic_file(p)
    for argv, expected in (
        ([str(p), *BALL], "give the impact speed"),
        ([str(p), *BALL, "--velocity", "1", "2"], "one per recording (1 recordings, 2 speeds)"),
        ([str(p), *BALL, "--velocity", "1", "--drop-height", "0.1"], "not both"),
        ([str(p), "--mass", "-1", "--velocity", "1"], "--mass must be a finite number > 0"),
        ([str(p), *BALL, "--velocity", "1.7", "--laws", "Foo"], "unknown model 'Foo'"),
        ([str(tmp_path / "missing.csv"), *BALL, "--velocity", "1"], "missing.csv"),
        ([*BALL, "--velocity", "1"], "give one or more recordings"),
    ):
        assert main(["fit", *argv, "--quiet"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and expected in err, err


def test_time_unit_mistake_is_recognised(tmp_path, capsys):
    """A recording in ms without a header, read as seconds, gives e = 1465 and a negative
    residual overlap: refused with one line naming --time-unit ms; with it, the fit runs."""
    from viscontact.fit.synthetic import example_recording

    rows = [ln for ln in example_recording().read_text().splitlines()
            if ln and not ln.startswith("#")][1:]  # no comments, no header: read as s, N
    p = tmp_path / "noheader.csv"
    p.write_text("\n".join(rows) + "\n")
    argv = ["fit", str(p), *BALL, "--drop-height", "0.15", "--laws", "KK", "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "e = 1465" in err
    assert "reads right with --time-unit ms" in err
    assert main(argv + ["--time-unit", "us"]) == 2  # too small an impulse: never reverses
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "reads right with --time-unit ms" in err
    assert main(argv + ["--time-unit", "ms", "--json"]) == 0
    assert 0.4 < json.loads(capsys.readouterr().out)["measured"]["e"] < 0.5


def test_out_follows_the_file_rule(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "fit.json").write_text("the user's own\n")
    argv = ["fit", "--example", *BALL, "--drop-height", "0.15", "--laws", "KK", "--quiet",
            "--out", str(out)]
    for extra in ([], ["--force"]):
        assert main(argv + extra) == 2
        assert "holds no earlier output" in capsys.readouterr().err
    assert [p.name for p in out.iterdir()] == ["fit.json"]
    assert (out / "fit.json").read_text() == "the user's own\n"
    (out / "fit.json").unlink()
    assert main(argv) == 0  # an empty directory
    assert main(argv) == 2 and "--force" in capsys.readouterr().err
    assert main(argv + ["--force"]) == 0
    assert sorted(p.name for p in out.iterdir()) == [".viscontact-output.json", "fit.json",
                                                     "fit_example_drop.png"]
