"""The numpy Runge-Kutta pairs of :mod:`acausal.runtime.explicit_rk` against scipy's.

``RK45`` and ``DOP853`` are meant to take scipy's steps: the same accepted
step times (to 1e-12 relative), the same states (to a few ulps per step),
the same dense output inside each step, the same number of evaluations.
They are also checked against closed-form solutions (exp(-t), cos/sin), and
the module must not import scipy.
"""

from __future__ import annotations

import ast
import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.integrate

from acausal.runtime import explicit_rk
from acausal.runtime.explicit_rk import DOP853, RK45

MODULE = Path(explicit_rk.__file__)
EPS = np.finfo(float).eps
PAIRS = [pytest.param(RK45, scipy.integrate.RK45, id="RK45"),
         pytest.param(DOP853, scipy.integrate.DOP853, id="DOP853")]


# -- problems --------------------------------------------------------------------------------------

def decay(t, y):
    return -y


def oscillator(t, y):
    return np.array([y[1], -y[0]])


def van_der_pol(t, y, mu=1.0):
    return np.array([y[1], mu * (1 - y[0] ** 2) * y[1] - y[0]])


def lotka_volterra(t, y):
    a, b, c, d = 1.5, 1.0, 3.0, 1.0
    return np.array([a * y[0] - b * y[0] * y[1], -c * y[1] + d * y[0] * y[1]])


def forced(t, y):
    """Non-autonomous, three states of different scales."""
    return np.array([-2 * y[0] + math.sin(3 * t), 1e3 * y[0] - 0.5 * y[1], 1e-3 * math.cos(t) - y[2]])


# name: (fun, t0, y0, t_bound, keywords)
PROBLEMS = {
    "decay": (decay, 0.0, [1.0], 10.0, {}),
    "decay-tight": (decay, 0.0, [1.0], 10.0, dict(rtol=1e-10, atol=1e-12)),
    "oscillator": (oscillator, 0.0, [1.0, 0.0], 20.0, dict(rtol=1e-8, atol=1e-10)),
    "van-der-pol": (van_der_pol, 0.0, [2.0, 0.0], 20.0, {}),
    "van-der-pol-tight": (van_der_pol, 0.0, [2.0, 0.0], 20.0, dict(rtol=1e-9, atol=1e-11)),
    "lotka-volterra": (lotka_volterra, 0.0, [10.0, 5.0], 15.0, dict(rtol=1e-6, atol=1e-8)),
    "vector-atol": (forced, 0.0, [1.0, 0.0, 1e-3], 10.0, dict(rtol=1e-7, atol=[1e-9, 1e-6, 1e-12])),
    "max-step": (van_der_pol, 0.0, [2.0, 0.0], 10.0, dict(max_step=0.05)),
    "first-step": (lotka_volterra, 0.0, [10.0, 5.0], 5.0, dict(first_step=1e-4, rtol=1e-7)),
    "backwards": (lotka_volterra, 5.0, [10.0, 5.0], -3.0, dict(rtol=1e-7, atol=1e-9)),
    "backwards-decay": (decay, 0.0, [1.0], -4.0, dict(rtol=1e-8, atol=1e-12)),
    "odd-bound": (oscillator, 0.1, [1.0, 0.0], 1.0 / 3.0 + 2.0, dict(rtol=1e-5)),
    "tiny-interval": (decay, 1.0, [1.0], 1.0 + 1e-9, {}),
    "atol-zero": (oscillator, 0.0, [1.0, 0.5], 3.0, dict(rtol=1e-6, atol=0.0)),
}


def run(cls, fun, t0, y0, t_bound, dense=True, **options):
    """Step to the end; the solver, the times, the states, the steps' interpolants."""
    solver = cls(fun, t0, np.array(y0, dtype=float), t_bound, **options)
    times, states, interpolants = [solver.t], [solver.y.copy()], []
    while solver.status == "running":
        message = solver.step()
        assert message is None, message
        times.append(solver.t)
        states.append(solver.y.copy())
        if dense:
            interpolants.append(solver.dense_output())
    assert solver.status == "finished"
    return solver, np.array(times), np.array(states), interpolants


