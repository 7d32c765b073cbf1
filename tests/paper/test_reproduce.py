"""``viscontact reproduce``: the study's tables against published values, files, safety."""

import csv
import io
import json
import math
import os

import pytest

import viscontact as vc
from viscontact.paper import report as build
from viscontact.paper.report import MARKER, ReportError, report_files, reproduce
from viscontact.paper.study import ALPHA_GRID, BETA_GRID, PUBLISHED_E


FIGS = [f"fig{i:02d}.png" for i in range(2, 13)]


def _csv(path):
    return list(csv.reader(io.StringIO(path.read_text(encoding="utf-8"))))


def test_report_has_every_file(report):
    out, seconds, proc = report
    names = {p.name for p in out.iterdir()}
    for f in ["table1.csv", "table2.csv", "table4.csv", "table1.md", "table2.md", "table4.md",
              "index.html", MARKER, *FIGS]:
        assert f in names, f
    for f in FIGS:
        data = (out / f).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000, f
    assert set(json.loads((out / MARKER).read_text())["files"]) == set(report_files())
    assert not [p for p in out.parent.iterdir() if ".partial-" in p.name]  # no leftovers
    assert "table 1" in proc.stderr and "fig12" in proc.stderr  # progress shown


def test_table1_matches_published_values(report):
    rows = _csv(report[0] / "table1.csv")
    assert rows[0] == ["alpha", "LH", "Ts", "KK", "Li", "Hunt"]
    alphas = [float(r[0]) for r in rows[1:]]
    assert len(alphas) == 30 and alphas == pytest.approx(list(ALPHA_GRID))
    assert alphas[:11] == pytest.approx([0.02 * i for i in range(11)])
    assert alphas[-1] == 3.0
    row = rows[1 + alphas.index(0.3)]
    for model, value in zip(rows[0][1:], row[1:]):
        assert round(float(value), 4) == PUBLISHED_E[model], model
    assert all(float(v) == 1.0 for v in rows[1][1:])  # alpha = 0: no loss
    for col in range(1, 6):  # e falls with alpha
        es = [float(r[col]) for r in rows[1:]]
        assert all(a > b for a, b in zip(es, es[1:]))


def test_table2_matches_published_values_and_kk(report):
    rows = _csv(report[0] / "table2.csv")
    assert rows[0] == ["alpha"] + [f"beta={b:g}" for b in BETA_GRID]
    alphas = [float(r[0]) for r in rows[1:]]
    assert len(alphas) == 30
    row = rows[1 + alphas.index(0.3)]
    assert round(float(row[rows[0].index("beta=0.5")]), 4) == PUBLISHED_E["Jian"]
    kk = [r[3] for r in _csv(report[0] / "table1.csv")[1:]]
    assert [r[1] for r in rows[1:]] == kk  # beta = 0 is exactly KK
    for r in rows[1:]:  # growing beta raises e at fixed alpha
        es = [float(x) for x in r[1:]]
        assert all(a <= b for a, b in zip(es, es[1:]))


def test_table4_by_hand(report):
    rows = _csv(report[0] / "table4.csv")
    head = rows[0]
    assert head[:2] == ["ball", "model"] and len(rows) == 1 + 12
    col = {h: i for i, h in enumerate(head)}
    for r in rows[1:]:
        b = vc.experiment.ball(r[0])
        m, k, v = b.mass, b.k_hertz, b.v_in
        T = (m * m / (k * k * v)) ** 0.2
        assert float(r[col["T [s]"]]) == pytest.approx(T, rel=1e-9)
        assert float(r[col["m_eff [kg]"]]) == pytest.approx(m)
        assert float(r[col["R_eff [m]"]]) == pytest.approx(b.radius)
        alpha, c = float(r[col["alpha"]]), float(r[col["c"]])
        if r[1] == "LH":
            assert c == pytest.approx(alpha * m / T, rel=1e-9)
        if r[1] == "Hunt":
            assert c == pytest.approx(alpha * k / v, rel=1e-9)
        if r[1] == "Jian":
            assert float(r[col["beta"]]) == b.beta
            assert float(r[col["tau [s]"]]) == pytest.approx(b.beta * T, rel=1e-9)
        tau = float(r[col["tau [s]"]]) if r[col["tau [s]"]] else None
        hit = vc.impact(r[1], m_eff=m, k_hertz=k, v=v, c=c, tau=tau, history=False)
        assert hit.e == pytest.approx(b.e, abs=1e-8)


