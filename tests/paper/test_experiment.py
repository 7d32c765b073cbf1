"""The lacrosse-ball data file and the study's calibration workflow
(docs/reproduce.md, "The drop tests" and "Calibrating a particle in physical units")."""

import json

import pytest

import viscontact as vc
from viscontact.cli import main
from viscontact.paper.experiment import ball, calibrate_ball, calibrate_physical, data_source, load_balls


def test_data_file_states_its_source_and_values():
    assert "Powder Technology 356 (2019)" in data_source()
    assert "10.1016/j.powtec.2019.08.110" in data_source()
    b = load_balls()
    assert set(b) == {"ILB", "OLB"}
    ilb, olb = b["ILB"], b["OLB"]
    assert (ilb.mass, ilb.radius, ilb.v_in, ilb.e, ilb.tc, ilb.k_hertz, ilb.beta) == pytest.approx(
        (0.1547, 0.03175, 1.716, 0.463, 3.83e-3, 1.688e6, 0.5))
    assert (olb.mass, olb.v_out, olb.e, olb.tc, olb.k_hertz, olb.beta) == pytest.approx(
        (0.1472, 1.482, 0.864, 4.15e-3, 1.724e6, 2.0))
    # e = v_o / v_i to the published 3 decimals; a 15 cm drop gives 171.6 cm/s
    for x in (ilb, olb):
        assert x.v_out / x.v_in == pytest.approx(x.e, abs=6e-4)
        assert vc.drop_speed(x.drop_height) == pytest.approx(x.v_in, abs=1e-3)
    assert ball("olb") is olb
    with pytest.raises(ValueError, match="known balls"):
        ball("tennis")


@pytest.mark.parametrize("key", ["ILB", "OLB"])
def test_calibration_workflow(key):
    b = ball(key)
    cals = calibrate_ball(b)
    assert list(cals) == list(vc.STUDY_MODELS)
    T = (b.mass**2 / (b.k_hertz**2 * b.v_in)) ** 0.2
    for m, cal in cals.items():
        assert cal.T == pytest.approx(T, rel=1e-14)
        beta = b.beta if m == "Jian" else None
        assert vc.restitution(m, cal.alpha, beta=beta) == pytest.approx(b.e, abs=1e-9)
        assert cal.c == pytest.approx(vc.damping_coefficient(m, cal.alpha, m_eff=b.mass,
                                                             k_hertz=b.k_hertz, v=b.v_in))
        r = vc.impact(m, m_eff=b.mass, k_hertz=b.k_hertz, v=b.v_in, c=cal.c, tau=cal.tau,
                      history=False)
        assert r.e == pytest.approx(b.e, abs=1e-9)
    assert cals["Jian"].tau == pytest.approx(b.beta * T)
    assert cals["LH"].c == pytest.approx(cals["LH"].alpha * b.mass / T)


def test_calibrate_physical_rejects_bad_input():
    with pytest.raises(ValueError):
        calibrate_physical("KK", 1.2, m_eff=0.1, k_hertz=1e6, v=1.0)
    with pytest.raises(ValueError):
        calibrate_physical("Jian", 0.5, m_eff=0.1, k_hertz=1e6, v=1.0)  # no beta
    with pytest.raises(ValueError):
        calibrate_physical("KK", 0.5, m_eff=0.1, k_hertz=1e6, v=0.0)


def test_cli_calibrate_ball_json(capsys):
    assert main(["calibrate", "--ball", "ILB", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["T"] == pytest.approx(1.373864e-3, rel=1e-6)
    laws = {d["model"]: d for d in out["laws"]}
    assert set(laws) == set(vc.STUDY_MODELS)
    assert laws["Jian"]["tau"] == pytest.approx(0.5 * out["T"])


def test_cli_calibrate_physical_text(capsys):
    # E and nu with the radius instead of k_Hertz; drop height instead of v
    assert main(["calibrate", "--mass", "0.15", "--radius", "0.03", "--E", "5e6", "--nu", "0.45",
                 "--drop-height", "0.15", "--e", "0.6", "--beta", "1"]) == 0
    out = capsys.readouterr().out
    assert "time scale T" in out
    for m in vc.STUDY_MODELS:
        assert f"\n{m} " in out


def test_cli_calibrate_nondimensional_still_works(capsys):
    assert main(["calibrate", "--model", "Ts", "--e", "0.5", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["alpha"] == pytest.approx(
        vc.alpha_from_e("Ts", 0.5))


@pytest.mark.parametrize("args", [
    ["--mass", "-0.1", "--k-hertz", "1e6", "--v", "1", "--e", "0.5"],
    ["--mass", "0.1", "--radius", "0", "--E", "1e6", "--nu", "0.3", "--v", "1", "--e", "0.5"],
    ["--mass", "0.1", "--radius", "0.01", "--E=-1e6", "--nu", "0.3", "--v", "1", "--e", "0.5"],
    ["--mass", "0.1", "--radius", "0.01", "--E", "1e6", "--nu", "0.6", "--v", "1", "--e", "0.5"],
    ["--mass", "0.1", "--radius", "0.01", "--E", "1e6", "--nu", "-1", "--v", "1", "--e", "0.5"],
    ["--mass", "0.1", "--k-hertz", "0", "--v", "1", "--e", "0.5"],
    ["--mass", "0.1", "--k-hertz", "1e6", "--v", "-1", "--e", "0.5"],
    ["--mass", "0.1", "--k-hertz", "1e6", "--drop-height", "0", "--e", "0.5"],
    ["--mass", "0.1", "--k-hertz", "1e6", "--e", "0.5"],  # no speed
    ["--mass", "0.1", "--v", "1", "--e", "0.5"],  # no stiffness
    ["--k-hertz", "1e6", "--v", "1", "--e", "0.5"],  # no mass
    ["--mass", "0.1", "--k-hertz", "1e6", "--v", "1"],  # no e
    ["--mass", "0.1", "--k-hertz", "1e6", "--v", "1", "--e", "0.5", "--model", "Jian"],
    ["--e", "0.5"],  # neither --model nor physical options
])
def test_cli_calibrate_bad_input(args, capsys):
    assert main(["calibrate", *args]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "error" in err, err