def both(ours, theirs, name, dense=True):
    fun, t0, y0, t_bound, options = PROBLEMS[name]
    return (run(ours, fun, t0, y0, t_bound, dense, **options),
            run(theirs, fun, t0, y0, t_bound, dense, **options))


def assert_same_run(a, b):
    (sa, ta, ya, _), (sb, tb, yb, _) = a, b
    assert len(ta) == len(tb), f"{len(ta) - 1} steps against scipy's {len(tb) - 1}"
    np.testing.assert_allclose(ta, tb, rtol=1e-12, atol=1e-12 * np.max(np.abs(tb)))
    steps = len(tb) - 1
    # a few ulps per step, relative to the size of the state
    size = np.maximum(np.abs(yb), np.max(np.abs(yb), axis=0))
    assert np.all(np.abs(ya - yb) <= 4 * steps * EPS * size + 1e-300)
    assert sa.t == sb.t
    assert sa.nfev == sb.nfev
    assert sa.njev == sb.njev == 0
    assert sa.nlu == sb.nlu == 0
    assert sa.step_size == pytest.approx(sb.step_size, rel=1e-12)


# -- the same steps as scipy -----------------------------------------------------------------------

@pytest.mark.parametrize("ours, theirs", PAIRS)
@pytest.mark.parametrize("name", list(PROBLEMS))
def test_same_steps_states_and_evaluations_as_scipy(ours, theirs, name):
    a, b = both(ours, theirs, name)
    assert_same_run(a, b)
    # the solver ends exactly on t_bound
    assert a[1][-1] == PROBLEMS[name][3]


@pytest.mark.parametrize("ours, theirs", PAIRS)
@pytest.mark.parametrize("name", ["decay", "oscillator", "van-der-pol-tight", "vector-atol", "backwards",
                                  "odd-bound"])
def test_dense_output_agrees_with_scipy_inside_steps(ours, theirs, name):
    a, b = both(ours, theirs, name)
    assert_same_run(a, b)
    scale = 1.0 + np.max(np.abs(b[2]))
    inside = np.linspace(0.0, 1.0, 11)
    for step, (da, db) in enumerate(zip(a[3], b[3]), start=1):
        assert (da.t_old, da.t) == (db.t_old, db.t)
        times = db.t_old + inside * (db.t - db.t_old)
        # an array of instants: shape (n, m)
        ya, yb = da(times), db(times)
        assert ya.shape == yb.shape == (len(b[2][0]), len(times))
        assert np.max(np.abs(ya - yb)) <= 16 * EPS * scale
        # one instant: shape (n,)
        for t in times[1:-1:3]:
            assert da(t).shape == (len(b[2][0]),)
            assert np.max(np.abs(da(t) - db(t))) <= 16 * EPS * scale
        # the ends of the step (to round-off: the interpolant, not the state)
        assert np.max(np.abs(da(da.t_old) - a[2][step - 1])) <= 1e-12 * scale
        assert np.max(np.abs(da(da.t) - a[2][step])) <= 1e-12 * scale


@pytest.mark.parametrize("cls", [RK45, DOP853])
def test_dense_output_of_many_instants_is_that_of_each_alone(cls):
    """Column j of dense(times) is bit for bit dense(times[j]) (what crossings.states_at needs)."""
    solver, _, _, interpolants = run(cls, van_der_pol, 0.0, [2.0, 0.0], 6.0, rtol=1e-7)
    for dense in interpolants:
        times = np.linspace(dense.t_old, dense.t, 9)
        together = dense(times)
        alone = np.array([dense(t) for t in times]).T
        assert np.array_equal(together.view(np.int64), np.ascontiguousarray(alone).view(np.int64))
        assert np.array_equal(dense(list(times)), together)
    with pytest.raises(ValueError):
        interpolants[0](np.zeros((2, 2)))


