"""The DEM lines written from an e(v) fit deliver the fitted e(v) in LAMMPS: a sphere hitting
the wall at three speeds of the data gives the fitted e to 1e-3 (real LAMMPS with the plugin;
skipped with the reason when absent).  ``scripts/dem_collide.py`` runs and measures; it knows
nothing of the force law."""

from __future__ import annotations

import numpy as np
import pytest

from dem_util import needs_lammps

pytestmark = needs_lammps

from viscontact import dem  # noqa: E402
from viscontact.dem.fromfit import fit_lines, law_from_fit  # noqa: E402
from viscontact.fit.restitution import fit_restitution, model_e, restitution_data  # noqa: E402

import dem_collide as dc  # noqa: E402

V = np.geomspace(0.4, 3.0, 8)
MAT = dc.Material(1.0e7, 0.3, 1100.0)


@pytest.mark.parametrize("law, second", [("Jian", 0.5), ("power", 0.8), ("Ts", None)])
def test_fitted_lines_deliver_the_fitted_e(law, second):
    kw = {"beta": second} if law == "Jian" else {"p": second} if law == "power" else {}
    e = model_e(law, V, 1.0, 0.4, **kw) + 3e-3 * np.sin(9 * V)  # not exactly the law
    fit = fit_restitution(restitution_data(V, e), [law])
    one = fit.laws[fit.ranking[0]]
    lines = fit_lines(fit, E=MAT.E, nu=MAT.nu)
    dl = law_from_fit(fit)
    # the fit's lines are the one writer's: the same as dem coeff writes for this law
    assert lines.pair_coeff == dem.coeff_lines(dl, E=MAT.E, nu=MAT.nu, plugin="x").pair_coeff
    speeds = V[[1, 4, 7]]
    shots = [dc.Shot("wall", float(v)) for v in speeds]
    measured = dc.run(dc.Setup(dl, MAT, 0.01, shots, wall="rigid", steps_per_tc=1000))
    got = np.array([m.e for m in measured])
    np.testing.assert_allclose(got, one.e_at(speeds), rtol=0, atol=1e-3)
