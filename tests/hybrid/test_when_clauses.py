"""The hybrid language against closed forms: when/elsewhen, reinit, sample, edge/change,
event-generating functions, initial(), terminate, assert, and the Zeno rule."""

import math

import numpy as np
import pytest

from acausal import (Assert, Boolean, Eq, Integer, Model, Parameter, Variable, When, ZenoError,
                     change, der, edge, floor, initial, mod, noEvent, pre, reinit, sample, simulate, terminal,
                     terminate, time)

G, E, H0 = 9.81, 0.8, 1.0


class Ball(Model):
    """h' = v, v' = -g; at an impact the speed reverses, scaled by the restitution e."""

    e = Parameter(E)
    g = Parameter(G)
    h = Variable(start=H0, fixed=True)
    v = Variable(start=0.0, fixed=True)

    def equations(self):
        return [Eq(der(self.h), self.v), Eq(der(self.v), -self.g),
                When(self.h <= 0, reinit(self.v, -self.e * pre(self.v)))]


def impact_times(n: int) -> np.ndarray:
    """Closed form: the first impact at sqrt(2 h0/g), then flights of 2 e^k v1 / g."""
    v1 = math.sqrt(2 * G * H0)
    times = [math.sqrt(2 * H0 / G)]
    for k in range(1, n):
        times.append(times[-1] + 2 * E ** k * v1 / G)
    return np.array(times)


def impacts(result) -> np.ndarray:
    return np.array([ev.time for ev in result.events
                     if any(name.startswith("reinit(") for name, _, _ in ev.changes)])


def test_bounce_times_and_apex_heights_follow_the_closed_form():
    result = simulate(Ball(), stop_time=3.0, interval=1e-4, rtol=1e-10, atol=1e-12)
    assert result.status == 0, result.message
    found = impacts(result)
    expected = impact_times(len(found))
    assert len(found) == np.searchsorted(impact_times(60), 3.0)
    np.testing.assert_allclose(found, expected, rtol=0, atol=1e-8)
    # apex between impacts k and k+1: e^(2k) h0 (sampled on the 1e-4 s grid: error g dt^2 / 8)
    t, h = result.time, result["h"]
    for k in range(len(found) - 1):
        inside = (t > found[k]) & (t < found[k + 1])
        assert h[inside].max() == pytest.approx(E ** (2 * (k + 1)) * H0, abs=2e-8)
    # the speed after each impact is e times the speed before
    for ev in result.events:
        for name, before, after in ev.changes:
            if name == "reinit(v)":
                assert after == pytest.approx(-E * before, rel=1e-12)


def test_a_ball_bouncing_to_rest_stops_at_its_zeno_point_with_the_reason():
    result = simulate(Ball(), stop_time=10.0, rtol=1e-10, atol=1e-12)
    assert result.status == -1
    assert isinstance(result.error, ZenoError)
    v1 = math.sqrt(2 * G * H0)
    t_star = math.sqrt(2 * H0 / G) + 2 * v1 * E / (G * (1 - E))  # the geometric series summed
    predicted = float(result.message.split("accumulate at t = ")[1].split(";")[0])
    assert predicted == pytest.approx(t_star, abs=1e-6)
    # stopped before the bounces got lost in the relation margin: the ball never fell through
    assert result["h"].min() > -1e-9
    assert result.time[-1] < t_star


class Counter(Model):
    n = Integer(start=0)
    y = Variable(start=0.0)
    period = Parameter(1e-3)

    def equations(self):
        return [When(sample(0, self.period), Eq(self.n, pre(self.n) + 1)),
                When(sample(0.5, 0.25), Eq(self.y, pre(self.y) + 1))]


def test_sample_ticks_are_exact_over_ten_thousand_periods_and_a_counter_counts_them():
    result = simulate(Counter(), stop_time=10.0, interval=0.5)
    assert result.status == 0, result.message
    ticks = [ev.time for ev in result.events if "sample(0, period)" in ev.relations
             or ev.kind == "initial"]
    assert len(ticks) == 10001
    # each tick is start + i*interval, to the last bit
    assert all(t == i * 1e-3 for i, t in enumerate(ticks))
    assert result["n"][-1] == 10001  # ticks at 0, 1e-3, ..., 10 (the first after initialization)
    assert result["y"][-1] == 39     # 0.5, 0.75, ..., 10.0


