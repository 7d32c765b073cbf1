"""The shipped ports of LAMMPS's granular examples (``viscontact/dem/examples``: pour onto a flat
wall, a rotating drum, a funnel, a mixer, a 2D pour, a frozen bed) next to native ``pair_style
granular`` on the pinned LAMMPS, through the exact equivalences of docs/pair_viscontact.md
(helper module ``dem_examples``):

- per-atom forces and torques equal native's to 1e-10 (relative to the largest) in the first
  dump frames of each contact-rich phase, while the two runs are still together (after that the
  flow is chaotic and rounding grows);
- over the whole run, kinetic energy, packing height and number of contacts differ from native's
  (same seed) by no more than native's own runs with two pour seeds differ;
- 2 ranks: the same, as native's 2-rank run does;
- after the bed has settled, no pair overlaps more than in native's runs;
- every shipped law file (LH, Ts, KK, Li, Hunt, Jian, power) runs each example's second phase
  from native's saved bed, and one example whole, through ``viscontact.dem.run_input`` (what
  ``viscontact dem run`` calls): no atom lost, the bed's height and overlaps within what native
  shows.

The test sizes are small (``-var n``, ``-var fill``, ``-var steps`` ...): 150 to 250 spheres,
1 to 3 10^4 steps of 1e-5 s.  The straight runs of native and plugin drift apart by rounding
from the pour's first collisions on (chaos), so their forces are compared at the onset; the
contact-rich second phases are compared from a common start, the bed native saved after its
fill (``-var resume 1``).
"""

from __future__ import annotations

import re
import shutil
from dataclasses import dataclass

import numpy as np
import pytest

import dem_examples as X
from dem_util import needs_lammps, needs_mpirun
from viscontact import dem

pytestmark = needs_lammps

#: relative force and torque agreement while plugin and native runs are together
FORCE_TOL = 1e-10


@dataclass(frozen=True)
class Case:
    """One example at test size.

    Attributes:
        name: ``in.NAME``; variables: ``-var`` values (size, steps of the two phases, dump
        interval).  The first phase pours; the second (chute flow, settling, turning drum,
        running funnel, mixing) is also run by native and plugin from the bed native saved
        after its fill (``-var resume 1``) for ``resumed`` steps, every frame compared.
        seeds: pour seeds of native's two runs; equiv: the laws compared with native.
        kk_diameter: sphere diameter when one size (KK's equivalence holds), else None;
        kk_frozen: "I J" of a moving and a frozen type (their pair has m* = m_I).
    """

    name: str
    variables: dict
    resumed: int = 2000
    seeds: tuple = (1, 2)
    equiv: tuple = ("LH",)
    kk_diameter: float | None = None
    kk_frozen: str | None = None


#: the test sizes pour in few, dense batches (-var vol) to fill within a short fill phase: the
#: comparison with native needs no clean insertion (test_example_runs_clean checks the defaults)
CASES = [
    Case("pour.flat", {"n": 200, "w": 0.05, "h": 0.15, "fill": 16000, "steps": 4000,
                       "every": 250, "vol": 0.3}, equiv=("LH", "Ts")),
    Case("pour.drum", {"n": 200, "fill": 12000, "steps": 4000, "every": 250, "vol": 0.3},
         equiv=("LH", "Ts")),
    Case("pour.funnel", {"n": 200, "fill": 12000, "steps": 4000, "every": 250, "vol": 0.3}),
    Case("mixer", {"n": 250, "fill": 8000, "steps": 4000, "every": 250, "vol": 0.3},
         equiv=("LH", "KK"), kk_diameter=0.01),
    Case("pour.2d", {"n": 150, "w": 0.15, "fill": 26000, "steps": 6000, "every": 250,
                     "vol": 0.4}),
    Case("bed.frozen", {"n": 150, "w": 0.05, "fill": 14000, "steps": 4000, "every": 250,
                        "vol": 0.3}, equiv=("LH", "Ts", "KK"), kk_diameter=0.01, kk_frozen="1 2"),
]
IDS = [c.name for c in CASES]
SHIPPED = ("LH", "Ts", "KK", "Li", "Hunt", "Jian", "power")
#: the examples also run on 2 ranks (each 2-rank pair costs as much as a whole example)
TWO_RANKS = ("pour.flat",)
#: the pour is compared from its first contact for this many steps, while the straight runs are
#: still together (the first collisions of a dilute pour amplify rounding quickly)
ONSET = 2500


