"""Nothing hangs and nothing is silently wrong (issue: reliability guarantees).

Each case that once hung runs in a subprocess with a hard timeout of its own,
so that a regression fails the test instead of stalling CI.
"""

from __future__ import annotations

import math
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from acausal import Eq, Experiment, If, Model, Parameter, Variable, der, simulate, time
from acausal.errors import SettingError, SimulationError, SimulationInterrupted, SolverError

REPO = Path(__file__).resolve().parents[2]


def _run_python(code: str, timeout: float = 60.0) -> subprocess.CompletedProcess:
    """Run ``code`` in a fresh interpreter; a hang fails the test at ``timeout``."""
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=timeout, cwd=str(REPO))


class Decay(Model):
    """der(x) = -x, x(0) = 1: x = exp(-t)."""

    experiment = Experiment(stop_time=1.0)
    x = Variable(start=1.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), -self.x)]


# -- settings -------------------------------------------------------------------------------


@pytest.mark.parametrize("options, words", [
    (dict(rtol=0.0), "rtol"),
    (dict(rtol=float("nan")), "rtol"),
    (dict(rtol=-1e-6), "rtol"),
    (dict(rtol=2.0), "rtol"),
    (dict(atol=-1.0), "atol"),
    (dict(atol=float("inf")), "atol"),
    (dict(interval=0.0), "interval"),
    (dict(interval=-0.1), "interval"),
    (dict(interval=float("nan")), "interval"),
    (dict(interval=1e-9), "output points"),
    (dict(stop_time=float("inf")), "stop time"),
    (dict(start_time=float("nan")), "start time"),
    (dict(stop_time=-1.0), "after start time"),
    (dict(chattering_events=0), "chattering_events"),
    (dict(max_event_iterations=0), "max_event_iterations"),
    (dict(max_steps=0), "max_steps"),
    (dict(timeout=-1.0), "timeout"),
    (dict(method="Euler", max_step=-0.01), "max_step"),
    (dict(method="RK4", max_step=float("inf")), "max_step"),
    (dict(method="RK45", max_step=0.0), "max_step"),
    (dict(relation_epsilon=float("nan")), "relation_epsilon"),
    (dict(method="Heun"), "unknown method"),
])
def test_a_setting_out_of_range_is_refused_before_anything_runs(options, words):
    with pytest.raises(SettingError, match=words) as info:
        simulate(Decay(), **options)
    assert isinstance(info.value, ValueError)


def test_the_output_cap_is_checked_before_any_allocation():
    # 1e-9 over 1 s would be 1e9 rows: refused at once, with a hint
    with pytest.raises(SettingError) as info:
        simulate(Decay(), interval=1e-9)
    assert "coarser interval" in info.value.hint


# -- non-finite values ----------------------------------------------------------------------


class InfiniteAfterHalf(Model):
    """der(x) = 1 until t = 0.5, then infinite: the run stops there, keeping what it computed.

    (``oo*x`` stays symbolic; a literal NaN would swallow the whole equation.)
    """

    experiment = Experiment(stop_time=1.0)
    x = Variable(start=0.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), If(time < 0.5, 1, sp.oo * self.x))]


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau", "BDF", "LSODA", "Euler", "RK4"])
def test_a_derivative_that_becomes_infinite_stops_the_run_there(method):
    result = simulate(InfiniteAfterHalf(), method=method, max_step=0.01 if method in ("Euler", "RK4") else None)
    assert result.status == -1
    assert isinstance(result.error, SolverError)
    assert "der(x)" in result.error.message and "0.5" in result.error.message
    assert result.time[-1] == pytest.approx(0.5)
    # what was computed is kept, and is right: x = t
    assert np.allclose(result["x"], result.time, atol=1e-9)


class SqrtGoesNegative(Model):
    """x = 1 - t, y = sqrt(x): y is undefined after t = 1."""

    experiment = Experiment(stop_time=2.0, interval=0.004)
    x = Variable(start=1.0, fixed=True)
    y = Variable()

    def equations(self):
        return [Eq(der(self.x), -1), Eq(self.y, sp.sqrt(self.x))]


