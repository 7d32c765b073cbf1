"""Calibration audit: engine presets, the report and the ``audit`` command (the formulas:
test_formulas.py).

Kept to a few dozen exact solves (the reference solver does ~100 collisions/s).
"""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

import viscontact as vc
from viscontact.audit import formulas as F
from viscontact.audit import report
from viscontact.audit.engines import ENGINES, PRESETS, audit_engine, get_preset
from viscontact.physics.pair import ContactPair
from viscontact.cli import main

PHYS = ContactPair(m_eff=0.1547, r_eff=0.03175, k_hertz=1.688e6, v=1.716)  # indoor lacrosse ball


# ------------------------------------------------------------------------------ engines
def test_physical_time_scale_and_validation():
    p = ContactPair.from_effective(m_eff=0.1547, r_eff=0.03175, k_hertz=1.688e6, v=1.716)
    assert p.T == pytest.approx((0.1547**2 / (1.688e6**2 * 1.716)) ** 0.2, rel=1e-14)
    assert p.at(1.716 / 32).T == pytest.approx(2 * p.T, rel=1e-12)
    q = ContactPair.from_effective(m_eff=1.0, r_eff=0.04, e_eff=3.0, v=1.0)
    assert q.k_hertz == pytest.approx(4 / 3 * 3.0 * 0.2)
    with pytest.raises(ValueError, match="exactly one"):
        ContactPair.from_effective(m_eff=1, r_eff=1, v=1)
    with pytest.raises(ValueError, match=r"m_eff must be in \[1e-24, 1e\+12\] kg, got -1"):
        ContactPair(m_eff=-1, r_eff=1, k_hertz=1, v=1)
    with pytest.raises(ValueError, match="impact speed"):
        ContactPair(m_eff=1, k_hertz=1).T
    with pytest.raises(ValueError, match="physical units"):  # a dashpot needs R* and v
        get_preset("lammps", "viscoelastic").to_alpha(1.0, ContactPair(m_eff=1, k_hertz=1, r_eff=1))


@pytest.mark.parametrize("key", sorted(PRESETS))
def test_preset_mapping_roundtrip_and_docs(key):
    pre = PRESETS[key]
    assert pre.source and pre.mapping and pre.model in vc.LAWS
    phys = PHYS if pre.needs_physical else None
    for alpha in (0.1, 0.3, 0.9):
        if pre.option.startswith("tsuji") and alpha > pre.to_alpha(1e-12, None):
            continue
        x = pre.from_alpha(alpha, phys)
        assert pre.to_alpha(x, phys) == pytest.approx(alpha, rel=1e-10)


def test_speed_dependent_alpha_of_physical_dashpots():
    """Fixed physical c: LH alpha ~ T, KK alpha ~ 1/T, and T ~ v^(-1/5)
    (T = (m*^2/(k_Hertz^2 v))^(1/5))."""
    slow = PHYS.at(PHYS.v / 32)
    assert slow.T / PHYS.T == pytest.approx(2.0, rel=1e-12)
    for opt, ratio in (("velocity", 2.0), ("mass_velocity", 2.0), ("viscoelastic", 0.5)):
        pre = get_preset("lammps", opt)
        assert pre.to_alpha(1.0, slow) / pre.to_alpha(1.0, PHYS) == pytest.approx(ratio, rel=1e-12)


def test_engine_end_criteria():
    assert audit_engine("lammps", "coeff_restitution", 0.7).end == "overlap"
    assert audit_engine("lammps", "coeff_restitution", 0.7, clamp=True).end == "force"
    assert audit_engine("liggghts", None, 0.7, clamp=True).end == "force"
    assert audit_engine("chrono", None, 0.7).end == "force"
    assert audit_engine("yade", None, 0.7).end == "force"
    assert audit_engine("mercurydpm", None, 0.7).end == "overlap"
    assert audit_engine("demengine", None, 0.7).end == "overlap"
    with pytest.raises(ValueError, match="no clamp switch"):
        audit_engine("chrono", None, 0.7, clamp=False)


