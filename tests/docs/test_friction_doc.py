"""docs/friction.md: its snippet runs and gives the closed form, and every element and
parameter the page names exists as named."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import acausal.library.rotational as rotational
import acausal.library.translational as translational

PAGE = Path(__file__).resolve().parents[2] / "docs" / "friction.md"


def test_the_snippet_slides_to_rest_as_the_closed_form_says(capsys):
    (block,) = re.findall(r"```python\n(.*?)```", PAGE.read_text(), re.S)
    exec(compile(block, str(PAGE), "exec"), {})
    t_stop, s, v = (float(x) for x in capsys.readouterr().out.split())
    m, v0, f_c = 2.0, 3.0, 4.0
    assert t_stop == pytest.approx(m * v0 / f_c, abs=1e-9)       # 1.5 s
    assert s == pytest.approx(m * v0 ** 2 / (2 * f_c), abs=1e-8)  # 2.25 m
    assert abs(v) < 1e-9                                          # at rest (the relation's margin)


@pytest.mark.parametrize("package, name, parameters", [
    (rotational, "BearingFriction", ["tau_pos", "peak", "useSupport", "useHeatPort", "w_small", "K_locked"]),
    (rotational, "Clutch", ["fn_max", "mu_pos", "cgeo", "peak", "useHeatPort"]),
    (rotational, "Brake", ["fn_max", "mu_pos", "cgeo", "useSupport", "useHeatPort"]),
    (rotational, "OneWayClutch", ["fn_max", "mu_pos"]),
    (rotational, "LossyGear", ["lossTable", "useSupport", "useHeatPort"]),
    (translational, "SupportFriction", ["f_pos", "peak", "useSupport", "useHeatPort", "v_small"]),
    (translational, "Brake", ["fn_max", "mu_pos", "cgeo", "useSupport", "useHeatPort"]),
    (translational, "MassWithStopAndFriction", ["F_Coulomb", "F_prop", "F_Stribeck", "fexp", "smin", "smax"]),
])
def test_the_elements_and_parameters_named_exist(package, name, parameters):
    assert name in PAGE.read_text()
    declared = getattr(package, name).declarations()
    missing = [p for p in parameters if p not in declared]
    assert not missing, f"{name} has no {missing}"
