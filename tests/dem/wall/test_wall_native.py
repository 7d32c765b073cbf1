"""``fix viscontact/wall`` against LAMMPS's own ``fix wall/gran`` and ``fix wall/gran/region``,
one step and a few dozen steps, forces and torques to 1e-10 of the largest.

Each case puts a few spheres (R = 5 mm) into a wall, pressed, sliding and spinning, and runs
the native fix and ours in two LAMMPS instances of this process, with laws that are the same
(LH ``c0`` = native ``damping velocity``; the wall of the particle's own material =
``wall_material E NU particle E NU``).  Geometries: planes with LO and HI, a zcylinder, a
region sphere (concave inside, convex outside), two planes meeting in a corner (two contacts
per sphere, each with its own history), a block moving along x and a cylinder turning about
z (the wall velocity from the region's motion), and planes and cylinders with ``wiggle`` and
``shear``.  Real LAMMPS (``lammps[mpi]==2025.7.22.4.0``; skipped with the reason when absent).
"""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import needs_lammps

pytestmark = needs_lammps

from viscontact.dem import plugin as _plugin  # noqa: E402

E, NU, RHO, R = 1.0e7, 0.3, 2500.0, 0.005
MU, C0 = 0.4, 0.05
TOL = 1e-10
STEPS = (0, 1, 50)


def run(wall: str, regions=(), atoms=(), steps: int = 1, extra=(), out=("f", "torque"),
        move: bool = True):
    """One in-process LAMMPS: ``atoms`` = [(x, diameter, v, omega)], the wall fix ``wall``
    (after ``regions``), no pair forces, ``steps`` steps of 1e-6 s; per-atom arrays ``out``.
    ``move`` False: no integrator (the spheres keep position and velocity, the history
    advances)."""
    lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        cmds = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                "comm_modify vel yes", "region box block -0.2 0.2 -0.2 0.2 -0.2 0.2",
                "create_box 1 box"]
        for k, (x, d, v, w) in enumerate(atoms, 1):
            cmds += ["create_atoms 1 single {!r} {!r} {!r}".format(*x),
                     f"set atom {k} diameter {d!r} density {RHO!r}",
                     "set atom {} vx {!r} vy {!r} vz {!r}".format(k, *v),
                     "set atom {} omega {!r} {!r} {!r}".format(k, *w)]
        cmds += ["pair_style zero 0.05", "pair_coeff * *", *regions, *extra, wall,
                 *(["fix 1 all nve/sphere"] if move else []), "timestep 1e-6", f"run {steps}"]
        for c in cmds:
            lmp.command(c)
        n = len(atoms)
        order = np.argsort(np.array(lmp.numpy.extract_atom("id")[:n]))    # atoms are sorted
        res = {name: np.array(lmp.numpy.extract_atom(name)[:n])[order] for name in out
               if name != "contacts"}
        if "contacts" in out:    # the wall fix's per-atom array
            from lammps import LMP_STYLE_ATOM, LMP_TYPE_ARRAY
            res["contacts"] = np.array(lmp.numpy.extract_fix("w", LMP_STYLE_ATOM,
                                                             LMP_TYPE_ARRAY)[:n])[order]
        return res
    finally:
        lmp.close()


def native_line(geom: str, model: str | None = None) -> str:
    model = model or (f"hertz/material {E!r} {C0} {NU} damping velocity tangential mindlin NULL "
                      f"0.0 {MU} limit_damping")
    style = "wall/gran/region" if geom.startswith("region") else "wall/gran"
    return f"fix w all {style} granular {model} {geom}"


def our_line(geom: str, model: str | None = None) -> str:
    model = model or f"damping LH c0 {C0} end force tangential mindlin {MU}"
    return (f"fix w all viscontact/wall {geom} wall_material {E!r} {NU} {model} "
            f"particle {E!r} {NU}")


def assert_same(a: dict, b: dict, what: str) -> None:
    for name in a:
        peak = np.abs(a[name]).max()
        assert np.all(np.isfinite(b[name])), (what, name)
        diff = np.abs(b[name] - a[name]).max()
        assert diff <= TOL * max(peak, 1e-300), (what, name, diff, peak)


def compare(geom, regions, atoms, *, native_model=None, our_model=None, extra=(),
            steps=STEPS, out=("f", "torque")):
    """Native and ours after each of ``steps``: equal forces and torques; returns the last
    native result (for the caller's checks that something happened)."""
    for s in steps:
        a = run(native_line(geom, native_model), regions, atoms, s, extra, out)
        b = run(our_line(geom, our_model), regions, atoms, s, extra, out)
        assert_same(a, b, f"{geom} after {s} steps")
    return a


