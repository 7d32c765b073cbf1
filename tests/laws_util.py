"""The parameter a law takes besides alpha, for the tests that loop over every law."""

from viscontact.physics.laws import lookup


def law_kwargs(model: str, beta: float | None = 0.5, p: float | None = 0.75) -> dict[str, float]:
    """``{"beta": beta}`` for a law with a relaxation time (Jian: beta = tau/T), ``{"p": p}``
    for the general power law (its exponent), ``{}`` for the laws of fixed exponent."""
    law = lookup(model)
    if law.needs_beta:
        return {"beta": beta}
    return {"p": p} if law.p is None else {}