# -- against closed forms --------------------------------------------------------------------------

@pytest.mark.parametrize("cls", [RK45, DOP853])
def test_decay_follows_the_exponential(cls):
    solver, times, states, interpolants = run(cls, decay, 0.0, [1.0], 10.0, rtol=1e-10, atol=1e-14)
    assert np.max(np.abs(states[:, 0] - np.exp(-times))) < 1e-9
    for dense in interpolants:
        t = np.linspace(dense.t_old, dense.t, 7)
        assert np.max(np.abs(dense(t)[0] - np.exp(-t))) < 1e-9
    # backwards: exp(-t) grows
    solver, times, states, _ = run(cls, decay, 0.0, [1.0], -3.0, rtol=1e-10, atol=1e-14)
    assert np.all(np.diff(times) < 0)
    assert np.max(np.abs(states[:, 0] / np.exp(-times) - 1)) < 1e-8


@pytest.mark.parametrize("cls", [RK45, DOP853])
def test_oscillator_follows_cos_and_sin(cls):
    solver, times, states, interpolants = run(cls, oscillator, 0.0, [1.0, 0.0], 4 * math.pi,
                                              rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(states[:, 0] - np.cos(times))) < 1e-8
    assert np.max(np.abs(states[:, 1] + np.sin(times))) < 1e-8
    for dense in interpolants:
        t = np.linspace(dense.t_old, dense.t, 7)
        assert np.max(np.abs(dense(t) - np.array([np.cos(t), -np.sin(t)]))) < 1e-8


# -- the contract's edges, as scipy's --------------------------------------------------------------

@pytest.mark.parametrize("ours, theirs", PAIRS)
def test_empty_interval_and_no_equations(ours, theirs):
    for y0, t_bound in (([1.0, 2.0], 0.0), ([], 1.0)):
        a = ours(oscillator if y0 else (lambda t, y: y), 0.0, np.array(y0), t_bound)
        b = theirs(oscillator if y0 else (lambda t, y: y), 0.0, np.array(y0), t_bound)
        assert a.step() is None and b.step() is None
        assert (a.status, a.t, a.t_old, a.nfev) == (b.status, b.t, b.t_old, b.nfev) == ("finished", t_bound, 0.0,
                                                                                        b.nfev)
        assert np.array_equal(a.dense_output()(0.5), b.dense_output()(0.5))
        assert a.dense_output()(np.array([0.0, 0.5])).shape == (len(y0), 2)
        with pytest.raises(RuntimeError):
            a.step()


@pytest.mark.parametrize("ours, theirs", PAIRS)
def test_dense_output_before_a_step(ours, theirs):
    with pytest.raises(RuntimeError):
        ours(decay, 0.0, [1.0], 1.0).dense_output()
    solver = ours(decay, 0.0, [1.0], 1.0)
    assert solver.t_old is None and solver.step_size is None and solver.status == "running"
    assert solver.direction == 1.0 and ours(decay, 0.0, [1.0], -1.0).direction == -1.0


def nan_after_start(t, y):
    return np.zeros(1) if t == 0 else np.full(1, np.nan)


@pytest.mark.parametrize("ours, theirs", PAIRS)
@pytest.mark.parametrize("fun", [lambda t, y: y ** 2, nan_after_start], ids=["pole", "nan"])
def test_a_blow_up_fails_as_scipy_does(ours, theirs, fun):
    """y' = y**2 from y(0) = 1 has a pole at t = 1, and a derivative that is NaN after the start
    makes every step fail: the step shrinks below the resolution."""
    results = []
    for cls in (ours, theirs):
        with np.errstate(all="ignore"):
            solver = cls(fun, 0.0, np.array([1.0]), 2.0)
            message, steps = None, 0
            while solver.status == "running" and steps < 100_000:
                message = solver.step()
                steps += 1
        results.append((solver.status, message, solver.t, steps, solver.nfev))
    assert results[0][0] == "failed"
    assert results[0] == results[1]