def _pressed(x, v=(0.1, 0.3, 0.0), w=(0.0, 0.0, 5.0)):
    return (x, 2 * R, v, w)


#: name -> (wall geometry, region lines, spheres)
PLANES = [_pressed((0.0, 0.0, -0.1 + R - 2e-5), (0.1, 0.3, -0.1)),
          _pressed((0.05, 0.0, 0.1 - R + 1e-5), (0.1, 0.3, 0.1), (3.0, 0.0, 5.0))]
CYLINDER = [_pressed((0.05 - R + 2e-5, 0.0, 0.0), (0.05, -0.2, 0.1), (1.0, 2.0, 3.0)),
            _pressed((0.0, -(0.05 - R + 1e-5), 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]
GEOMETRIES = {
    "planes lo hi": ("zplane -0.1 0.1", [], PLANES),
    "xplane": ("xplane -0.1 NULL", [],
               [_pressed((-0.1 + R - 3e-5, 0.01, 0.0), (-0.2, 0.1, 0.0), (0.0, 4.0, 1.0))]),
    "zcylinder": ("zcylinder 0.05", [], CYLINDER),
    "region sphere inside": (
        "region c", ["region c sphere 0 0 0 0.05 side in"],
        [_pressed((0.05 - R + 2e-5, 0.0, 0.0)),
         _pressed((0.0, -(0.05 - R + 1e-5), 0.0), (0.0, -0.1, 0.2), (1.0, 0.0, 0.0))]),
    "region sphere outside": (
        "region c", ["region c sphere 0 0 0 0.05 side out"],
        [_pressed((0.05 + R - 2e-5, 0.0, 0.0))]),
    "region corner": (
        "region c", ["region p1 plane 0 0 0 0 0 1", "region p2 plane 0 0 0 1 0 0",
                     "region c intersect 2 p1 p2"],
        [_pressed((R - 1e-5, 0.0, R - 2e-5), (-0.1, 0.3, -0.2), (0.0, 3.0, 5.0)),
         _pressed((0.1, 0.0, R - 1e-5))]),
    "region move": (
        "region c", ["variable dx equal 2e-5*sin(2*PI*elapsed*dt/0.001)",
                     "region c block -0.1 0.1 -0.1 0.1 -0.1 0.1 side in move v_dx NULL NULL"],
        [_pressed((0.1 - R + 1e-5, 0.0, 0.0)), _pressed((0.0, 0.1 - R + 1e-5, 0.0))]),
    "region rotate": (
        "region c", ["variable th equal 2*PI*elapsed*dt/0.5",
                     "region c cylinder z 0 0 0.05 -0.1 0.1 side in rotate v_th 0.001 0 0 0 0 1"],
        [_pressed((0.05 - R + 1e-5, 0.0, 0.0)),
         _pressed((0.01, -(0.05 - R + 2e-5), 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]),
    # the drum's case: open ends (Region::surface() asks the faces from outside and inside)
    "region rotate open": (
        "region c", ["variable th equal 2*PI*elapsed*dt/0.5",
                     "region c cylinder z 0 0 0.05 -0.1 0.1 side in open 1 open 2 "
                     "rotate v_th 0.001 0 0 0 0 1"],
        [_pressed((0.05 - R + 1e-5, 0.0, 0.0)),
         _pressed((0.01, -(0.05 - R + 2e-5), 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]),
    # both motions, about a tilted axis through an off-centre point: the transform's every term
    "region move rotate": (
        "region c", ["variable dx equal 2e-5*sin(2*PI*elapsed*dt/0.001)",
                     "variable th equal 2*PI*elapsed*dt/0.5",
                     "region c sphere 0 0 0 0.05 side in move v_dx NULL NULL "
                     "rotate v_th 0.003 0.001 0 0.3 0.2 1"],
        [_pressed((0.05 - R + 2e-5, 0.0, 0.0)),
         _pressed((0.0, -(0.05 - R + 1e-5), 0.0), (0.0, -0.1, 0.2), (1.0, 0.0, 0.0))]),
    "zplane wiggle z": ("zplane -0.1 0.1 wiggle z 2e-5 0.001", [], PLANES),
    "zplane wiggle x": ("zplane -0.1 0.1 wiggle x 2e-5 0.001", [], PLANES),
    "zplane shear x": ("zplane -0.1 0.1 shear x 0.5", [], PLANES),
    "zplane shear y": ("zplane -0.1 NULL shear y -0.5", [], PLANES[:1]),
    "zcylinder shear z": ("zcylinder 0.05 shear z 0.3", [], CYLINDER),
    "zcylinder wiggle z": ("zcylinder 0.05 wiggle z 2e-5 0.001", [], CYLINDER),
}


@pytest.mark.parametrize("name", list(GEOMETRIES))
def test_geometry_as_native(name):
    geom, regions, atoms = GEOMETRIES[name]
    ref = compare(geom, regions, atoms)
    # every sphere touches (a force) and slides or spins against the wall (a torque)
    assert np.all(np.linalg.norm(ref["f"], axis=1) > 0), name
    assert np.abs(ref["torque"]).max() > 0, name


def test_corner_two_contacts_each_with_history():
    """The sphere in the corner touches both planes: its force has both normals' components,
    and it equals the sum of the two single-plane forces (each face its own history: 50 steps
    of a sphere held sliding and spinning, so that the springs grow)."""
    geom, regions, atoms = GEOMETRIES["region corner"]
    both = run(our_line(geom), regions, atoms[:1], 50, move=False)
    parts = [run(our_line("zplane 0.0 NULL" if k == 0 else "xplane 0.0 NULL"), [], atoms[:1], 50,
                 move=False) for k in range(2)]
    total = parts[0]["f"] + parts[1]["f"]
    assert abs(both["f"][0, 0]) > 0.01 and abs(both["f"][0, 2]) > 0.01
    np.testing.assert_allclose(both["f"], total, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(both["torque"], parts[0]["torque"] + parts[1]["torque"],
                               rtol=1e-12, atol=1e-18)


def test_zcylinder_shear_about_axis():
    """zcylinder ``shear x V`` turns the wall about z with surface speed V.  Native's code adds
    V along x to the documented rotation velocity (and accumulates it over atoms); for a sphere
    on the x axis that extra V is normal to the wall, so without normal damping it changes
    nothing: there ours equals native.  Off the axis the first step's spring force of a sphere
    at rest is F_t = k_t V dt along the wall velocity V (y, -x)/r, k_t = 8 G* a."""
    on_axis = [_pressed((0.05 - R + 2e-5, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]
    compare("zcylinder 0.05 shear x 0.3", [], on_axis,
            native_model=(f"hertz/material {E!r} 0.0 {NU} damping velocity tangential mindlin "
                          f"NULL 0.0 {MU} limit_damping"),
            our_model=f"damping LH c0 0.0 end force tangential mindlin {MU}")
    theta, rc, delta, v = 0.7, 0.05, 2e-5, 0.3
    rr = rc - R + delta
    at_rest = [((float(rr * np.cos(theta)), float(rr * np.sin(theta)), 0.0), 2 * R, (0, 0, 0), (0, 0, 0))]
    got = run(our_line(f"zcylinder {rc} shear y {v}"), [], at_rest, 1)["f"][0]
    n = -np.array([np.cos(theta), np.sin(theta), 0.0])
    gstar = E / (4 * (2 - NU) * (1 + NU))
    rstar = R * 2 * rc / (2 * rc - R)
    kt = 8 * gstar * np.sqrt(rstar * delta)
    vwall = v * np.array([np.sin(theta), -np.cos(theta), 0.0])
    ft = got - np.dot(got, n) * n
    np.testing.assert_allclose(ft, kt * vwall * 1e-6, rtol=1e-6)


@pytest.mark.parametrize("name", ["planes lo hi", "zcylinder", "region sphere inside",
                                  "region rotate"])
def test_contacts_array_as_native(name):
    """``contacts``: native's 8 columns (touching, force, contact point, radius) per atom."""
    geom, regions, atoms = GEOMETRIES[name]
    far = [((0.0, 0.0, 0.0), 2 * R, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]    # touches nothing
    ref = compare(f"{geom} contacts", regions, atoms + far, out=("f", "contacts"), steps=(0, 3))
    assert np.all(ref["contacts"][:-1, 0] == 1.0) and np.all(ref["contacts"][-1] == 0.0)
    np.testing.assert_array_equal(ref["contacts"][:-1, 7], R)


# ---- every sub-model at the wall ----------------------------------------------------------------

def _models() -> dict:
    """name -> (native model words, our model words, flat walls only): the same contact model
    (the equivalences of docs/pair_viscontact.md: LH c0 = native damping velocity; KK c0 =
    eta0 m sqrt(R*) = native viscoelastic for one size on a flat wall; Ts alpha = native
    tsuji)."""
    from viscontact.audit.formulas import tsuji_polynomial

    m = 4.0 / 3.0 * np.pi * R**3 * RHO
    eta0 = 3000.0
    kk = float(eta0 * m * np.sqrt(R))
    w = 0.05    # surface energy [J/m^2]
    hz = f"hertz/material {E!r} {C0} {NU} damping velocity"
    ours_lh = f"damping LH c0 {C0}"
    out = {}
    for tang in ("linear_nohistory 0.5 0.4", "linear_history 2000 0.5 0.4",
                 "mindlin NULL 0.5 0.4", "mindlin 8e6 0.0 0.4", "mindlin_rescale NULL 0.5 0.4",
                 "mindlin/force NULL 0.5 0.4", "mindlin_rescale/force 8e6 0.5 0.05",
                 "mindlin NULL 0.5 0.01"):
        out[tang] = (f"{hz} tangential {tang} limit_damping",
                     f"{ours_lh} end force tangential {tang}", False)
    spin = "tangential mindlin NULL 0.5 0.4 rolling sds 50 0.02 0.1"
    out["rolling twisting marshall"] = (f"{hz} {spin} twisting marshall limit_damping",
                                        f"{ours_lh} end force {spin} twisting marshall", False)
    out["rolling twisting sds"] = (f"{hz} {spin} twisting sds 1e-4 1e-6 0.01 limit_damping",
                                   f"{ours_lh} end force {spin} twisting sds 1e-4 1e-6 0.01",
                                   False)
    out["slipping rolling twisting"] = (
        f"{hz} tangential linear_history 2000 0.5 0.05 rolling sds 5000 0.02 0.001 "
        "twisting sds 1 1e-6 1e-5",
        f"{ours_lh} end overlap tangential linear_history 2000 0.5 0.05 rolling sds 5000 0.02 "
        "0.001 twisting sds 1 1e-6 1e-5", False)
    for normal in ("dmt", "jkr"):
        out[f"{normal} LH"] = (
            f"{normal} {E!r} {C0} {NU} {w} damping velocity tangential mindlin NULL 0.5 0.4 "
            "rolling sds 50 0.02 0.1",
            f"normal {normal} {w} {ours_lh} tangential mindlin NULL 0.5 0.4 "
            "rolling sds 50 0.02 0.1", False)
        out[f"{normal} KK"] = (
            f"{normal} {E!r} {eta0} {NU} {w} damping viscoelastic tangential linear_history "
            "2000 0.5 0.4 twisting marshall",
            f"normal {normal} {w} damping KK c0 {kk!r} tangential linear_history 2000 0.5 0.4 "
            "twisting marshall", True)
    out["KK"] = (f"hertz/material {E!r} {eta0} {NU} damping viscoelastic tangential mindlin "
                 "NULL 0.5 0.4 limit_damping",
                 f"damping KK c0 {kk!r} tangential mindlin NULL 0.5 0.4", True)
    e = 0.7
    out["Ts"] = (f"hertz/material {E!r} {e} {NU} damping tsuji tangential mindlin NULL 0.5 0.4 "
                 "limit_damping",
                 f"damping Ts alpha {tsuji_polynomial(e)!r} vref 1 tangential mindlin NULL 0.5 "
                 "0.4", False)
    return out


MODEL_NAMES = list(_models())
MODEL_GEOMETRIES = ["planes lo hi", "region corner", "zcylinder", "region rotate"]


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_submodels_as_native(model):
    """Each tangential model, rolling, twisting, dmt and jkr (LH and KK), Ts: forces and torques
    after 1 and 50 steps equal native on planes, the corner (two contacts), the cylinder and a
    turning region (the last two have curved walls: not for KK, whose c0 equals native's for
    one R* only)."""
    native, ours, flat_only = _models()[model]
    for name in MODEL_GEOMETRIES:
        geom, regions, atoms = GEOMETRIES[name]
        if flat_only and name in ("zcylinder", "region rotate"):
            continue
        ref = compare(geom, regions, atoms, native_model=native, our_model=ours, steps=(1, 50))
        assert np.abs(ref["torque"]).max() > 0, (model, name)


def test_heat_as_native():
    """heat area K with a wall at temperature T (a constant, and v_T an equal-style variable):
    the heat flow into each sphere equals native's, with forces and torques."""
    extra = ["fix p all property/atom temperature heatflow", "set atom 1 temperature 300",
             "set atom 2 temperature 350", "variable T equal 320+1e5*time"]
    for geom in ("zplane -0.1 0.1 temperature 320", "region c temperature v_T"):
        regions = GEOMETRIES["region corner"][1] if geom.startswith("region") else []
        atoms = GEOMETRIES["region corner" if regions else "planes lo hi"][2]
        ref = compare(geom, regions, atoms,
                      native_model=(f"hertz/material {E!r} {C0} {NU} damping velocity tangential "
                                    f"mindlin NULL 0.5 0.4 heat area 2.5 limit_damping"),
                      our_model=f"damping LH c0 {C0} tangential mindlin NULL 0.5 0.4 heat area 2.5",
                      extra=extra, out=("f", "torque", "heatflow"), steps=(0, 1, 20))
        assert np.all(np.abs(ref["heatflow"]) > 0), geom


def test_rigid_wall_is_native_with_twice_the_modulus():
    """``wall_material rigid`` against native with the particle's material at E' = 2 E (native
    uses one material for both sides: E* = E'/(2(1-nu^2)) = E/(1-nu^2), and G* likewise)."""
    for name in ("planes lo hi", "region corner"):
        geom, regions, atoms = GEOMETRIES[name]
        for s in (1, 50):
            a = run(native_line(geom, f"hertz/material {2 * E!r} {C0} {NU} damping velocity "
                                      f"tangential mindlin NULL 0.5 {MU} limit_damping"),
                    regions, atoms, s)
            b = run(f"fix w all viscontact/wall {geom} wall_material rigid damping LH c0 {C0} "
                    f"tangential mindlin NULL 0.5 {MU} particle {E!r} {NU}", regions, atoms, s)
            assert_same(a, b, f"{name} rigid after {s} steps")


@pytest.mark.parametrize("geom,regions", [("zplane 0.0 NULL", []),
                                          ("region p", ["region p plane 0 0 0 0 0 1"])])
def test_jkr_pulled_off_as_native(geom, regions):
    """A sphere pulled off the wall at constant speed (fix move) with jkr: the force at every
    step equals native's.  A plane keeps the contact (tensile force) until the overlap reaches
    -delta_c, delta_c = (3 pi^2/16)^(1/3) (R* W^2/E*^2)^(1/3) with R* = R; a region ends it at
    zero overlap (native's region searches within R only)."""
    w, v, dt = 0.05, 0.02, 1e-6
    estar = E / (2 * (1 - NU**2))
    delta_c = (3 * np.pi**2 / 16) ** (1 / 3) * (R * w**2 / estar**2) ** (1 / 3)
    atoms = [((0.0, 0.0, R - 2e-6), 2 * R, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]
    steps = int(1.5 * (2e-6 + delta_c) / (v * dt))
    lines = {"native": native_line(geom, f"jkr {E!r} {C0} {NU} {w} damping velocity "
                                         f"tangential linear_history 2000 0.5 {MU}"),
             "ours": our_line(geom, f"normal jkr {w} damping LH c0 {C0} tangential "
                                    f"linear_history 2000 0.5 {MU}")}
    fz, z = {}, None
    for impl, line in lines.items():
        lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
        try:
            for c in ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
                      "region box block -0.1 0.1 -0.1 0.1 -0.1 0.1", "create_box 1 box",
                      "create_atoms 1 single {!r} {!r} {!r}".format(*atoms[0][0]),
                      f"set atom 1 diameter {2 * R!r} density {RHO!r}", "pair_style zero 0.05",
                      "pair_coeff * *", *regions, line, f"fix m all move linear 0 0 {v}",
                      f"timestep {dt}", "run 0"]:
                lmp.command(c)
            f, zz = [], []
            for _ in range(steps):
                lmp.command("run 1 pre no post no")
                f.append(float(lmp.numpy.extract_atom("f")[0, 2]))
                zz.append(float(lmp.numpy.extract_atom("x")[0, 2]))
        finally:
            lmp.close()
        fz[impl], z = np.array(f), np.array(zz)
    peak = np.abs(fz["native"]).max()
    assert np.abs(fz["ours"] - fz["native"]).max() <= TOL * peak
    delta = R - z
    last = delta[np.nonzero(fz["ours"])[0][-1]]    # the last overlap with a force
    assert fz["ours"].min() < 0    # tensile
    if geom.startswith("region"):
        assert 0 < last < v * dt * 1.01
    else:
        assert -delta_c < last < -delta_c + v * dt * 1.01