def test_comparison_lists_every_law_and_ball(report):
    rows = _csv(report[0] / "comparison.csv")
    col = {h: i for i, h in enumerate(rows[0])}
    assert {(r[0], r[1]) for r in rows[1:]} == {(b, m) for b in ("ILB", "OLB")
                                                 for m in vc.STUDY_MODELS}
    for r in rows[1:]:
        b = vc.experiment.ball(r[0])
        assert float(r[col["e predicted"]]) == pytest.approx(b.e, abs=1e-6)
        tc = float(r[col["tc predicted [s]"]])
        assert 0.5 * b.tc < tc < 1.5 * b.tc
        assert float(r[col["fmax predicted [N]"]]) > 0
    md = (report[0] / "comparison.md").read_text()
    assert "| ILB | Jian |" in md


def test_index_shows_every_table_and_figure(report):
    page = (report[0] / "index.html").read_text(encoding="utf-8")
    for f in FIGS:
        assert f'src="{f}"' in page
    for t in ("table1", "table2", "table4", "comparison", "published"):
        assert f'<table id="{t}">' in page
    assert page.count("<figcaption>") == len(FIGS)
    assert "NO</td>" not in page  # every published value agrees


# --- directory safety (a stub stands in for the slow computation) ---------------------------

@pytest.fixture
def fast(monkeypatch):
    def fake_write(res, tmp, step):
        for f in report_files():
            (tmp / f).write_text("new\n")
        return report_files()

    monkeypatch.setattr(build, "run_study", lambda step: None)
    monkeypatch.setattr(build, "_write_all", fake_write)


def test_existing_report_needs_force(tmp_path, fast):
    out = tmp_path / "rep"
    reproduce(out, progress=None)
    (out / "notes.txt").write_text("mine\n")
    with pytest.raises(ReportError, match="--force"):
        reproduce(out, progress=None)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    inode = (out / "table1.csv").stat().st_ino
    reproduce(out, force=True, progress=None)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert (out / "table1.csv").stat().st_ino != inode  # replaced, not left alone
    assert (out / "notes.txt").read_text() == "mine\n"  # never deleted
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


def test_edited_report_file_is_kept_even_with_force(tmp_path, fast):
    out = tmp_path / "rep"
    reproduce(out, progress=None)
    (out / "table1.csv").write_text("my edits\n")
    with pytest.raises(ReportError, match="table1.csv not written by viscontact reproduce"):
        reproduce(out, force=True, progress=None)
    assert (out / "table1.csv").read_text() == "my edits\n"
    assert (out / "table2.csv").read_text() == "new\n"


def test_foreign_files_are_never_overwritten(tmp_path, fast):
    out = tmp_path / "rep"
    out.mkdir()
    (out / "fig02.png").write_text("someone else's\n")
    for force in (False, True):
        with pytest.raises(ReportError, match="holds no earlier output"):
            reproduce(out, force=force, progress=None)
    assert [p.name for p in out.iterdir()] == ["fig02.png"]
    (out / "fig02.png").unlink()
    reproduce(out, progress=None)  # an empty directory is fine
    (out / "readme.txt").write_text("x")  # unrelated files beside a report are fine
    reproduce(out, force=True, progress=None)
    assert (out / "readme.txt").read_text() == "x" and (out / MARKER).exists()


def test_root_and_foreign_outputs_refused(tmp_path, fast):
    with pytest.raises(ReportError, match="root"):
        reproduce("/", progress=None)
    other = tmp_path / "other"
    other.mkdir()
    (other / MARKER).write_text('{"tool": "viscontact", "command": "fit", "files": {}}')
    with pytest.raises(ReportError, match="viscontact fit"):
        reproduce(other, force=True, progress=None)


def test_failure_leaves_nothing(tmp_path, monkeypatch):
    def boom(res, tmp, step):
        (tmp / "table1.csv").write_text("half")
        raise RuntimeError("disk full")

    monkeypatch.setattr(build, "run_study", lambda step: None)
    monkeypatch.setattr(build, "_write_all", boom)
    with pytest.raises(RuntimeError):
        reproduce(tmp_path / "a" / "b" / "rep", progress=None)
    assert list(tmp_path.iterdir()) == []


def test_unwritable_directory_exit_2(tmp_path, capsys):
    from viscontact.cli import main

    blocker = tmp_path / "file"
    blocker.write_text("a file, not a directory\n")
    for out in (blocker / "rep", blocker / "a" / "rep", blocker):
        assert main(["reproduce", "--out", str(out), "--quiet"]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1, err
        assert err.startswith("viscontact reproduce: error:")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]
    assert blocker.read_text() == "a file, not a directory\n"


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0,
                    reason="root can write into read-only directories")
def test_read_only_parent_exit_2(tmp_path, capsys):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        from viscontact.cli import main

        assert main(["reproduce", "--out", str(ro / "rep"), "--quiet"]) == 2
        assert list(ro.iterdir()) == []
    finally:
        ro.chmod(0o755)


def test_published_table_in_study_constants():
    assert len(ALPHA_GRID) == 30 and math.isclose(ALPHA_GRID[11], 0.3)