@pytest.mark.parametrize("ours, theirs", PAIRS)
@pytest.mark.parametrize("options, error", [
    (dict(first_step=0.0), ValueError), (dict(first_step=2.0), ValueError), (dict(max_step=0.0), ValueError),
    (dict(atol=[1e-6, 1e-6]), ValueError), (dict(atol=-1.0), ValueError)])
def test_invalid_settings_are_refused_as_by_scipy(ours, theirs, options, error):
    for cls in (ours, theirs):
        with pytest.raises(error):
            cls(decay, 0.0, np.array([1.0]), 1.0, **options)


@pytest.mark.parametrize("ours, theirs", PAIRS)
def test_invalid_states_are_refused(ours, theirs):
    for y0 in ([np.nan], [[1.0]], [1j]):
        with pytest.raises(ValueError):
            ours(decay, 0.0, np.array(y0), 1.0)


@pytest.mark.parametrize("ours, theirs", PAIRS)
def test_tiny_rtol_and_unknown_keywords_warn(ours, theirs):
    with pytest.warns(UserWarning, match="rtol"):
        a = ours(decay, 0.0, np.array([1.0]), 1.0, rtol=1e-20)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        b = theirs(decay, 0.0, np.array([1.0]), 1.0, rtol=1e-20)
    assert a.rtol == b.rtol == 100 * EPS
    with pytest.warns(UserWarning, match="jac"):
        ours(decay, 0.0, np.array([1.0]), 1.0, jac=None)


@pytest.mark.parametrize("cls", [RK45, DOP853])
def test_vectorized_right_hand_side_takes_the_same_steps(cls):
    def columns(t, y):
        return np.vstack([y[1], (1 - y[0] ** 2) * y[1] - y[0]])
    a = run(cls, van_der_pol, 0.0, [2.0, 0.0], 5.0)
    b = run(cls, columns, 0.0, [2.0, 0.0], 5.0, vectorized=True)
    assert np.array_equal(a[1], b[1]) and np.array_equal(a[2], b[2])


def test_dop853_builds_a_steps_interpolant_once():
    solver = DOP853(van_der_pol, 0.0, np.array([2.0, 0.0]), 1.0)
    solver.step()
    nfev = solver.nfev
    first = solver.dense_output()
    assert solver.nfev == nfev + 3  # its three extra stages
    assert solver.dense_output() is first and solver.nfev == nfev + 3
    solver.step()
    assert solver.dense_output() is not first


# -- numpy only ------------------------------------------------------------------------------------

def test_the_module_imports_numpy_only():
    imported = set()
    for node in ast.walk(ast.parse(MODULE.read_text())):
        if isinstance(node, ast.Import):
            imported |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            assert node.level == 0, "no relative imports: the module must load on its own"
            imported.add(node.module.split(".")[0])
    assert imported <= {"__future__", "math", "warnings", "numpy"}


def test_loading_the_module_does_not_import_scipy():
    # `import acausal` imports scipy (the runtime, the compiler), so the module's file is
    # loaded on its own, as a module of no package
    code = ("import importlib.util, sys\n"
            f"spec = importlib.util.spec_from_file_location('explicit_rk', {str(MODULE)!r})\n"
            "module = importlib.util.module_from_spec(spec)\n"
            "spec.loader.exec_module(module)\n"
            "import numpy as np\n"
            "solver = module.DOP853(lambda t, y: -y, 0.0, np.array([1.0]), 1.0)\n"
            "while solver.status == 'running':\n"
            "    solver.step()\n"
            "    solver.dense_output()(solver.t)\n"
            "solver = module.RK45(lambda t, y: -y, 0.0, np.array([1.0]), 1.0)\n"
            "while solver.status == 'running':\n"
            "    solver.step()\n"
            "    solver.dense_output()([solver.t_old, solver.t])\n"
            "assert 'scipy' not in sys.modules, sorted(m for m in sys.modules if m.startswith('scipy'))\n"
            "assert 'sympy' not in sys.modules\n")
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
