"""Published closed-form calibrations alpha(e), one function each, in one registry.

Every formula is written for one of the laws of :mod:`viscontact.physics.laws`, in that law's
non-dimensional damping constant alpha (Jian et al. 2019, eqs. of the damping terms), so that the exact solver can say
what restitution the alpha really delivers.  Conversions used here:

* Hunt-Crossley papers write F = k delta^(3/2) (1 + chi delta'), with chi = lambda / k_Hertz.
  Non-dimensionally F^ = x^(3/2) (1 + alpha x') with alpha = chi v_i, so a published
  "chi v_i = f(e)" is alpha = f(e).
* Kuwabara-Kono / Brilliantov: Schwager & Poschel and Muller & Poschel expand e in the
  constant beta of e = 1 - C1 beta + C2 beta^2 - ... whose first coefficient C1 = 1.15344 is
  exactly the first-order energy coefficient I1(1/2) of our alpha (checked in the tests), so
  their beta is our alpha.
* Tsuji: c = alpha sqrt(m* k_Hertz) delta^(1/4) is exactly our Ts alpha.

Adding a formula: write ``def _name(e) -> alpha`` with its reference in the docstring, and add
a :class:`Formula` line to ``_REGISTERED``.  A formula that has no alpha for some e (a
quadratic without a real root, a curve that leaves its range) returns NaN there.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

# scipy is imported in the functions that use it: the command line loads this module for
# its --help, which should not pay for scipy.
from ..physics import domain
from ..calibration.inverse import alpha_from_e, restitution
from ..collision.single import check_end
from ..physics.laws import exponent, lookup
from ..physics.laws import Hunt, KK, LH, Li, Power, Ts

__all__ = [
    "Formula", "FORMULAS", "FormulaAudit", "audit_formula", "exact_alpha", "delivered_e",
    "first_order_coefficient", "first_order_formula", "get_formula", "hunt_exact_alpha",
    "antypov_elliott_alpha", "tsuji_polynomial", "thornton_alpha", "thornton_gamma", "THORNTON_H",
]

SQRT5 = math.sqrt(5.0)


def _check_e(e: float) -> float:
    """A restitution coefficient in (0, 1], for the closed forms (they answer for any)."""
    try:
        v = domain.check_number("e", e)
    except ValueError:
        v = math.nan
    if not (0.0 < v <= 1.0):
        raise ValueError(f"e must be a number in (0, 1]; got {e!r}")
    return v


def _check_target_e(e: float) -> float:
    """A target restitution for an exact solve: inside its domain (:mod:`viscontact.physics.domain`)."""
    return domain.check("e", e)


# ----------------------------------------------------------------------------- Hunt-Crossley
def _hunt_crossley(e: float) -> float:
    """alpha = 3(1 - e)/2.  K.H. Hunt, F.R.E. Crossley, J. Appl. Mech. 42 (1975) 440;
    also D.W. Marhefka, D.E. Orin, IEEE Trans. Syst. Man Cybern. A 29 (1999) 566."""
    return 1.5 * (1.0 - e)


def _lee_wang(e: float) -> float:
    """alpha = 3(1 - e)/4.  T.W. Lee, A.C. Wang, J. Mech. Transm. Autom. Des. 105 (1983) 534."""
    return 0.75 * (1.0 - e)


def _herbert_mcwhannell(e: float) -> float:
    """alpha = 6(1 - e)/((2e - 1)^2 + 3).  R.G. Herbert, D.C. McWhannell,
    J. Eng. Ind. 99 (1977) 513."""
    return 6.0 * (1.0 - e) / ((2.0 * e - 1.0) ** 2 + 3.0)


def _lankarani_nikravesh(e: float) -> float:
    """alpha = 3(1 - e^2)/4.  H.M. Lankarani, P.E. Nikravesh, J. Mech. Des. 112 (1990) 369."""
    return 0.75 * (1.0 - e * e)


def _gonthier(e: float) -> float:
    """alpha = (1 - e^2)/e.  Y. Gonthier, J. McPhee, C. Lange, J.-C. Piedboeuf,
    Multibody Syst. Dyn. 11 (2004) 209."""
    return (1.0 - e * e) / e


def _zhiying_qishao(e: float) -> float:
    """alpha = 3(1 - e^2) exp(2(1 - e))/4.  Q. Zhiying, L. Qishao (2006), as tabulated by Flores et al.,
    Multibody Syst. Dyn. 25 (2011) 357."""
    return 0.75 * (1.0 - e * e) * math.exp(2.0 * (1.0 - e))


def _flores(e: float) -> float:
    """alpha = 8(1 - e)/(5e).  P. Flores, M. Machado, M.T. Silva, J.M. Martins,
    Multibody Syst. Dyn. 25 (2011) 357."""
    return 8.0 * (1.0 - e) / (5.0 * e)


def _gharib_hurmuzlu(e: float) -> float:
    """alpha = 1/e - 1.  M. Gharib, Y. Hurmuzlu, J. Appl. Mech. (2012)."""
    return 1.0 / e - 1.0


def _hu_guo(e: float) -> float:
    """alpha = 3(1 - e)/(2e).  S. Hu, X. Guo, Multibody Syst. Dyn. (2015)."""
    return 1.5 * (1.0 - e) / e


def _hunt_residual(a: float, e: float, le: float) -> float:
    """[ln((1 + a)/(1 - a e)) - (1 + e) a] / a^2, without cancellation.

    Expanding both logarithms, the bracket is sum_{k>=2} a^k (e^k - (-1)^k)/k, so the scaled
    residual is (e^2 - 1)/2 + a (1 + e^3)/3 + a^2 (e^4 - 1)/4 + ... (summed for small a,
    where the direct form loses all digits); ``le`` = ln e.
    """
    if a < 0.05:
        total, ak = 0.0, 1.0
        for k in range(2, 40):
            ck = math.expm1(k * le) if k % 2 == 0 else math.exp(k * le) + 1.0
            total += ak * ck / k
            ak *= a
        return total
    return (math.log1p(a) - math.log1p(-a * e) - (1.0 + e) * a) / (a * a)


def hunt_exact_alpha(e: float) -> float:
    """The exact Hunt-Crossley relation (1 + e) alpha = ln((1 + alpha)/(1 - alpha e)), solved for alpha.

    Follows from integrating v dv/dx = -x^(3/2)(1 + alpha v) between the two zero-overlap
    states; the Hunt force and overlap vanish together, so it holds for both end criteria.
    A.S. Carvalho, J.M. Martins, Mech. Mach. Theory (2019), after Hunt & Crossley (1975).
    The root lies in (0, 1/e); for small e it is 1/e to machine precision.
    """
    e = _check_e(e)
    if e == 1.0:
        return 0.0
    le = math.log(e)
    inv = 1.0 / e
    # the scaled residual is (e^2 - 1)/2 < 0 at 0 and -> +inf at 1/e: find a point where it is > 0
    delta = 0.5
    while True:
        hi = inv * (1.0 - delta)
        if hi >= inv or delta < 1e-300:
            return inv  # root indistinguishable from 1/e
        if _hunt_residual(hi, e, le) > 0:
            break
        delta *= 1e-2
    from scipy.optimize import brentq

    return brentq(lambda a: _hunt_residual(a, e, le), 0.0, hi, xtol=1e-300, rtol=1e-15, maxiter=500)


# ---------------------------------------------------------------------------- Kuwabara-Kono
_SP_C1, _SP_C2 = 1.15344, 0.79827


def _schwager_poschel(e: float) -> float:
    """Inverse of e = 1 - 1.15344 alpha + 0.79827 alpha^2 (smaller root).

    T. Schwager, T. Poschel, Phys. Rev. E 57 (1998) 650.  No real root for e < 1 - C1^2/(4 C2)
    = 0.5833: NaN there (the series has no alpha giving such an e).
    """
    disc = _SP_C1 * _SP_C1 - 4.0 * _SP_C2 * (1.0 - e)
    if disc < 0:
        return math.nan
    return 2.0 * (1.0 - e) / (_SP_C1 + math.sqrt(disc))  # smaller root, cancellation-free


_MP = (0.501086, 1.15345, 0.577977, 0.532178)


def muller_poschel_e(alpha: float) -> float:
    """Pade approximant e(alpha), s = sqrt(alpha):
    e = (1 + 0.501086 s)/(1 + 0.501086 s + 1.15345 s^2 + 0.577977 s^3 + 0.532178 s^4).
    P. Muller, T. Poschel, Phys. Rev. E 84 (2011) 021302."""
    s = math.sqrt(alpha)
    a, b, c, d = _MP
    return (1.0 + a * s) / (1.0 + a * s + b * s**2 + c * s**3 + d * s**4)


def _muller_poschel(e: float) -> float:
    """Inverse of the Muller-Poschel Pade approximant (monotone in alpha), by bracketing.
    P. Muller, T. Poschel, Phys. Rev. E 84 (2011) 021302."""
    if e == 1.0:
        return 0.0
    hi = 1.0
    while muller_poschel_e(hi) > e:
        hi *= 4.0
        if hi > 1e120:  # pragma: no cover - only for e below ~1e-180
            return math.nan
    from scipy.optimize import brentq

    return brentq(lambda a: muller_poschel_e(a) - e, 0.0, hi, xtol=1e-15, rtol=1e-15)


# ----------------------------------------------------------------------------------- Tsuji
def antypov_elliott_alpha(e: float) -> float:
    """alpha = -sqrt(5) ln e / sqrt(ln^2 e + pi^2).

    Exact for the Tsuji law with the zero-overlap criterion (checked against the published values of Jian et al. 2019).
    D. Antypov, J.A. Elliott, EPL 94 (2011) 50004.  This is also the formula inside LAMMPS
    ``coeff_restitution``, LIGGGHTS ``hertz``, Chrono SMC Hertz, DEM-Engine, MercuryDPM and
    Yade up to 2022.01a (Yade 2023.02a and Kratos DEM use :func:`thornton_gamma`; see
    :mod:`viscontact.audit.engines`).
    """
    le = math.log(e)
    return -SQRT5 * le / math.sqrt(le * le + math.pi**2)


def antypov_elliott_inverse(alpha: float) -> float:
    """The e that :func:`antypov_elliott_alpha` maps to ``alpha``; ValueError for alpha >= sqrt(5)."""
    if not (0.0 <= alpha < SQRT5):
        raise ValueError(f"the Antypov-Elliott formula reaches only alpha < sqrt(5) = {SQRT5:.6f}; "
                         f"alpha = {alpha:.6g} needs a larger damping than it can express")
    return math.exp(-math.pi * alpha / math.sqrt(5.0 - alpha * alpha))


_TSUJI_COEFFS = (1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218)


def tsuji_polynomial(e: float) -> float:
    """The Tsuji et al. (1992) alpha(e) curve as LAMMPS documents it (Marshall 2009, eq. 53):
    alpha = 1.2728 - 4.2783 e + 11.087 e^2 - 22.348 e^3 + 27.467 e^4 - 18.022 e^5 + 4.8218 e^6."""
    return float(np.polynomial.polynomial.polyval(e, _TSUJI_COEFFS))


#: Thornton, Cummins & Cleary (2013), Powder Technol. 233, 30-46, Appendix B: the fit of
#: eq. (B7), ln-term a(e) = sum_{i=1..10} h_i e^i, with the h_i of their Table 2 (as quoted,
#: with the same digits, in Yade 2023.02a pkg/dem/HertzMindlin.cpp and Kratos 10.4.4
#: DEMApplication/sphere_strategy.py GammaForHertzThornton).
THORNTON_H = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29,
              -11342.18, 6276.757, -1489.915)


def thornton_gamma(e: float) -> float:
    """The damping ratio gamma(e) of Thornton et al. (2013), eqs. (B6)-(B7):

    a(e) = sum_{i=1..10} h_i e^i (B7),  gamma = sqrt(1 / (1 - (1 + e)^2 exp(a)) - 1) (B6).

    Fitted for a Hertz spring with the dashpot c = 2 gamma sqrt(m* k_t), k_t = dF/d(delta)
    = 2 E* sqrt(R* delta) the tangent stiffness, and a contact that ends at zero force.
    Strictly decreasing on (0, 1); it tends to 0.00453 (not 0) as e -> 1, so the engines that
    use it special-case e = 1 (Yade, and this function) or e > 0.999 (Kratos) to gamma = 0.
    C. Thornton, S.J. Cummins, P.W. Cleary, Powder Technol. 233 (2013) 30.
    """
    if e == 1.0:
        return 0.0  # the fit's limit is 0.00453; Yade sets 0 for en = 1 exactly, so do we
    a = 0.0
    for h in reversed(THORNTON_H):  # Horner: e (h1 + e (h2 + ... + e h10))
        a = a * e + h
    a *= e
    return math.sqrt(1.0 / (1.0 - (1.0 + e) ** 2 * math.exp(a)) - 1.0)


#: our Ts alpha per unit Thornton gamma: c = 2 gamma sqrt(m* 2 E* sqrt(R* delta))
#: = 2 sqrt(3/2) gamma sqrt(m* k_Hertz) delta^(1/4), since 2 E* sqrt(R*) = (3/2) k_Hertz
THORNTON_ALPHA_PER_GAMMA = 2.0 * math.sqrt(1.5)


def thornton_alpha(e: float) -> float:
    """Our Ts alpha for the Thornton et al. (2013) fit: alpha = sqrt(6) gamma(e) (eqs. B6-B7)."""
    return THORNTON_ALPHA_PER_GAMMA * thornton_gamma(e)


def _tsuji_lammps(e: float) -> float:
    """Tsuji curve as in the LAMMPS ``pair granular`` documentation (damping tsuji).
    Y. Tsuji, T. Tanaka, T. Ishida, Powder Technol. 71 (1992) 239; J.S. Marshall,
    J. Comput. Phys. 228 (2009) 1541, eq. 53; LAMMPS doc/src/pair_granular.rst."""
    return tsuji_polynomial(e)


def _tsuji_lammps_sqrt2(e: float) -> float:
    """Tsuji curve times sqrt(2), as recent LAMMPS applies it ("effective mass convention").
    LAMMPS src/GRANULAR/gran_sub_mod_damping.cpp, GranSubModDampingTsuji::init()."""
    return math.sqrt(2.0) * tsuji_polynomial(e)


# ------------------------------------------------------------------------- any law (energy)
@lru_cache(maxsize=64)
def first_order_coefficient(p: float) -> float:
    """I1(p) = (5/4)^(2(p+1)/5 - 1) B(2(p+1)/5, 3/2): 1 - e = I1(p) alpha + O(alpha^2).

    The energy dissipated along the undamped Hertz trajectory, to first order in alpha.
    """
    from scipy.special import beta as beta_fn

    q = 2.0 * (p + 1.0) / 5.0
    return 1.25 ** (q - 1.0) * float(beta_fn(q, 1.5))


@dataclass(frozen=True)
class Formula:
    """One published calibration alpha(e) for one law.

    Attributes:
        name: registry key (lower case, hyphenated).
        title: short human name.
        model: the viscontact law the alpha belongs to ("Hunt", "KK", "Ts", ..., "power").
        p: the exponent, only for model "power".
        derived_for: the end-of-contact criterion the formula was derived or fitted for
            ("force", "overlap", "both" when they coincide, or None when not stated/approximate).
        reference: the paper(s).
        func: e -> alpha (NaN where the formula has no alpha).
    """

    name: str
    title: str
    model: str
    reference: str
    func: Callable[[float], float]
    derived_for: str | None = None
    p: float | None = None

    def alpha(self, e: float) -> float:
        """The alpha this formula prescribes for restitution ``e`` (NaN if it prescribes none)."""
        e = _check_e(e)
        a = float(self.func(e))
        if math.isfinite(a) and a < 0:
            return math.nan
        return a

    @property
    def law_label(self) -> str:
        return f"power (p = {self.p:g})" if self.model == Power.name else self.model


def first_order_formula(model: str, p: float | None = None) -> Formula:
    """The first-order energy estimate 1 - e = I1(p) alpha for any law (not Jian)."""
    law = lookup(model)
    if law.needs_beta:
        raise ValueError("the first-order estimate is for laws with g = 1; Jian has a relaxation factor")
    pp = exponent(law, p)
    suffix = law.name.lower() if law.p is not None else f"power-p{pp:g}"
    return Formula(
        name=f"first-order-{suffix}", title=f"first-order energy ({law.name})", model=law.name,
        reference="energy dissipated along the undamped Hertz path, 1 - e = I1(p) alpha",
        # I1(p) on first use: the registry is built at import, scipy.special only when needed
        func=lambda e: (1.0 - e) / first_order_coefficient(pp), derived_for=None,
        p=pp if law.p is None else None,
    )


_REGISTERED: tuple[Formula, ...] = (
    Formula("hunt-crossley", "Hunt-Crossley / Marhefka-Orin", Hunt.name,
            "K.H. Hunt, F.R.E. Crossley, J. Appl. Mech. 42 (1975) 440; D.W. Marhefka, D.E. Orin, "
            "IEEE Trans. SMC-A 29 (1999) 566", _hunt_crossley),
    Formula("lee-wang", "Lee-Wang", Hunt.name,
            "T.W. Lee, A.C. Wang, J. Mech. Transm. Autom. Des. 105 (1983) 534", _lee_wang),
    Formula("herbert-mcwhannell", "Herbert-McWhannell", Hunt.name,
            "R.G. Herbert, D.C. McWhannell, J. Eng. Ind. 99 (1977) 513", _herbert_mcwhannell),
    Formula("lankarani-nikravesh", "Lankarani-Nikravesh", Hunt.name,
            "H.M. Lankarani, P.E. Nikravesh, J. Mech. Des. 112 (1990) 369", _lankarani_nikravesh),
    Formula("gonthier", "Gonthier et al.", Hunt.name,
            "Y. Gonthier, J. McPhee, C. Lange, J.-C. Piedboeuf, Multibody Syst. Dyn. 11 (2004) 209",
            _gonthier),
    Formula("zhiying-qishao", "Zhiying-Qishao", Hunt.name,
            "Q. Zhiying, L. Qishao (2006), as tabulated by P. Flores et al., Multibody Syst. Dyn. 25 (2011) 357", _zhiying_qishao),
    Formula("flores", "Flores et al.", Hunt.name,
            "P. Flores, M. Machado, M.T. Silva, J.M. Martins, Multibody Syst. Dyn. 25 (2011) 357",
            _flores),
    Formula("gharib-hurmuzlu", "Gharib-Hurmuzlu", Hunt.name,
            "M. Gharib, Y. Hurmuzlu, J. Appl. Mech. (2012)", _gharib_hurmuzlu),
    Formula("hu-guo", "Hu-Guo", Hunt.name, "S. Hu, X. Guo, Multibody Syst. Dyn. (2015)", _hu_guo),
    Formula("carvalho-martins", "exact Hunt relation (Carvalho-Martins)", Hunt.name,
            "(1+e) alpha = ln((1+alpha)/(1-alpha e)); A.S. Carvalho, J.M. Martins, Mech. Mach. "
            "Theory (2019)", hunt_exact_alpha, derived_for="both"),
    Formula("schwager-poschel", "Schwager-Poschel series", KK.name,
            "T. Schwager, T. Poschel, Phys. Rev. E 57 (1998) 650", _schwager_poschel,
            derived_for="overlap"),
    Formula("muller-poschel", "Muller-Poschel Pade", KK.name,
            "P. Muller, T. Poschel, Phys. Rev. E 84 (2011) 021302", _muller_poschel,
            derived_for="force"),
    Formula("antypov-elliott", "Antypov-Elliott", Ts.name,
            "D. Antypov, J.A. Elliott, EPL 94 (2011) 50004", antypov_elliott_alpha,
            derived_for="overlap"),
    Formula("thornton-2013", "Thornton-Cummins-Cleary fit", Ts.name,
            "C. Thornton, S.J. Cummins, P.W. Cleary, Powder Technol. 233 (2013) 30, eqs. B6-B7 "
            "(Table 2 coefficients); alpha = sqrt(6) gamma", thornton_alpha, derived_for="force"),
    Formula("tsuji-lammps", "Tsuji curve (LAMMPS doc)", Ts.name,
            "Y. Tsuji et al., Powder Technol. 71 (1992) 239; J.S. Marshall, J. Comput. Phys. 228 "
            "(2009) 1541 eq. 53; LAMMPS doc pair_granular", _tsuji_lammps),
    Formula("tsuji-lammps-sqrt2", "Tsuji curve x sqrt(2) (LAMMPS source)", Ts.name,
            "as tsuji-lammps, times sqrt(2): LAMMPS src/GRANULAR/gran_sub_mod_damping.cpp",
            _tsuji_lammps_sqrt2),
) + tuple(first_order_formula(m) for m in (LH.name, Ts.name, KK.name, Li.name, Hunt.name))

FORMULAS: dict[str, Formula] = {f.name: f for f in _REGISTERED}


def get_formula(name: str, *, model: str | None = None, p: float | None = None) -> Formula:
    """The registered formula ``name`` (case-insensitive); ``first-order`` takes ``model``/``p``."""
    if not isinstance(name, str):
        raise ValueError(f"formula name must be a string, got {name!r}")
    key = name.strip().lower()
    if key == "first-order":
        if model is None:
            raise ValueError("formula first-order needs a model (--law NAME)")
        return first_order_formula(model, p)
    if key in FORMULAS:
        if model is not None and lookup(model).name != FORMULAS[key].model:
            raise ValueError(f"formula {key} is for model {FORMULAS[key].model}, not {model}")
        return FORMULAS[key]
    raise ValueError(f"unknown formula {name!r}; valid formulas are: first-order, {', '.join(FORMULAS)}")


# ------------------------------------------------------------------------- exact numbers
@lru_cache(maxsize=4096)
def _exact_alpha_cached(model: str, p: float | None, e: float, end: str) -> float:
    if model == Hunt.name:
        return hunt_exact_alpha(e)  # exact for both criteria (tested against the solver)
    try:
        return float(alpha_from_e(model, e, p=p, end=end))
    except ValueError:
        return math.nan


def exact_alpha(model: str, e: float, end: str = "force", *, p: float | None = None) -> float | None:
    """The alpha that gives exactly ``e`` for ``model`` under ``end`` (None if unreachable)."""
    check_end(end)
    a = _exact_alpha_cached(lookup(model).name, None if p is None else float(p),
                            _check_target_e(e), end)
    return a if math.isfinite(a) else None


@lru_cache(maxsize=8192)
def _delivered_cached(model: str, p: float | None, alpha: float, end: str) -> float:
    return float(restitution(model, alpha, p=p, end=end))


def delivered_e(model: str, alpha: float | None, end: str = "force", *,
                p: float | None = None) -> float | None:
    """The restitution that ``alpha`` really gives (exact solve); None when there is no alpha
    or it lies outside the domain of alpha ([0, 1000]: a formula may prescribe more; see
    :func:`missing_alpha_reason`)."""
    check_end(end)
    if alpha is None:
        return None
    alpha = domain.check_number("alpha", alpha)
    if not domain.DOMAIN["alpha"].contains(alpha):
        return None
    return _delivered_cached(lookup(model).name, None if p is None else float(p), float(alpha), end)


def missing_alpha_reason(alpha: float | None, owner: str) -> str:
    """Why an alpha gives no delivered e (``owner``: whose alpha, e.g. "the formula"), or ""
    when it gives one."""
    if alpha is None:
        return f"{owner} gives no alpha for this e; no delivered e"
    if not domain.DOMAIN["alpha"].contains(alpha):
        return (f"{owner}'s alpha {alpha:.6g} is outside the domain "
                f"{domain.range_text('alpha')}; no delivered e")
    return ""


@dataclass(frozen=True)
class FormulaAudit:
    """What one formula gives for one target e and one end criterion.

    A value that does not exist is None (never NaN), and ``note`` says why (docs/audit.md).

    Attributes:
        formula, model, end: which formula, law and end criterion (``force``/``overlap``).
        target_e: the restitution the user asked for.
        alpha: the formula's alpha (None when it has none for this e).
        delivered_e: the restitution that alpha really produces (exact solve; None without an
            alpha or for an alpha outside the domain [0, 1000]).
        error: delivered_e - target_e (None with delivered_e).
        exact_alpha: the alpha that gives target_e exactly (None if unreachable).
        note: why a value is None ("" when none is).
    """

    formula: str
    model: str
    end: str
    target_e: float
    alpha: float | None
    delivered_e: float | None
    error: float | None
    exact_alpha: float | None
    derived_for: str | None = None
    p: float | None = None
    note: str = ""

    def to_dict(self) -> dict:
        return {
            "formula": self.formula, "model": self.model, "p": self.p, "end": self.end,
            "derived_for": self.derived_for, "target_e": self.target_e, "alpha": self.alpha,
            "delivered_e": self.delivered_e, "error": self.error, "exact_alpha": self.exact_alpha,
            "note": self.note,
        }


def audit_formula(formula: Formula | str, e: float, end: str = "force") -> FormulaAudit:
    """Audit one formula at one target ``e`` under one end criterion."""
    f = get_formula(formula) if isinstance(formula, str) else formula
    if not isinstance(f, Formula):
        raise ValueError(f"formula must be a formula name or a Formula, got {formula!r}")
    check_end(end)
    e = _check_target_e(e)
    a = f.alpha(e)
    a = a if math.isfinite(a) else None
    d = delivered_e(f.model, a, end, p=f.p)
    ex = exact_alpha(f.model, e, end, p=f.p)
    notes = [missing_alpha_reason(a, "the formula")]
    if ex is None:
        notes.append(unreachable_reason(f.model, e, end))
    return FormulaAudit(
        formula=f.name, model=f.model, end=end, target_e=e, alpha=a, delivered_e=d,
        error=None if d is None else d - e, exact_alpha=ex,
        derived_for=f.derived_for, p=f.p, note="; ".join(n for n in notes if n),
    )


def unreachable_reason(model: str, e: float, end: str) -> str:
    """Why no alpha gives ``e`` (the note of a None exact alpha)."""
    return (f"the {model} law cannot reach e = {e:g} under the zero-{end} criterion with alpha "
            f"in {domain.range_text('alpha')}")