def test_an_output_that_leaves_its_domain_stops_the_run_instead_of_filling_nan():
    result = simulate(SqrtGoesNegative())
    assert result.status == -1
    assert "y" in result.error.message
    t_stop = result.time[-1]
    assert 1.0 < t_stop <= 1.0 + 0.004 + 1e-12  # the first output point past the domain's end
    # every row but the failing one is finite and right: y = sqrt(1 - t)
    ok = result.time < 1.0
    assert np.allclose(result["y"][ok], np.sqrt(1.0 - result.time[ok]), rtol=1e-6)
    assert np.isfinite(result["x"]).all()


class InfiniteRelation(Model):
    """A relation whose side becomes infinite: the run stops (NaN would make it false for ever)."""

    experiment = Experiment(stop_time=1.0)
    x = Variable(start=0.0, fixed=True)
    u = Variable()
    b = Variable()

    def equations(self):
        return [Eq(der(self.x), 1), Eq(self.u, If(time < 0.5, self.x, sp.oo * self.x)),
                Eq(self.b, If(self.u > 0.7, 1, 0))]


def test_a_relation_side_that_becomes_infinite_stops_the_run():
    result = simulate(InfiniteRelation())
    assert result.status == -1
    assert "not finite" in result.error.message
    assert result.time[-1] == pytest.approx(0.5)


def test_a_nan_derivative_from_the_start_does_not_hang_any_solver():
    # scipy's RK45 and DOP853 loop for ever on a NaN first step; the derivative
    # is checked before the solver sees it.  oo*(x - 1) at x = 1 is 0*inf = NaN.
    for method in ("RK45", "DOP853", "Radau", "BDF", "LSODA"):
        done = _run_python(f"""
            import sympy as sp
            from acausal import Eq, Model, Variable, der, simulate
            class M(Model):
                x = Variable(start=1.0, fixed=True)
                def equations(self):
                    return [Eq(der(self.x), sp.oo * (self.x - 1))]
            r = simulate(M(), method={method!r}, timeout=2, max_steps=100)
            print(r.status, r.message.splitlines()[0])
        """, timeout=60)
        assert done.returncode == 0, done.stderr
        assert done.stdout.startswith("-1 ") and "der(x)" in done.stdout


# -- budgets ----------------------------------------------------------------------------------


def test_a_timeout_stops_a_run_that_spends_its_time_writing_output():
    # 5 million output points of a trivial model without states: the time goes into the
    # rows, written one at a time (some 20 s of them; with a state, a step's points are
    # written as one block, all 5 million in well under the budget of 1 s)
    done = _run_python("""
        import time
        from acausal import Eq, Experiment, Model, Variable, simulate, time as t
        class M(Model):
            y = Variable()
            def equations(self):
                return [Eq(self.y, 2 * t)]
        t0 = time.perf_counter()
        r = simulate(M(), stop_time=5.0, interval=1e-6, timeout=1.0)
        print(round(time.perf_counter() - t0, 2), r.status)
        print(r.error.message)
        print(r.error.hint)
        print(len(r.time), r.time[-1])
    """, timeout=120)
    assert done.returncode == 0, done.stderr
    first, message, hint, rows = done.stdout.splitlines()[:4]
    seconds, status = first.split()
    assert status == "-1"
    assert float(seconds) < 15.0  # the budget held (1 s, plus the result's assembly)
    assert "time budget" in message and "writing output points" in message
    assert "coarser interval" in hint
    n, t_last = rows.split()
    assert int(n) > 1 and 0 < float(t_last) < 5.0  # what was computed is kept


def test_a_step_budget_says_where_the_time_went():
    result = simulate(Decay(), method="RK45", rtol=1e-10, max_steps=5)
    assert result.status == -1
    assert "budget of 5 steps" in result.error.message and "integrating" in result.error.message
    assert result.time[-1] < 1.0


# -- interrupts --------------------------------------------------------------------------------