def _run(tmp, case: Case, law: str, seed: int, np_: int = 1, tag: str | None = None):
    return X.run_example(tmp, case.name, law, {**case.variables, "seed": seed}, np_=np_,
                         tag=tag, kk_diameter=case.kk_diameter, kk_frozen=case.kk_frozen)


@pytest.fixture(scope="module", params=CASES, ids=IDS)
def native(request, tmp_path_factory):
    """Native runs of one example with its two pour seeds: (case, directory, run, run)."""
    case = request.param
    tmp = tmp_path_factory.mktemp(case.name)
    nat = _run(tmp, case, "nat-LH", case.seeds[0], tag="nat")
    other = _run(tmp, case, "nat-LH", case.seeds[1], tag="nat-seed2")
    return case, tmp, nat, other


@pytest.fixture(scope="module")
def flows(native):
    """The native runs and the plugin's (LH c0, first seed): (case, directory, native run,
    native run of the second seed, plugin run)."""
    case, tmp, nat, other = native
    return case, tmp, nat, other, _run(tmp, case, "vc-LH", case.seeds[0], tag="vc")


_RESUMED: dict = {}


def _resumed_run(tmp, case: Case, law: str, bed, np_: int = 1):
    """The second phase from ``bed``'s saved bed with the law file ``law``, dumped every 100
    steps; each run once per test session."""
    key = (str(tmp), law, np_)
    if key not in _RESUMED:
        variables = {**case.variables, "steps": case.resumed, "every": 100}
        _RESUMED[key] = X.run_example(tmp, case.name, law, variables, np_=np_,
                                      tag=f"{law}-resumed-{np_}", kk_diameter=case.kk_diameter,
                                      kk_frozen=case.kk_frozen, resume=bed)
    return _RESUMED[key]


def _resumed_differences(tmp, case: Case, law: str, bed) -> list:
    """Native and plugin (law X: ``nat-X``, ``vc-X``) run the second phase from native's bed;
    the force differences of every frame (every 100 steps)."""
    return X.force_differences(*(_resumed_run(tmp, case, f"{side}-{law}", bed)
                                 for side in ("nat", "vc")))


def _assert_forces(case: Case, rows, what: str) -> None:
    """Every row's force difference within FORCE_TOL."""
    worst = max(r[2] for r in rows)
    print(f"{case.name}: {what}: max force/torque difference {worst:.1e} over {len(rows)} "
          f"frames, {min(r[1] for r in rows)} to {max(r[1] for r in rows)} contacts")
    assert worst <= FORCE_TOL, rows


def _check(case: Case, ok: bool, detail) -> None:
    """A statistical check."""
    assert ok, detail


def _onset(diffs):
    """The (step, contacts, difference) rows of the pour's first ONSET steps of contact."""
    first = next(r[0] for r in diffs if r[1] > 0)
    return [r for r in diffs if first <= r[0] <= first + ONSET]


def test_forces_equal_native_while_together(flows):
    case, _, nat, _, ours = flows
    _assert_forces(case, _onset(X.force_differences(nat, ours)), "pour, LH c0 vs native velocity")


def test_statistics_within_native_seed_spread(flows):
    case, _, nat, other, ours = flows
    ref, ns = X.statistics(nat), X.statistics(other)
    ours_d = X.statistic_distance(ref, X.statistics(ours))
    seed_d = X.statistic_distance(ref, ns)
    print(f"{case.name}: plugin vs native {ours_d}; native seed spread {seed_d}")
    assert ours.frames[-1].natoms == nat.frames[-1].natoms
    _check(case, all(ours_d[k] <= seed_d[k] for k in ref), (ours_d, seed_d))


