"""Progress of a run: a callback in the API, a terminal line only where someone watches."""

import io

import pytest

from acausal import Model, simulate
from acausal.errors import SettingError
from acausal.library.rotational import ConstantTorque, Inertia
from acausal.runtime import simulate as simulate_module
from acausal.runtime.simulate import TerminalProgress, progress_reporter


class Spin(Model):
    def build(self):
        self.src = ConstantTorque(tau_constant=1.0)
        self.j = Inertia(J=1.0, phi=dict(fixed=True), w=dict(fixed=True))
        self.connect(self.src.flange, self.j.flange_a)


def test_the_callback_sees_time_advance_to_the_stop_time(monkeypatch):
    monkeypatch.setattr(simulate_module, "PROGRESS_PERIOD", 0.0)  # every step
    calls = []
    result = simulate(Spin(), stop_time=5.0, max_step=0.1, progress=lambda t, t0, t1: calls.append((t, t0, t1)))
    assert result.status == 0
    times = [t for t, _, _ in calls]
    assert len(calls) > 10
    assert all(t0 == 0.0 and t1 == 5.0 for _, t0, t1 in calls)
    assert times == sorted(times)          # time only moves on
    assert times[-1] == pytest.approx(5.0)  # the last call is the end of the run


def test_the_callback_is_throttled_by_wall_time():
    calls = []
    simulate(Spin(), stop_time=5.0, max_step=0.01, progress=lambda *a: calls.append(a))
    # 500 steps in well under a second of wall time: a few calls, not one per step
    assert 1 <= len(calls) < 100


def test_the_terminal_line_is_drawn_in_place_and_ended():
    stream = io.StringIO()
    line = TerminalProgress("Spin", stream=stream, width=10)
    line(2.5, 0.0, 5.0)
    line(5.0, 0.0, 5.0)
    line.close()
    text = stream.getvalue()
    assert text.count("\r") == 2 and text.endswith("\n")
    assert "[#####.....]   50%" in text and "[##########]  100%" in text


def test_quiet_in_tests_and_pipes_by_default():
    # pytest is running (and standard error is captured, not a terminal)
    assert progress_reporter(None, "Spin") is None
    assert progress_reporter(False, "Spin") is None
    assert isinstance(progress_reporter(True, "Spin"), TerminalProgress)


def test_a_wrong_progress_value_is_a_setting_error():
    with pytest.raises(SettingError, match="progress"):
        simulate(Spin(), stop_time=1.0, progress="yes")