class Toggle(Model):
    """b is true in the first half of every second (mod() makes the time events)."""

    b = Boolean()
    rises = Integer(start=0)
    changes = Integer(start=0)

    def equations(self):
        return [Eq(self.b, mod(time, 1.0) < 0.5),
                When(edge(self.b), Eq(self.rises, pre(self.rises) + 1)),
                When(change(self.b), Eq(self.changes, pre(self.changes) + 1))]


def test_edge_and_change_fire_exactly_once_per_transition():
    result = simulate(Toggle(), stop_time=3.2, interval=0.01)
    assert result.status == 0, result.message
    assert result["rises"][-1] == 3    # at 1, 2, 3 (true from the start: no edge at 0)
    assert result["changes"][-1] == 6  # at 0.5, 1, 1.5, 2, 2.5, 3
    b, t = result["b"], result.time
    assert np.all(b[(t > 0.01) & (t < 0.49)] == 1) and np.all(b[(t > 0.51) & (t < 0.99)] == 0)


class Staircase(Model):
    """floor() of a continuous signal, held between its events."""

    x = Variable(start=0.0, fixed=True)
    k = Variable()
    smooth_k = Variable()

    def equations(self):
        return [Eq(der(self.x), 1.3), Eq(self.k, floor(self.x)), Eq(self.smooth_k, noEvent(floor(self.x)))]


def test_floor_steps_at_the_integer_crossings_and_holds_between():
    result = simulate(Staircase(), stop_time=4.0, interval=0.01)
    assert result.status == 0, result.message
    steps = sorted({round(ev.time, 9) for ev in result.events if ev.kind == "state"})
    # x = 1.3 t crosses 1, ..., 5 within 4 s
    np.testing.assert_allclose(steps, [n / 1.3 for n in range(1, 6)], atol=1e-9)
    x, k = result["x"], result["k"]
    grid = np.abs(x - np.round(x)) > 1e-6  # away from the steps, both forms agree exactly
    np.testing.assert_array_equal(k[grid], np.floor(x[grid]))
    np.testing.assert_array_equal(result["smooth_k"][grid], np.floor(x[grid]))


class Priorities(Model):
    """elsewhen: the first branch that fires wins; a discrete Real keeps its value between."""

    y = Variable(start=-1.0)
    fired = Integer(start=0)

    def equations(self):
        return [When(time >= 0.5, Eq(self.y, 1.0), Eq(self.fired, 1))
                .elsewhen(time >= 0.25, Eq(self.y, 2.0), Eq(self.fired, 2))
                .elsewhen(initial(), Eq(self.y, 3.0), Eq(self.fired, 3))]


def test_elsewhen_branches_and_initial():
    result = simulate(Priorities(), stop_time=1.0, interval=0.05)
    assert result.status == 0, result.message
    t, y = result.time, result["y"]
    assert y[0] == 3.0 and result["fired"][0] == 3          # initial() fires at initialization
    assert np.all(y[(t > 0.25) & (t < 0.5)] == 2.0)         # held between events
    assert np.all(y[t > 0.5] == 1.0) and result["fired"][-1] == 1


class Stopper(Model):
    x = Variable(start=0.0, fixed=True)
    limit = Parameter(0.75)
    last = Variable(start=0.0)

    def equations(self):
        return [Eq(der(self.x), 1.0),
                When(self.x >= self.limit, terminate("x reached its limit")),
                When(terminal(), Eq(self.last, self.x)),
                Assert(self.x < 0.5, "x passed 0.5", level="warning")]


def test_terminate_ends_the_run_successfully_with_the_reason_and_warnings_are_noted():
    result = simulate(Stopper(), stop_time=2.0, interval=0.01)
    assert result.status == 1 and result.success
    assert "x reached its limit" in result.message
    assert result.time[-1] == pytest.approx(0.75, abs=1e-9)
    assert [n for n in result.notes if "x passed 0.5" in n] and len(
        [n for n in result.notes if "x passed 0.5" in n]) == 1


def test_terminal_is_true_in_the_last_event_iteration():
    class Final(Model):
        x = Variable(start=0.0, fixed=True)
        last = Variable(start=-1.0)

        def equations(self):
            return [Eq(der(self.x), 2.0), When(terminal(), Eq(self.last, self.x))]

    result = simulate(Final(), stop_time=1.5, interval=0.1)
    assert result.status == 0
    assert result["last"][0] == -1.0 and result["last"][-1] == pytest.approx(3.0)
    assert result.events[-1].kind == "terminal"


