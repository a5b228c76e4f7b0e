"""The translation driver: work shared between the discrete states of a model.

The systems of one model share what was derived from each equation (its
specialisation, time derivative, solution and printed code), and discrete
states with the same equations share one compiled system.  Neither may change
what a state's system is: these tests compile states in different orders and
compare with states compiled alone.
"""

import numpy as np
import pytest

from acausal import simulate, translate
from acausal.codegen import python_identifiers
from examples.coupled_clutches import CoupledClutches


@pytest.fixture(scope="module")
def visited():
    """A CoupledClutches translation after a full simulation."""
    translation = translate(CoupledClutches(), cache=False)
    result = simulate(translation)
    assert result.success
    return translation


def test_states_with_equal_equations_share_one_system(visited):
    systems = visited.systems
    shared = [s for s in systems.values() if s.shares is not None]
    # pre(mode) of a clutch that slides on selects nothing: such states repeat
    assert shared, "CoupledClutches visits states that differ only in unused pre values"
    assert visited.compiled_systems == len(systems) - len(shared)
    for system in shared:
        twin = systems[system.shares]
        assert twin.shares is None
        assert [e.residual for e in system.equations] == [e.residual for e in twin.equations]
        assert system.key != twin.key


def test_states_with_different_equations_never_share(visited):
    compiled = [s for s in visited.systems.values() if s.shares is None]
    signatures = {tuple(e.residual for e in s.equations) for s in compiled}
    assert len(signatures) == len(compiled)


def test_code_does_not_depend_on_the_order_states_are_compiled(visited):
    """Each state compiled alone in a fresh translation gets the same code."""
    for key, system in list(visited.systems.items())[::-1]:
        alone = translate(CoupledClutches(), cache=False).system(key)
        source = visited.systems[system.shares].code.source if system.shares else system.code.source
        # the first line names the state the code was generated for
        assert alone.code.source.split("\n", 1)[1] == source.split("\n", 1)[1]
        # and it computes the same values
        x = np.linspace(0.1, 0.9, len(alone.states))
        assert np.allclose(alone.outputs(0.3, x), system.outputs(0.3, x), rtol=1e-14, atol=0)


def test_python_identifiers_are_readable_and_distinct():
    names = ["J1.w", "der(J1.w)", "J1_w", "t", "x", "if", "_private", "1st.value", "der(der(J1.phi))",
             "max", "abs"]
    identifiers = python_identifiers(names)
    assert identifiers["J1.w"] == "J1_w"
    assert identifiers["der(J1.w)"] == "der_J1_w"
    assert identifiers["der(der(J1.phi))"] == "der_der_J1_phi"
    values = list(identifiers.values())
    assert len(set(values)) == len(values)
    for ident in values:
        assert ident.isidentifier()
        assert ident not in {"t", "x", "p", "if", "max", "abs"} and not ident.startswith("_")