def test_ctrl_c_keeps_the_partial_result(monkeypatch):
    from acausal.runtime import recorder as recorder_module

    original = recorder_module.Recorder.add

    def add(self, t, system, x, discrete):
        if t > 0.5:
            raise KeyboardInterrupt
        original(self, t, system, x, discrete)

    monkeypatch.setattr(recorder_module.Recorder, "add", add)
    with pytest.raises(SimulationInterrupted) as info:
        simulate(Decay(), cache=False)
    error = info.value
    assert isinstance(error, KeyboardInterrupt) and not isinstance(error, Exception)
    result = error.result
    assert result.status == -2 and "interrupted" in result.message
    assert result.error.result is result
    assert 0.45 < result.time[-1] <= 0.5
    assert np.allclose(result["x"], np.exp(-result.time), rtol=1e-5)


# -- the translation cache cannot go stale --------------------------------------------------------


class RateFromInstance(Model):
    """der(x) = -rate*x with ``rate`` an instance attribute read by equations()."""

    experiment = Experiment(stop_time=1.0)
    x = Variable(start=1.0, fixed=True)

    def __init__(self, rate: float, **modifiers) -> None:
        super().__init__(**modifiers)
        object.__setattr__(self, "rate", rate)

    def equations(self):
        return [Eq(der(self.x), -self.rate * self.x)]


def test_an_instance_attribute_read_by_equations_reaches_a_cached_run():
    slow = simulate(RateFromInstance(1.0), rtol=1e-8)
    fast = simulate(RateFromInstance(5.0), rtol=1e-8)
    assert slow.final("x") == pytest.approx(math.exp(-1.0), rel=1e-6)
    assert fast.final("x") == pytest.approx(math.exp(-5.0), rel=1e-5)


def test_a_parameter_default_changed_on_the_class_reaches_a_cached_run():
    class Scaled(Model):
        experiment = Experiment(stop_time=1.0)
        k = Parameter(1.0)
        x = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), self.k)]

    assert simulate(Scaled()).final("x") == pytest.approx(1.0)
    Scaled.k = Parameter(3.0)
    Scaled.k.__set_name__(Scaled, "k")
    assert simulate(Scaled()).final("x") == pytest.approx(3.0)


def test_cache_false_translates_anew_and_gives_the_same_result():
    from acausal.compiler import translate as translate_module

    cached = simulate(Decay())
    before = len(translate_module._CACHE)
    fresh = simulate(Decay(), cache=False)
    assert len(translate_module._CACHE) == before
    assert np.array_equal(cached["x"], fresh["x"])


def test_a_simulation_error_is_still_a_runtime_error():
    assert issubclass(SolverError, SimulationError) and issubclass(SimulationError, RuntimeError)


# -- review findings ---------------------------------------------------------------------------


def test_a_simulated_translation_is_freed_with_its_evaluators():
    import gc
    import weakref

    from acausal import translate

    refs = []
    for _ in range(3):
        translation = translate(Decay(), cache=False)
        simulate(translation)
        refs.append(weakref.ref(translation))
        del translation
    gc.collect()
    assert all(r() is None for r in refs)


def test_the_error_of_a_result_keeps_its_traceback():
    result = simulate(InfiniteAfterHalf())
    frames = []
    tb = result.error.__traceback__
    while tb is not None:
        frames.append(tb.tb_frame.f_code.co_name)
        tb = tb.tb_next
    assert "_segment" in frames  # where the run stopped, not only where the copy was made