def test_an_error_assertion_stops_the_run_and_keeps_the_result():
    class Guarded(Model):
        x = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), 1.0), Assert(self.x < 0.3, "x must stay below 0.3")]

    result = simulate(Guarded(), stop_time=1.0, interval=0.01)
    assert result.status == -1 and "x must stay below 0.3" in result.message
    assert 0.3 <= result.time[-1] < 0.4 and result["x"][result.time < 0.3].size > 20


def test_two_models_that_differ_only_in_a_reinit_are_not_one_translation():
    class Falling(Model):
        h = Variable(start=H0, fixed=True)
        v = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.h), self.v), Eq(der(self.v), -G)]

    class Softer(Falling):
        def equations(self):
            return [When(self.h <= 0, reinit(self.v, -0.5 * pre(self.v)))]

    class Harder(Falling):
        def equations(self):
            return [When(self.h <= 0, reinit(self.v, -0.9 * pre(self.v)))]

    soft, hard = (simulate(m(), stop_time=0.5) for m in (Softer, Harder))
    v_impact = -math.sqrt(2 * G * H0)
    t_impact = math.sqrt(2 * H0 / G)
    for result, e in ((soft, 0.5), (hard, 0.9)):
        assert result["v"][-1] == pytest.approx(-e * v_impact - G * (0.5 - t_impact), rel=1e-6)


def test_the_bouncing_ball_example_comes_to_rest_by_its_own_rule():
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parents[2] / "examples" / "bouncing_ball.py"
    spec = importlib.util.spec_from_file_location("bouncing_ball_example", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    result = simulate(module.BouncingBall())
    assert result.status == 0, result.message
    assert result["resting"][-1] == 1 and result["v"][-1] == 0
    assert abs(result["h"][-1]) < 1e-9
    # it rests at the first impact whose rebound speed e^k v1 is below v_small
    v1 = math.sqrt(2 * 9.81 * 1.0)
    k = next(k for k in range(1, 100) if 0.8 ** k * v1 < 0.05)
    assert len(impacts(result)) == k


class BodyRelation(Model):
    """A relation in a when-clause's body is evaluated at the clause's events only."""

    b = Boolean()
    held_a = Variable(discrete=True)
    held_b = Variable(discrete=True)

    def equations(self):
        return [When(sample(0, 0.1), Eq(self.b, time <= 0.05), Eq(self.held_a, time),
                     Eq(self.held_b, 2 * time))]


def test_a_relation_in_a_when_body_makes_no_event_of_its_own():
    result = simulate(BodyRelation(), stop_time=0.35, interval=0.05)
    assert result.status == 0, result.message
    assert [ev.time for ev in result.events] == pytest.approx([0.0, 0.1, 0.2, 0.3])
    assert result["b"][0] == 1 and result["b"][-1] == 0
    assert result["held_b"][-1] == pytest.approx(0.6)


def test_an_output_demand_may_leave_out_discrete_reals():
    result = simulate(BodyRelation(), stop_time=0.35, interval=0.05, outputs=["held_a"])
    assert result.status == 0, result.message
    assert result["held_a"][-1] == pytest.approx(0.3) and "held_b" not in result


def test_an_assertion_is_checked_at_the_output_points_of_a_step_that_ends_in_an_event():
    """A falling ball: the speed passes -4 m/s only in the step that ends at the impact (the
    step is long; the event truncates it). The output points before the event are checked."""

    class FastBall(Model):
        h = Variable(start=1.0, fixed=True)
        v = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.h), self.v), Eq(der(self.v), -9.81),
                    When(self.h <= 0, reinit(self.v, -0.8 * pre(self.v))),
                    Assert(self.v > -4.0, "falling fast", level="warning")]

    result = simulate(FastBall(), stop_time=0.6, interval=0.01)
    assert result.success
    t_fast = 4.0 / 9.81  # v = -4 here, before the impact at sqrt(2/9.81) = 0.4515
    assert [n for n in result.notes if "falling fast" in n], result.notes
    note = next(n for n in result.notes if "falling fast" in n)
    t_note = float(note.split("t = ")[1].split(":")[0])
    assert t_fast < t_note <= t_fast + 0.01 + 1e-12  # the first output point past it