# ------------------------------------------------------------- Thornton 2013 and versions
def test_thornton_fit_is_made_for_the_zero_force_end():
    """Thornton et al. 2013 fitted gamma(e) (eqs. B6-B7) to the clamped (zero-force) Hertz
    contact: with alpha = sqrt(6) gamma the exact solve gives back e to 3e-4 over 0.05-0.9;
    above 0.9 the fit drifts (0.95 delivers 0.948, 0.99 delivers 0.979), and for zero overlap
    it is far off."""
    for e in (0.05, 0.1, 0.25, 0.3, 0.5, 0.7, 0.9):
        a = F.thornton_alpha(e)
        assert a == pytest.approx(math.sqrt(6) * F.thornton_gamma(e), rel=1e-15)
        assert vc.restitution("Ts", a, end="force") == pytest.approx(e, abs=3e-4)
    assert vc.restitution("Ts", F.thornton_alpha(0.95), end="force") < 0.95 - 1e-3
    assert vc.restitution("Ts", F.thornton_alpha(0.99), end="force") < 0.98
    assert vc.restitution("Ts", F.thornton_alpha(0.3), end="overlap") < 0.2
    assert F.thornton_alpha(1.0) == 0.0  # Yade: en = 1 means no damping (the fit's limit is not 0)
    assert F.thornton_gamma(1 - 1e-9) == pytest.approx(0.00453, abs=1e-5)
    es = np.linspace(1e-4, 1 - 1e-9, 20001)
    assert np.all(np.diff([F.thornton_gamma(e) for e in es]) < 0)  # the inverse relies on it


def test_engine_versions_pick_the_mapping():
    cur, old = audit_engine("yade", None, 0.3), audit_engine("yade", None, 0.3, version="2022.01a")
    assert audit_engine("yade", None, 0.3, version="2023.02a") == cur
    assert cur.delivered_e == pytest.approx(0.3002, abs=1e-4)  # Thornton: what Yade 2023.02a delivers
    assert old.delivered_e == pytest.approx(0.3971, abs=1e-4)  # Antypov-Elliott, zero force
    assert old.input_for_target == pytest.approx(0.16522, abs=1e-5)
    assert "2023.02a" in cur.versions and "2022.01a" in old.versions
    assert get_preset("yade", version="2020.01a").until == "2022.01a"
    kr = audit_engine("kratos", None, 0.6)
    assert kr.delivered_e == pytest.approx(cur_e := audit_engine("yade", None, 0.6).delivered_e, abs=1e-15)
    assert abs(cur_e - 0.6) < 1e-4
    for p in PRESETS.values():  # every preset says which versions, whether they were run, its wall
        ran = p.versions.endswith("run)") and "not run" not in p.versions
        assert p.checked.startswith("run:" if ran else "source only"), p.key
        assert "E*" in p.spring and "R*" in p.spring, p.key  # the Hertz spring it uses
        assert bool(p.wall) == (p.wall_r_factor is not None), p.key  # a wall radius in words
    assert get_preset("yade").wall_r_factor == 0.5 and get_preset("liggghts").wall_r_factor == 1.0
    assert get_preset("kratos").wall_r_factor == 1.0
    with pytest.raises(ValueError, match="no preset for version"):
        get_preset("liggghts", version="2.3")
    with pytest.raises(ValueError, match="not a release number"):
        get_preset("yade", version="latest")


def test_thornton_engines_near_e_1():
    """Kratos: e > 0.999 means no damping (delivers 1), e < 0.001 is taken as 0.001; Yade
    2023.02a: only e = 1 is undamped, 0.9999 still delivers about 0.984."""
    assert audit_engine("kratos", None, 0.9995).delivered_e == 1.0
    assert get_preset("kratos").to_alpha(1e-5, None) == get_preset("kratos").to_alpha(0.001, None)
    assert audit_engine("yade", None, 0.9999).delivered_e == pytest.approx(0.984, abs=1e-3)
    r = audit_engine("yade", None, 0.99)
    assert r.input_for_target is None and "Thornton fit" in r.note
    inp = audit_engine("kratos", None, 0.5).input_for_target
    assert vc.restitution("Ts", get_preset("kratos").to_alpha(inp, None), end="force") == pytest.approx(0.5, abs=1e-9)