def test_a_component_hint_reaches_chattering_caused_by_a_relation_alone():
    from acausal import Component

    class Relay(Component):
        hints = {"chattering": "this relay has no hysteresis"}
        x = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), If(self.x > 0, -1000, 1000))]

    class Loop(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.relay = Relay()

    result = simulate(Loop())
    assert result.status == -1
    assert "relay" in result.error.components
    assert "no hysteresis" in result.error.hint


def test_discrete_variables_that_never_settle_at_initialization_are_named():
    from acausal import Boolean, Component, pre
    from acausal.errors import InitializationError

    class FlipFlop(Component):
        hints = {"event_iteration": "the flip-flop feeds itself back"}
        a = Boolean(start=False)

        def equations(self):
            return [Eq(self.a, sp.Not(pre(self.a)))]

    class Holder(Model):
        def build(self):
            self.ff = FlipFlop()

    with pytest.raises(InitializationError) as info:
        simulate(Holder())
    assert "ff.a" in info.value.message
    assert "feeds itself back" in info.value.hint and info.value.components == ("ff",)


def test_the_issue_reproducer_a_nan_parameter_neither_hangs_nor_passes_silently():
    # the reproducer of the issue: p = nan with der(x) = p.  By default a NaN
    # parameter is refused when the model is flattened; allowed explicitly,
    # the run stops at once with the derivative named, inside its budgets.
    done = _run_python("""
        from acausal import Eq, Model, Parameter, Variable, der, simulate
        from acausal.errors import ParameterError
        class M(Model):
            p = Parameter(float("nan"))
            x = Variable(start=1.0, fixed=True)
            def equations(self):
                return [Eq(der(self.x), self.p)]
        try:
            simulate(M(), timeout=2, max_steps=100)
        except ParameterError as exc:
            print("refused:", exc.message)
        class Allowed(M):
            p = Parameter(float("nan"), finite=False)
        r = simulate(Allowed(), timeout=2, max_steps=100)
        print(r.status, r.message.splitlines()[0])
    """, timeout=60)
    assert done.returncode == 0, done.stderr
    refused, stopped = done.stdout.splitlines()[:2]
    assert refused.startswith("refused:") and "p" in refused
    assert stopped.startswith("-1 ") and "der(x) = nan" in stopped


def test_a_clutch_with_a_nan_normal_force_is_refused_not_hung():
    # the issue's RK45/DOP853 hang: fn_max = nan; refused at flattening, by name
    done = _run_python("""
        from acausal import Experiment, Model, simulate
        from acausal.errors import ParameterError
        from acausal.library.blocks import Constant
        from acausal.library.rotational import Clutch, Inertia
        class NaNClutch(Model):
            experiment = Experiment(stop_time=1.0)
            def build(self):
                self.a = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=10, fixed=True))
                self.b = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
                self.clutch = Clutch(fn_max=float("nan"))
                self.force = Constant(k=1.0)
                self.connect(self.a.flange_b, self.clutch.flange_a)
                self.connect(self.clutch.flange_b, self.b.flange_a)
                self.connect(self.force.y, self.clutch.f_normalized)
        model = NaNClutch()
        for method in ("RK45", "DOP853"):
            try:
                simulate(model, method=method, timeout=5)
                print("ran")
            except ParameterError as exc:
                print("refused", exc.message)
    """, timeout=60)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert len(lines) == 2 and all(line.startswith("refused") and "fn_max" in line for line in lines)


class OverflowThenBlowUp(Model):
    """An output that overflows from t = 0.142 on (exp(5000 t)), while the state it does not
    feed blows up at t = 1 (x' = x^2, x(0) = 1): the run must not keep the rows in between."""

    experiment = Experiment(stop_time=2.0, interval=0.01)
    x = Variable(start=1.0, fixed=True)
    y = Variable()

    def equations(self):
        return [Eq(der(self.x), self.x ** 2), Eq(self.y, sp.exp(5000 * time))]


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau", "BDF", "LSODA", "Euler", "RK4"])
def test_a_non_finite_output_ends_the_kept_rows_whatever_ends_the_run(method):
    """Issue 23, item 6: the check of the outputs used to be skipped when the run later failed
    for another reason, so rows with y = inf from 0.142 to the solver's failure near 1 were kept."""
    with np.errstate(all="ignore"):
        result = simulate(OverflowThenBlowUp(), method=method, max_step=0.01)
    assert result.status == -1
    assert "y" in result.error.message and "not finite" in result.error.message
    overflow = math.log(np.finfo(float).max) / 5000          # 0.14196...
    assert overflow <= result.time[-1] <= overflow + 0.01 + 1e-9
    # every row but the last (the first non-finite one, where the run is cut) is finite
    assert np.isfinite(result["y"][:-1]).all() and np.isfinite(result["x"]).all()
    np.testing.assert_allclose(result["x"], 1 / (1 - result.time), rtol=1e-2)