def test_poured_bed_overlaps_as_native(flows):
    """The bed saved after the fill (the poured bed, settling) and the last frame: the largest
    pair overlap no larger than native's, plus what native itself varies between two seeds."""
    case, _, nat, other, ours = flows
    for what, get in (("poured bed", lambda r: X.saved_bed(r, case.name)),
                      ("end", lambda r: r.frames[-1])):
        seeds = [X.max_overlap(get(nat)), X.max_overlap(get(other))]
        mine = X.max_overlap(get(ours))
        print(f"{case.name}: {what}: largest overlap / diameter: plugin {mine:.4f}, native "
              f"{seeds[0]:.4f} and {seeds[1]:.4f}")
        _check(case, mine <= max(seeds) + abs(seeds[0] - seeds[1]), (what, mine, seeds))


def test_second_phase_forces_equal_native(native):
    """Chute flow, settling, the turning drum, the running funnel, the mixing: native and
    plugin both start from the bed native saved after its fill (tangential springs from zero in
    both); a contact-rich phase from its first step."""
    case, tmp, nat, _ = native
    rows = _resumed_differences(tmp, case, "LH", nat)
    assert min(r[1] for r in rows) >= 10, rows
    _assert_forces(case, rows, "second phase, LH c0 vs native velocity")


def test_other_equivalences(native):
    """Ts alpha = native tsuji (any sizes and masses, frozen partners included) and KK c0 =
    native viscoelastic (one size): forces as for LH over the second phase started from
    native's bed."""
    case, tmp, nat, _ = native
    if len(case.equiv) == 1:
        pytest.skip(f"{case.name}: LH only (CI time)")
    for law in case.equiv[1:]:
        _assert_forces(case, _resumed_differences(tmp, case, law, nat),
                       f"second phase, {law} vs native")


@needs_mpirun
def test_two_ranks_as_native(flows):
    """Plugin and native on 2 ranks.  The pour: the 2-rank plugin run keeps native's forces at
    the onset, and over the run stays as close to the 1-rank plugin run as native's seeds are
    apart.  The second phase from native's bed: the 2-rank plugin run equals the 2-rank native
    run and its own 1-rank run to FORCE_TOL, as native's 1- and 2-rank runs agree."""
    case, tmp, nat, other, ours = flows
    if case.name not in TWO_RANKS:
        pytest.skip(f"2 ranks are checked on {', '.join(TWO_RANKS)} (CI time)")
    nat2 = _run(tmp, case, "nat-LH", case.seeds[0], np_=2, tag="nat-np2")
    ours2 = _run(tmp, case, "vc-LH", case.seeds[0], np_=2, tag="vc-np2")
    _assert_forces(case, _onset(X.force_differences(nat2, ours2)), "2 ranks, pour")
    seed_d = X.statistic_distance(X.statistics(nat), X.statistics(other))
    ours_d = X.statistic_distance(X.statistics(ours), X.statistics(ours2))
    for key in seed_d:
        assert ours_d[key] <= seed_d[key], (key, ours_d, seed_d)
    runs = {(side, np_): _resumed_run(tmp, case, f"{side}-LH", nat, np_)
            for side in ("nat", "vc") for np_ in (1, 2)}
    _assert_forces(case, X.force_differences(runs["nat", 2], runs["vc", 2]),
                   "2 ranks, second phase, LH c0 vs native velocity")
    for side in ("nat", "vc"):
        _assert_forces(case, X.force_differences(runs[side, 1], runs[side, 2]),
                       f"second phase, {side} 1 vs 2 ranks")


#: each shipped law also runs one example whole (pour and second phase); the rest start from
#: native's saved bed (CI time)
WHOLE = {"LH": "pour.flat", "Ts": "pour.drum", "KK": "pour.funnel", "Li": "mixer",
         "Hunt": "pour.2d", "Jian": "bed.frozen", "power": "pour.flat"}


