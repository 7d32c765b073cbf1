import pytest

import viscontact as vc
from viscontact.physics import laws as laws_mod
from viscontact.physics.laws import LAWS, ContactLaw, resolve, substitution_order


def test_registry_lists_every_law_once():
    assert vc.MODELS == ("LH", "Ts", "KK", "Li", "Hunt", "Jian", "power")
    # every law class the module defines is registered (the registry is a hand-written list)
    defined = sorted(c.name for c in vars(laws_mod).values()
                     if isinstance(c, type) and issubclass(c, ContactLaw) and c is not ContactLaw)
    assert defined == sorted(vc.MODELS)
    # names are looked up case-insensitively: no two may differ only in case
    assert len({n.lower() for n in vc.MODELS}) == len(vc.MODELS)


@pytest.mark.parametrize("name", vc.MODELS)
def test_each_law_documents_equation_units_reference(name):
    doc = LAWS[name].__doc__
    assert "F = " in doc and "Non-dimensional" in doc and "[" in doc  # equation and units
    assert LAWS[name].reference


def test_exponents_and_history():
    assert [LAWS[n].p for n in ("LH", "Ts", "KK", "Li", "Hunt", "Jian")] == [0, 0.25, 0.5, 1, 1.5, 0.5]
    assert LAWS["Jian"].needs_beta and LAWS["Jian"].history == ("contact_start_time",)
    assert all(not LAWS[n].history for n in vc.MODELS if n != "Jian")


def test_substitution_keeps_powers_integral():
    for p in (0, 0.25, 0.5, 0.75, 1, 1.5, 2, 1 / 3):
        m = substitution_order(p)
        assert m % 2 == 0 and (float(m * p).is_integer() or m == 2)
    assert substitution_order(0.25) == 4


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        ({"model": "Foo"}, "valid models are: LH, Ts, KK, Li, Hunt, Jian, power"),
        ({"model": "Jian"}, "needs beta"),
        ({"model": "KK", "beta": 0.5}, "takes no beta"),
        ({"model": "power"}, "needs the exponent p"),
        ({"model": "power", "p": -1}, r"p must be in \[0, 10\]"),
        ({"model": "power", "p": float("nan")}, r"p must be in \[0, 10\]"),
        ({"model": "Jian", "beta": float("inf")}, r"beta must be in \[0, 1000\]"),
        ({"model": "Hunt", "p": 1.5}, "fixed exponent"),
    ],
)
def test_bad_law_parameters_raise_value_error(kwargs, fragment):
    model = kwargs.pop("model")
    with pytest.raises(ValueError, match=fragment):
        resolve(model, **kwargs)


def test_model_names_case_insensitive():
    assert resolve("kk").name == "KK" and resolve("HUNT").name == "Hunt"