def test_engine_audit_delivered_and_input_for_target():
    plain = audit_engine("lammps", "coeff_restitution", 0.5)
    assert plain.delivered_e == pytest.approx(0.5, abs=1e-8)  # exact without limit_damping
    assert plain.input_for_target == pytest.approx(0.5, abs=1e-9)
    lim = audit_engine("lammps", "coeff_restitution", 0.5, clamp=True)
    assert lim.delivered_e > 0.54
    pre = get_preset("lammps", "coeff_restitution")
    assert pre.to_alpha(lim.input_for_target, None) == pytest.approx(lim.exact_alpha, rel=1e-12)
    assert vc.restitution("Ts", lim.exact_alpha) == pytest.approx(0.5, abs=1e-9)


def test_engine_physical_and_value():
    with pytest.raises(ValueError, match="physical units"):
        audit_engine("lammps", "velocity", 0.5)
    r = audit_engine("lammps", "velocity", 0.5, physical=PHYS, clamp=True)
    assert r.T == pytest.approx(PHYS.T)
    assert r.input_for_target == pytest.approx(r.exact_alpha * PHYS.m_eff / PHYS.T)
    given = audit_engine("lammps", "mass_velocity", 0.5, physical=PHYS, value=200.0)
    assert given.alpha == pytest.approx(200.0 * PHYS.T)
    with pytest.raises(ValueError, match=">= 0"):
        audit_engine("lammps", "mass_velocity", 0.5, physical=PHYS, value=-1.0)


def test_engine_unreachable_input():
    # the LAMMPS Tsuji curve tops out at alpha = 1.2728: no e typed gives target 0.05 (clamped)
    r = audit_engine("lammps", "tsuji", 0.05, clamp=True)
    assert r.input_for_target is None and "no input" in r.note


def test_engine_value_beyond_the_domain_delivers_none():
    """eta_n0 = 1e308 kg/s is alpha = eta_n0 T / m* ~ 1e306: no delivered e (None, not NaN)."""
    r = audit_engine("lammps", "velocity", 0.7, physical=PHYS, value=1e308)
    assert r.alpha == pytest.approx(1e308 * PHYS.T / PHYS.m_eff, rel=1e-12)
    assert r.delivered_e is None and r.error is None
    assert "outside the domain [0, 1000]" in r.note
    assert r.input_for_target == pytest.approx(r.exact_alpha * PHYS.m_eff / PHYS.T)


def test_engine_lookup_errors():
    with pytest.raises(ValueError, match="unknown engine"):
        get_preset("gromacs")
    with pytest.raises(ValueError, match="needs a damping option"):
        get_preset("lammps")
    with pytest.raises(ValueError, match="no damping option"):
        get_preset("lammps", "hooke")
    assert get_preset("LAMMPS", "coeff-restitution").option == "coeff_restitution"
    assert set(ENGINES) == {"lammps", "liggghts", "mercurydpm", "chrono", "demengine", "yade", "kratos"}


# ------------------------------------------------------------------------------- report
def test_report_small_grid(tmp_path):
    paths = report.write_all(str(tmp_path), grid=(0.5,), physical=PHYS, plots=True)
    names = {p.split("/")[-1] for p in paths}
    assert names == {"formulas.csv", "formulas.md", "formulas.png", "engines.csv", "engines.md",
                     "engines.png", "summary.md"}
    rows = list(csv.DictReader(open(tmp_path / "formulas.csv")))
    assert len(rows) == 2 * len(F.FORMULAS)
    assert {"formula", "target_e", "alpha", "delivered_e", "error", "exact_alpha"} <= set(rows[0])
    erows = list(csv.DictReader(open(tmp_path / "engines.csv")))
    assert len(erows) == len(report.engine_settings())
    summary = (tmp_path / "summary.md").read_text()
    for name in F.FORMULAS:
        assert f"| {name} |" in summary
    assert "lammps coeff_restitution +limit_damping" in summary