def _run_shipped(tmp, case: Case, law: str, bed=None):
    """The example with its shipped ``law.LAW`` through ``dem.run_input`` (what ``viscontact dem
    run`` calls, in-process): (thermo, last dump frame).  ``bed``: start the second phase from
    that run's saved bed, dumped every 100 steps."""
    d = tmp / f"law-{law}" if bed is None else tmp / f"law-{law}-resumed"
    if d.exists():
        shutil.rmtree(d)
    shutil.copytree(X.EXAMPLES, d)
    variables = {**case.variables, "law": law, "seed": case.seeds[0]}
    if bed is not None:
        shutil.copy(bed.directory / f"{case.name}.bed", d)
        variables.update(resume=1, steps=case.resumed, every=100)
    res = dem.run_input(d / f"in.{case.name}", variables=variables)
    return res.thermo, dem.read_dump(next(d.glob("*.dump")))[-1]


def _assert_sane(thermo, last, refs, span: float, overlap_refs=None) -> None:
    """No atom lost (the inputs stop with an error if one is; the count never falls), finite
    energy and height, the final height within ``span`` of native's, the largest overlap at most
    twice native's (``overlap_refs``: the runs for the overlap, default ``refs``)."""
    assert np.all(np.diff(thermo["Atoms"]) >= 0) and last.natoms == thermo["Atoms"][-1]
    assert np.all(np.isfinite(thermo["c_ke"])) and np.all(np.isfinite(thermo["c_height"]))
    heights = [float(r.thermo["c_height"][-1]) for r in refs]
    assert min(heights) - span <= thermo["c_height"][-1] <= max(heights) + span, heights
    bound = max(X.max_overlap(r.frames[-1]) for r in (overlap_refs or refs))
    assert X.max_overlap(last) <= 2.0 * bound, (X.max_overlap(last), bound)


@pytest.mark.parametrize("law", SHIPPED)
def test_every_law_runs_sane(native, law):
    """Every shipped law file (alpha calibrated to e = 0.8 at 1 m/s) runs the example's second
    phase from native's bed through dem.run_input: no atom lost, the height within a sphere
    diameter of native's (LH c0) and overlaps at most twice native's.  On its WHOLE example it
    also runs pour and second phase, the height within native's seed spread plus a diameter."""
    case, tmp, nat, other = native
    thermo, last = _run_shipped(tmp, case, law, bed=nat)
    ref = _resumed_run(tmp, case, "nat-LH", nat)
    assert last.natoms == ref.frames[-1].natoms
    # the height against the resumed native run; the overlaps against every native run of the
    # example (the largest overlap of a flowing bed is one impact: native's own two seeds differ
    # by 1.5 times in it)
    _assert_sane(thermo, last, [ref], 0.01, overlap_refs=[ref, nat, other])
    if WHOLE[law] == case.name:
        thermo, last = _run_shipped(tmp, case, law)
        spread = abs(float(nat.thermo["c_height"][-1]) - float(other.thermo["c_height"][-1]))
        _assert_sane(thermo, last, [nat, other], spread + 0.01)


def test_dem_run_command_line(tmp_path):
    """``viscontact dem run`` (the command a user types) runs an example with a law chosen by
    ``--var law`` on 2 ranks, saves the bed and resumes from it; an unknown law is one line."""
    import json

    from conftest import run_cli

    d = tmp_path / "granular"
    shutil.copytree(X.EXAMPLES, d)
    args = ["dem", "run", "in.pour.2d", "--var", "law", "Hunt", "--var", "n", "30", "--var",
            "fill", "3000", "--var", "steps", "200", "--json"]
    proc = run_cli(*args, "--np", "2", cwd=d)
    assert proc.returncode == 0, proc.stderr
    first = json.loads(proc.stdout)
    assert first["last"]["Step"] == 3200 and first["last"]["Atoms"] > 0
    assert (d / "pour.2d.bed").is_file()
    proc = run_cli(*args, "--var", "resume", "1", "--force", cwd=d)
    assert proc.returncode == 0, proc.stderr
    again = json.loads(proc.stdout)
    assert again["last"]["Step"] == 200 and again["last"]["Atoms"] == first["last"]["Atoms"]
    proc = run_cli("dem", "run", "in.pour.2d", "--var", "law", "XX", "--force", cwd=d)
    assert proc.returncode != 0 and "law.XX" in proc.stderr and len(proc.stderr.splitlines()) == 1


