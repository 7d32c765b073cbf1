"""LAMMPS lines from a fit of e(v) (:func:`viscontact.fit.fit_restitution`).

The fitted constants go on the lines in the alpha form (``alpha A vref V [beta B]``, the
fitted alpha_ref and beta_ref at the fit's v_ref): the plugin turns them into each pair's c0
(and tau) from that pair's m* and k_Hertz (:mod:`.law`), so every contact, whatever its
masses and radii, has the fitted e(v).  Sphere-sphere contacts therefore inherit the
ball-plate curve that was measured; the lines' elastic part (``hertz/material E NU``) needs
the particles' E and nu, which e(v) does not determine.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..fit.restitution import RestitutionFit, RestitutionLawFit
from ..physics.laws import lookup
from .coeff import WALL_FIX_ID, contact_words
from .law import DemLaw
from .materials import Wall
from .submodels import SubModels
from .units import check_units

__all__ = ["law_from_fit", "FitLines", "fit_lines"]


def law_from_fit(fit: RestitutionFit | RestitutionLawFit, law: str | None = None) -> DemLaw:
    """The :class:`DemLaw` (alpha form at the fit's v_ref) of ``law`` in ``fit`` (a whole
    :class:`RestitutionFit`: its best law unless ``law`` names one; or one law's fit)."""
    if isinstance(fit, RestitutionFit):
        if law is None:
            one = fit.best
        else:
            name = lookup(law).name
            if name not in fit.laws:
                raise ValueError(f"--dem-law {law}: that law was not fitted (fitted: "
                                 f"{', '.join(fit.laws)})")
            one = fit.laws[name]
    elif isinstance(fit, RestitutionLawFit):
        one = fit
    else:
        raise ValueError(f"fit must be a RestitutionFit or RestitutionLawFit, got "
                         f"{type(fit).__name__}")
    spec = lookup(one.law)
    return DemLaw(law=spec.name, p=one.p, end=one.end, alpha=one.alpha, vref=one.vref,
                  beta=one.beta if spec.needs_beta else None)


@dataclass(frozen=True)
class FitLines:
    """The damping keywords of a fitted law and, with E and nu, its ``pair_style``,
    ``pair_coeff * *`` and rigid-floor wall-fix lines; ``notes`` say what they assume."""

    law: DemLaw
    keywords: str
    pair_style: str | None = None
    pair_coeff: str | None = None
    wall_fix: str | None = None
    notes: list[str] = field(default_factory=list)

    def lines(self) -> list[str]:
        return [x for x in (self.pair_style, self.pair_coeff, self.wall_fix) if x]

    def to_dict(self) -> dict[str, Any]:
        return {"law": self.law.law, "keywords": self.keywords, "lines": self.lines(),
                "notes": self.notes, **self.law.to_dict()}


def fit_lines(fit: RestitutionFit | RestitutionLawFit, *, law: str | None = None,
              E: float | None = None, nu: float | None = None, units: str = "si") -> FitLines:
    """The lines for ``law`` of ``fit`` (its best by default), written by the one writer of
    contact keywords (:func:`viscontact.dem.coeff.contact_words`); the plugin load line is
    ``viscontact dem plugin``'s."""
    units = check_units(units)
    dl = law_from_fit(fit, law)
    notes = ["sphere-sphere contacts inherit the ball-plate e(v) that was fitted (the alpha "
             "form gives every pair the same e at the same impact speed)"]
    if (E is None) != (nu is None):
        raise ValueError("the lines' elastic part needs both E and nu (--E and --nu)")
    if E is None:
        notes.append("the lines' elastic part (hertz/material E NU) needs the particles' E and "
                     "nu: give --E and --nu for complete pair_coeff and wall lines")
        return FitLines(dl, dl.keywords(units), notes=notes)
    sub = SubModels.build()
    floor = Wall("zplane", (0.0, None), "rigid")
    return FitLines(
        dl, dl.keywords(units), pair_style="pair_style viscontact",
        pair_coeff=f"pair_coeff * * {contact_words(dl, sub, units, E=E, nu=nu)}",
        wall_fix=(f"fix {WALL_FIX_ID} all viscontact/wall "
                  + contact_words(dl, sub, units, wall=floor, wall_material=None)),
        notes=notes + ["load the plugin first: `viscontact dem plugin` prints its line"])