# ---------------------------------------------------------------------------------- CLI
def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_cli_formula_json(capsys):
    d = _json(capsys, ["audit", "--formula", "lankarani-nikravesh", "--e", "0.5", "--json"])
    assert {"target_e", "alpha", "delivered_e", "exact_alpha", "error", "end"} <= set(d)
    assert d["alpha"] == 0.5625 and d["end"] == "force"
    d = _json(capsys, ["audit", "--formula", "antypov-elliott", "--e", "0.5", "--end", "overlap", "--json"])
    assert d["delivered_e"] == pytest.approx(0.5, abs=1e-8)


def test_cli_engine_json(capsys):
    d = _json(capsys, ["audit", "--engine", "lammps", "--damping", "coeff_restitution", "--e", "0.7",
                       "--limit-damping", "--json"])
    assert {"target_e", "alpha", "delivered_e", "exact_alpha", "input_for_target"} <= set(d)
    assert d["end"] == "force" and d["delivered_e"] > 0.7
    d = _json(capsys, ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff",
                       "0.1547", "--r-eff", "0.03175", "--k-hertz", "1.688e6", "--v", "1.716", "--json"])
    assert d["T"] == pytest.approx(PHYS.T) and d["input_for_target"] > 0


def test_cli_text_and_all(capsys, tmp_path):
    assert main(["audit", "--engine", "liggghts", "--e", "0.5", "--limit-force"]) == 0
    out = capsys.readouterr().out
    assert "type instead" in out and "zero force" in out
    assert main(["audit", "--engine", "yade", "--e", "0.3", "--engine-version", "2022.01a"]) == 0
    out = capsys.readouterr().out
    assert "up to 2022.01a" in out and "R* = R/2" in out and "0.1652" in out
    assert main(["audit", "--all", "--out", str(tmp_path / "r"), "--grid", "0.9", "--no-plots"]) == 0
    assert (tmp_path / "r" / "summary.md").exists()


@pytest.mark.parametrize("argv", [
    ["audit", "--formula", "nope", "--e", "0.5"],
    ["audit", "--formula", "gonthier", "--e", "1.5"],
    ["audit", "--formula", "gonthier"],
    ["audit", "--formula", "gonthier", "--e", "0.5", "--limit-damping"],
    ["audit", "--engine", "lammps", "--e", "0.5"],
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.5"],
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.5", "--m-eff", "1"],
    ["audit", "--engine", "chrono", "--e", "0.5", "--limit-damping"],
    ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "0.5", "--limit-force"],
    ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "0.5", "--end", "force"],
    ["audit", "--all", "--e", "0.5"],
    ["audit", "--engine", "yade", "--e", "0.5", "--engine-version", "foo"],
    ["audit", "--engine", "liggghts", "--e", "0.5", "--engine-version", "2.3"],
    ["audit", "--formula", "gonthier", "--e", "0.5", "--engine-version", "2023.02a"],
    ["audit", "--all", "--engine-version", "2023.02a"],
    ["audit", "--all", "--grid", "2"],
    ["audit", "--e", "0.5"],
    ["audit", "--formula", "gonthier", "--engine", "lammps", "--e", "0.5"],
])
def test_cli_bad_input_one_line_exit_2(capsys, argv):
    with pytest.raises(SystemExit) if argv in (["audit", "--e", "0.5"],
                                                ["audit", "--formula", "gonthier", "--engine", "lammps",
                                                 "--e", "0.5"]) else _NoRaise() as ctx:
        rc = main(argv)
    if ctx is not None and getattr(ctx, "value", None) is not None:
        rc = ctx.value.code
    assert rc == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


class _NoRaise:
    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False


def test_default_grid_spans_the_issue():
    assert report.DEFAULT_GRID[0] == 0.05 and report.DEFAULT_GRID[-1] == 0.99
    assert all(e in report.DEFAULT_GRID for e in report.SUMMARY_E)
