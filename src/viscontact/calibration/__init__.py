"""Calibration: the inverse of the collision, alpha from a target restitution e, and back
(imports physics, solvers, collision and _support).

:mod:`.inverse` holds the public functions (:func:`restitution`, :func:`alpha_from_e`); they
answer through precomputed interpolants of e(alpha) (and e(alpha, beta) for Jian): the table
(:mod:`.table`), its compiled evaluation and inversion (:mod:`._interp`), its building and
verification against the exact solver (:mod:`.build`), and its cache and entry point
(:mod:`.tables`).  Outside a table's range the exact solver answers.
"""

from .inverse import ALPHA_MAX, alpha_from_e, restitution

__all__ = ["ALPHA_MAX", "alpha_from_e", "restitution"]
