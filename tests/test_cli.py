"""The command line: help, JSON, CSV, plots, and one-line errors with exit 2."""

import json
import subprocess
import sys

import pytest

from viscontact.cli import build_parser, main


def run(*args):
    return subprocess.run([sys.executable, "-m", "viscontact", *args], capture_output=True, text=True)


def command_names():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    return list(sub.choices)


def test_every_command_has_help(capsys):
    for name in [None, *command_names()]:
        argv = ([name] if name else []) + ["--help"]
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 0
        assert "usage:" in capsys.readouterr().out


def test_collide_json_keys(capsys):
    assert main(["collide", "--model", "Jian", "--alpha", "0.3", "--beta", "0.5", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("e", "tc", "fmax", "xmax", "t_xmax", "residual", "dissipated", "separated"):
        assert key in d
    assert round(d["e"], 4) == 0.7622


def test_collide_overlap_no_rebound_is_valid_json(capsys):
    assert main(["collide", "--model", "LH", "--alpha", "10", "--end", "overlap", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["separated"] is False and d["e"] == 0.0 and d["tc"] is None


def test_collide_plot(tmp_path, capsys):
    out = tmp_path / "c.png"
    assert main(["collide", "--model", "KK", "--alpha", "0.3", "--plot", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_restitution_csv(capsys):
    assert main(["restitution", "--model", "KK", "--alpha", "0.1", "0.2", "0.3", "--csv"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0] == "alpha,e" and len(lines) == 4
    assert round(float(lines[3].split(",")[1]), 4) == 0.7221


def test_restitution_jian_beta_per_alpha(capsys):
    assert main(["restitution", "--model", "Jian", "--alpha", "0.3", "0.3", "--beta", "0", "0.5",
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [round(e, 4) for e in d["e"]] == [0.7221, 0.7622]


def test_calibrate_json(capsys):
    assert main(["calibrate", "--model", "Hunt", "--e", "0.463", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["alpha"] > 0


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["collide", "--model", "Foo", "--alpha", "0.3"], "valid models are"),
        (["collide", "--model", "KK", "--alpha", "abc"], "invalid float value"),
        (["collide", "--model", "KK", "--alpha", "-1"], "alpha must be"),
        (["collide", "--model", "KK", "--alpha", "nan"], "--alpha: must be a finite number"),
        (["collide", "--model", "KK", "--alpha", "0.3", "--beta", "1"], "takes no beta"),
        (["collide", "--model", "Jian", "--alpha", "0.3"], "needs beta"),
        (["collide", "--model", "power", "--alpha", "0.3"], "needs the exponent p"),
        (["collide", "--model", "KK"], "required: --alpha"),
        (["restitution", "--model", "Jian", "--alpha", "0.1", "0.2", "0.3", "--beta", "1", "2"],
         "one --beta or one per --alpha"),
        (["calibrate", "--model", "KK", "--e", "1.5"], "e must be in [1e-06, 1]"),
        (["calibrate", "--model", "Hunt", "--e", "1e-4"], "allowed range"),
        (["frobnicate"], "invalid choice"),
    ],
)
def test_user_mistakes_exit_2_with_one_line(args, fragment):
    res = run(*args)
    assert res.returncode == 2
    assert "Traceback" not in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1, res.stderr
    assert fragment in res.stderr


def test_console_script_and_module_agree():
    res = run("--version")
    assert res.returncode == 0 and "viscontact" in res.stdout