#: every shipped input with its defaults (size, geometry, insertion), and the law and sizes the
#: docs show where they show one (docs/examples.md), its long phases cut short: what is checked
#: is the input's design (every sphere inserted, none lost, no warning), not the flow
CLEAN = {
    "settle": {"steps": 2000},
    "pour.flat": {"steps": 500},
    "pour.drum": {"law": "Ts", "steps": 500},      # the docs: --var law Ts (--np 2)
    "pour.funnel": {"steps": 500},
    "mixer": {"law": "Jian", "steps": 500},        # the docs: --var law Jian --var steps 10000
    "heap": {"settle": 2000, "steps": 500},
    "powder": {"steps": 2000},
    "pour.2d": {"steps": 500},
    "bed.frozen": {"steps": 500},
    # the mesh walls, their STL files written first by the command each input's header gives:
    # the whole fill with the input's own n and -var vol (its last batch at step 12,295, 9,011
    # and 13,519); the discharge that follows loses spheres through the orifice by design
    "mesh.silo": {"fill": 12400, "steps": 0},
    "mesh.hopper": {"fill": 9100, "steps": 0},
    "mesh.mixer": {"fill": 13600, "steps": 0},
    # create_atoms random places all 320 at once; a short settle and the first turning steps
    "mesh.drum": {"settle": 2000, "steps": 500},
}


def _default(text: str, name: str) -> int | None:
    """The default of ``variable NAME index VALUE`` in an input, or None."""
    m = re.search(rf"^variable\s+{name}\s+index\s+(\S+)", text, re.M)
    return int(m.group(1)) if m else None


@pytest.mark.parametrize("name", list(CLEAN))
def test_example_runs_clean(tmp_path, name):
    """The shipped input inserts exactly its ``n`` spheres (fix pour, create_atoms random),
    loses none (the inputs stop on a lost atom; the count never falls) and ends with no LAMMPS
    warning (e.g. "Fewer insertions than requested", "Only inserted N particles")."""
    d = tmp_path / "granular"
    shutil.copytree(X.EXAMPLES, d)
    text = (d / f"in.{name}").read_text()
    assert set(CLEAN) == {p.name[3:] for p in X.EXAMPLES.glob("in.*")}  # none left out
    mesh = re.search(r"^#\s+python3 -m viscontact\.dem\.stl (.*)$", text, re.M)
    if mesh:  # the mesh file, as the header tells the user to write it
        from viscontact.dem import stl

        shape, out, *opts = mesh.group(1).split()
        assert stl.main([shape, str(d / out), *opts]) == 0
    res = dem.run_input(d / f"in.{name}", variables=CLEAN[name], progress=False, quiet=True)
    log = res.log_path.read_text()
    atoms = res.thermo["Atoms"]
    warnings = [ln for ln in log.splitlines() if ln.startswith("WARNING")]
    assert not warnings, warnings
    assert np.all(np.diff(atoms) >= 0), "atoms lost"
    n = _default(text, "n")
    if re.search(r"^fix\s+\S+\s+\S+\s+pour\s", text, re.M):
        requested = [int(m) for m in re.findall(r"Particle insertion: \d+ every \d+ steps, (\d+)",
                                                 log)]
        assert requested == [n]
        assert atoms[-1] - atoms[0] == n, (atoms[0], atoms[-1], n)   # inserted by the pour
    elif n is not None:
        created = re.findall(r"create_atoms\s+\d+\s+random\s+(\d+)[^\n]*\n(?:[^\n]*\n){0,6}?"
                             r"Created (\d+) atoms", log)
        assert created and all(int(a) == int(b) == n for a, b in created), created
    else:
        assert atoms[0] == atoms[-1] > 0
