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
    assert main(["collide", "--law", "Jian", "--alpha", "0.3", "--beta", "0.5", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("e", "tc", "fmax", "xmax", "t_xmax", "residual", "dissipated", "separated"):
        assert key in d
    assert round(d["e"], 4) == 0.7622


def test_collide_overlap_no_rebound_is_valid_json(capsys):
    assert main(["collide", "--law", "LH", "--alpha", "10", "--end", "overlap", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["separated"] is False and d["e"] == 0.0 and d["tc"] is None


def test_collide_plot(tmp_path, capsys):
    out = tmp_path / "c.png"
    assert main(["collide", "--law", "KK", "--alpha", "0.3", "--plot", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_restitution_csv(capsys):
    assert main(["restitution", "--law", "KK", "--alpha", "0.1", "0.2", "0.3", "--csv"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0] == "alpha,e" and len(lines) == 4
    assert round(float(lines[3].split(",")[1]), 4) == 0.7221


def test_restitution_jian_beta_per_alpha(capsys):
    assert main(["restitution", "--law", "Jian", "--alpha", "0.3", "0.3", "--beta", "0", "0.5",
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [round(e, 4) for e in d["e"]] == [0.7221, 0.7622]


def test_calibrate_json(capsys):
    assert main(["calibrate", "--law", "Hunt", "--e", "0.463", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["alpha"] > 0


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["collide", "--law", "Foo", "--alpha", "0.3"], "valid models are"),
        (["collide", "--law", "KK", "--alpha", "abc"], "invalid float value"),
        (["collide", "--law", "KK", "--alpha", "-1"], "alpha must be"),
        (["collide", "--law", "KK", "--alpha", "nan"], "--alpha: must be a finite number"),
        (["collide", "--law", "KK", "--alpha", "0.3", "--beta", "1"], "takes no beta"),
        (["collide", "--law", "Jian", "--alpha", "0.3"], "needs beta"),
        (["collide", "--law", "power", "--alpha", "0.3"], "needs the exponent p"),
        (["collide", "--law", "KK"], "required: --alpha"),
        (["restitution", "--law", "Jian", "--alpha", "0.1", "0.2", "0.3", "--beta", "1", "2"],
         "one --beta or one per --alpha"),
        (["calibrate", "--law", "KK", "--e", "1.5"], "e must be in [1e-06, 1]"),
        (["calibrate", "--law", "Hunt", "--e", "1e-4"], "allowed range"),
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


def test_model_is_a_deprecated_alias_of_law(capsys):
    """``--model`` gives the same result as ``--law`` and one deprecation line on stderr."""
    argv = ["collide", "--alpha", "0.3", "--json"]
    assert main([*argv, "--law", "KK"]) == 0
    new = capsys.readouterr()
    assert main([*argv, "--model", "KK"]) == 0
    old = capsys.readouterr()
    assert old.out == new.out and new.err == ""
    assert old.err.strip().splitlines() == ["note: --model is deprecated; use --law (same meaning)"]


@pytest.mark.parametrize("args, fragment", [
    (["collide", "--alpha", "0.3"], "required: --law"),
    (["collide", "--law", "KK", "--model", "KK", "--alpha", "0.3"], "given twice"),
    (["audit", "--formula", "first-order", "--e", "0.5", "--law", "KK", "--model", "KK"],
     "given twice"),
    (["reproduce", "--no-progress", "--quiet"], "given twice"),
    (["fit", "--example", "--mass", "0.15", "--quiet", "--no-progress"], "given twice"),
])
def test_law_and_progress_words_are_one_option(args, fragment):
    res = run(*args)
    assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1, res.stderr
    assert fragment in res.stderr


def test_audit_first_order_takes_law(capsys):
    argv = ["audit", "--formula", "first-order", "--e", "0.5", "--json"]
    assert main([*argv, "--law", "KK"]) == 0
    new = json.loads(capsys.readouterr().out)
    assert main([*argv, "--model", "KK"]) == 0
    assert json.loads(capsys.readouterr().out) == new


def test_collide_plot_status_goes_to_stderr(tmp_path, capsys):
    """Results on stdout, the status line on stderr: stdout is the same with and without --plot."""
    argv = ["collide", "--law", "KK", "--alpha", "0.3"]
    assert main(argv) == 0
    plain = capsys.readouterr()
    assert main([*argv, "--plot", str(tmp_path / "c.png")]) == 0
    plotted = capsys.readouterr()
    assert plotted.out == plain.out
    assert plotted.err.strip() == f"plot written to {tmp_path / 'c.png'}"
