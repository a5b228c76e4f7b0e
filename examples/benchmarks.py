"""The cases of ``acausal bench``: what it measures, and the exact solutions it measures against.

``acausal bench`` (:mod:`acausal.tools.bench`) is generic machinery: it
times translations and simulations, draws work-precision plots and fits
scaling laws.  What it runs is defined here, in the examples folder, because
the cases are models of the component libraries.  The bench imports this
module (with ``examples/`` on ``sys.path``) and uses:

``cases()``
    The work-precision cases in table order, two kinds:

    * **Exact-solution cases** ``CoastDown`` and ``StickSlip``.  A single
      inertia against a ``BearingFriction`` with a constant friction torque
      (no speed dependence) moves by ``J w' = drive - tau0`` while it slides
      and has ``w = 0`` while it sticks, so its speed is an integral of known
      functions and is known exactly -- the integrator's and the event
      handling's error can be measured free of any reference's own error:

      - ``CoastDown``: spinning at ``w0`` with nothing driving it, the speed
        falls linearly, ``w(t) = w0 - tau0 t / J``, until it stops at
        ``t* = J w0 / tau0 = 4 s`` and stays stuck (no torque to break it
        away).  See :func:`coast_down_exact`.
      - ``StickSlip``: a sine torque ``A sin(2 pi f t)`` on the inertia at
        rest.  It sticks until the drive reaches the breakaway torque,
        ``t_b = asin(peak tau0 / A) / (2 pi f)``, then slides forward with
        ``w(t) = (A/omega)(cos(omega t_b) - cos(omega t))/J - tau0 (t - t_b)/J``
        until the speed returns to zero at ``t_s`` (a root of that closed
        form, found to 1e-15 s).  The error is measured on ``[0, t_s]``.
        See :func:`stick_slip_times` and :func:`stick_slip_exact`.

      Their *error* is ``max |w - w_exact|`` in rad/s on the output grid,
      their *event-time error* the distance of the breakaway and stop
      events to the exact instants.
    * **Reference cases**: MSL examples of this folder (``first.py``,
      ``two_masses.py``, ``friction.py``, ``coupled_clutches.py``),
      measured against the MSL reference results.

``QUICK_CASES``
    The cases of ``acausal bench --quick``.
``effects_cases(n_units)``
    The models of the *effects on demand* section: ``BearingHeating`` and a
    generated drive train with heat ports (:func:`drive_train_model`), each
    with the one output requested.
``scaling_model(n, stop_time)``, ``SCALING_DESCRIPTION``, ``SCALING_SIZE_LABEL``
    The model of size ``n`` of the *scaling* section (the drive train
    without heat ports) and the words describing it in the table and plot.
``array_scaling_case()``
    The array case of the *scaling* section: the heat rod of
    ``examples/heat_rod.py`` (``n`` cells built with arrays), translated for
    growing ``n`` to show that translation time grows linearly.
``storm_model(n)`` and the ``STORM_*`` constants
    The model of the *storm* section: ``n`` independent stick-slip units
    (independent parts, each with its own modes and events), simulated for
    ``STORM_STOP_TIME`` with output interval ``STORM_INTERVAL``; the words
    describing it in the table (``STORM_DESCRIPTION``), on the plot's axis
    (``STORM_SIZE_LABEL``) and in the reading of the events' growth
    (``STORM_EVENTS_GROWTH``); ``STORM_WATCHED``, the variable whose final
    value each storm point records (the same with and without clusters).
``floor_case()``
    The *floors* section's hand-coded floor (:class:`acausal.tools.bench.FloorCase`):
    ``StickSlip`` written by hand on ``scipy.integrate.RK45``
    (:func:`stick_slip_floor`), the speed whose final values are compared,
    the agreement required, and the words describing the floor.
``COMMAND_TARGETS``, ``SIMULATE_COMMAND_TARGETS``
    The examples whose ``acausal compare`` (``acausal simulate``) command is
    timed in a fresh process.
The targets (``TARGETS_SOURCE``: where they were set)
    ``WARM_COMMAND_FILES`` and ``WARM_COMMAND_MAX_X_IMPORT_NUMPY`` (a warm
    command within a multiple of ``python -c "import numpy"``), the floor
    case's ``target_ratio``, ``STORM_PER_EVENT_TARGET`` and
    ``STORM_WALL_TARGETS``, ``SCALING_TIME_TARGETS`` and
    ``SCALING_MEMORY_TARGET``: each section states them in its Markdown,
    measured, met or not, and why.
``start_case()``
    The state of ``parameter_case()``'s model whose start value the
    *parameters* section changes at run time, and its values.
``soak_case()``
    ``(name, make)`` of the model the *soak* section simulates again and
    again in one process (``CoupledClutches``: several discrete states, so
    every run compiles or reuses more than one system).
``EXACT_ERROR_TEXT``
    How the exact cases' *error* is measured, for the bench's table.
``table_models(rows)``
    The models of the *tables* section: a 1-D table in a feedback loop, an
    Akima time table integrated, a 2-D table in a loop, with tables of about
    ``rows`` rows (:mod:`acausal.tools.table_bench`).

``acausal simulate examples/benchmarks.py:CoastDown`` (or ``:StickSlip``)
runs an exact-solution case on its own.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from acausal import Experiment, Model

# The component libraries are imported inside ``build`` (as the bench always
# did), so that importing this module stays light and a translation's
# flatten time includes the same work as before.

# ---------------------------------------------------------------------------
# Exact-solution models
# ---------------------------------------------------------------------------

#: Coast-down: inertia J spinning at w0, bearing with constant friction tau0.
CD_J, CD_W0, CD_TAU0, CD_STOP = 2.0, 3.0, 1.5, 6.0


class CoastDown(Model):
    """Inertia (J=2, w=3) coasting to a stop against BearingFriction(tau_pos=[[0, 1.5]]).

    ``w(t) = max(w0 - tau0 t/J, 0)``, stopping at ``t* = J w0/tau0 = 4``.
    """

    experiment = Experiment(start_time=0.0, stop_time=CD_STOP, interval=0.005)

    def build(self):
        from acausal.library.rotational import BearingFriction, Inertia

        self.inertia = Inertia(J=CD_J, phi=dict(start=0, fixed=True), w=dict(start=CD_W0, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0.0, CD_TAU0]])
        self.connect(self.inertia.flange_b, self.bearing.flange_a)


def coast_down_exact(t) -> np.ndarray:
    """Exact speed of :class:`CoastDown`."""
    return np.maximum(CD_W0 - CD_TAU0 * np.asarray(t, dtype=float) / CD_J, 0.0)


CD_T_STOP = CD_J * CD_W0 / CD_TAU0

#: Stick-slip: Torque(A sin(2 pi f t)) on an inertia at rest, bearing tau0, peak p.
SS_A, SS_F, SS_J, SS_TAU0, SS_PEAK = 10.0, 1.0, 1.0, 1.0, 1.0


class StickSlip(Model):
    """Sine torque (A=10, f=1) on an inertia at rest against BearingFriction(tau_pos=[[0, 1]], peak=1).

    Breakaway at ``t_b = asin(p tau0/A)/(2 pi f)``; until the first stop ``t_s``
    the speed is the integral of the net torque (:func:`stick_slip_exact`).
    """

    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        from acausal.library.blocks import Sine
        from acausal.library.rotational import BearingFriction, Inertia, Torque

        self.sine = Sine(amplitude=SS_A, f=SS_F)
        self.torque = Torque()
        self.inertia = Inertia(J=SS_J, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0.0, SS_TAU0]], peak=SS_PEAK)
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bearing.flange_a)


def _stick_slip_w(t):
    t_b = math.asin(SS_PEAK * SS_TAU0 / SS_A) / (2 * math.pi * SS_F)
    om = 2 * math.pi * SS_F
    t = np.asarray(t, dtype=float)
    return (SS_A / om) * (math.cos(om * t_b) - np.cos(om * t)) / SS_J - SS_TAU0 * (t - t_b) / SS_J


@lru_cache(maxsize=None)
def stick_slip_times() -> tuple[float, float]:
    """``(t_b, t_s)``: exact breakaway and first stop of :class:`StickSlip`."""
    from scipy.optimize import brentq

    t_b = math.asin(SS_PEAK * SS_TAU0 / SS_A) / (2 * math.pi * SS_F)
    # w grows while the drive exceeds the friction, i.e. until sin returns to tau0/A
    t_peak = 0.5 / SS_F - math.asin(SS_TAU0 / SS_A) / (2 * math.pi * SS_F)
    hi = t_peak
    while _stick_slip_w(hi) > 0:
        hi += 0.05 / SS_F
    t_s = brentq(lambda t: float(_stick_slip_w(t)), t_peak, hi, xtol=1e-15, rtol=1e-15)
    return t_b, t_s


def stick_slip_exact(t) -> np.ndarray:
    """Exact speed of :class:`StickSlip` on ``[0, t_s]`` (0 before the breakaway)."""
    t_b, _ = stick_slip_times()
    t = np.asarray(t, dtype=float)
    return np.where(t <= t_b, 0.0, _stick_slip_w(t))


def stick_slip_stop_time() -> float:
    """0.6 s if the first stop comes before it, else 1.1 t_s."""
    _, t_s = stick_slip_times()
    return 0.6 if t_s < 0.6 else 1.1 * t_s


def _changed(event, name: str, old=None, new=None) -> bool:
    for n, a, b in event.changes:
        if n == name and (old is None or a == old) and (new is None or b == new):
            return True
    return False


def evaluate_coast_down(result, translation) -> dict:
    """Error of a :class:`CoastDown` result: speed against :func:`coast_down_exact`, stop time against 4 s."""
    t = result.time
    w = result["inertia.w"]
    error = float(np.max(np.abs(w - coast_down_exact(t))))
    stops = [e.time for e in result.events if _changed(e, "bearing.mode", 1, 0)]
    event_error = abs(stops[0] - CD_T_STOP) if stops else math.inf
    return {"error": error, "event_error": event_error}


def evaluate_stick_slip(result, translation) -> dict:
    """Error of a :class:`StickSlip` result on ``[0, t_s]``; breakaway and stop against the exact instants."""
    t_b, t_s = stick_slip_times()
    t = result.time
    w = result["inertia.w"]
    window = t <= t_s
    error = float(np.max(np.abs(w[window] - stick_slip_exact(t[window]))))
    breaks = [e.time for e in result.events if e.kind != "initial" and
              (_changed(e, "bearing.startForward", False, True)
               or _changed(e, "bearing.locked", True, False))]
    stops = [e.time for e in result.events if any(n == "bearing.mode" and a == 1 and b != 1
                                                  for n, a, b in e.changes)]
    if breaks and stops:
        event_error = max(abs(breaks[0] - t_b), abs(stops[0] - t_s))
    else:
        event_error = math.inf
    return {"error": error, "event_error": event_error}


def stick_slip_floor(stop_time: float, interval: float, rtol: float = 1e-6, atol: float = 1e-6,
                     bisections: int = 40) -> dict:
    """:class:`StickSlip` written by hand on ``scipy.integrate.RK45``: the floor of its simulation.

    One inertia ``J`` driven by ``A sin(2 pi f t)`` against Coulomb friction
    ``tau0`` with static limit ``peak*tau0`` (the ``SS_*`` constants), states
    ``(phi, w)`` and three modes: *stuck* (``w' = 0``), *forward* (``J w' =
    drive - tau0``) and *backward* (``J w' = drive + tau0``).  The switching
    functions: stuck -> sliding when ``|drive|`` exceeds the static limit;
    sliding -> the next mode when ``w`` changes sign, then stuck if
    ``|drive|`` is within the static limit, else sliding the way the drive
    pushes (what the friction state machine does at a stop).  Each accepted
    step's dense output fills the output grid points in the step and samples
    the mode's switching function there and at the step's end (at least 4
    samples a step); a sign change is narrowed by ``bisections`` bisection
    steps on the dense output and the solver is restarted at the switch.
    Returns ``time``, ``w`` on the output grid, the switch ``events`` as
    ``(t, old mode, new mode)``, ``final`` (the last ``w``), ``steps`` and
    ``rhs_evaluations`` -- what :class:`acausal.tools.bench.FloorCase` asks of
    a floor.
    """
    from scipy.integrate import RK45

    A, om, J, tau0 = SS_A, 2.0 * math.pi * SS_F, SS_J, SS_TAU0
    tau_max = SS_PEAK * SS_TAU0
    STUCK, FORWARD, BACKWARD = 0, 1, -1

    def rhs(mode):
        if mode == STUCK:
            return lambda t, y: np.zeros(2)
        friction = tau0 if mode == FORWARD else -tau0
        return lambda t, y: np.array([y[1], (A * math.sin(om * t) - friction) / J])

    def switching(mode, t, y):
        """Positive while the mode holds (vectorised over sample times, states as columns)."""
        if mode == STUCK:
            return tau_max - np.abs(A * np.sin(om * np.asarray(t)))
        return y[1] if mode == FORWARD else -y[1]

    def next_mode(t):
        drive = A * math.sin(om * t)
        return FORWARD if drive > tau_max else BACKWARD if drive < -tau_max else STUCK

    n_out = int(math.floor((stop_time - 0.0) / interval + 1e-9)) + 1
    grid = np.arange(n_out) * interval
    if stop_time - grid[-1] > 1e-12 * max(1.0, stop_time):
        grid = np.append(grid, stop_time)
    out_w = np.empty(len(grid))
    out_w[0] = 0.0
    filled = 1
    t, y, mode = 0.0, np.array([0.0, 0.0]), next_mode(0.0)
    events, steps, nfev = [], 0, 0
    while t < stop_time:
        solver = RK45(rhs(mode), t, y, stop_time, rtol=rtol, atol=atol)
        switched = False
        while solver.status == "running":
            t_old = solver.t
            solver.step()
            steps += 1
            if solver.status == "failed":
                raise RuntimeError(f"RK45 failed at t = {solver.t}: {solver.message}")
            t_new = solver.t
            dense = solver.dense_output()
            hi = int(np.searchsorted(grid, t_new, side="right"))
            inside = grid[filled:hi]
            samples = np.union1d(np.linspace(t_old, t_new, 5)[1:], inside)
            states = dense(samples)
            g = np.asarray(switching(mode, samples, states))
            crossed = np.nonzero(g < 0)[0]
            if crossed.size:
                i = int(crossed[0])
                lo_t, hi_t = (samples[i - 1] if i > 0 else t_old), samples[i]
                for _ in range(bisections):
                    mid = 0.5 * (lo_t + hi_t)
                    if switching(mode, mid, dense(mid)) < 0:
                        hi_t = mid
                    else:
                        lo_t = mid
                t_event = hi_t
                keep = int(np.searchsorted(grid, t_event, side="right"))
                if keep > filled:
                    out_w[filled:keep] = dense(grid[filled:keep])[1]
                    filled = keep
                y = dense(t_event)
                t = t_event
                new = next_mode(t)
                if new == mode:  # cannot happen (the switch is where the mode stops holding)
                    raise RuntimeError(f"stick_slip_floor: mode {mode} switched to itself at t = {t}")
                events.append((t, mode, new))
                mode = new
                switched = True
                break
            if hi > filled:  # the output points of the step (samples too)
                out_w[filled:hi] = states[1][np.searchsorted(samples, inside)]
                if grid[hi - 1] == t_new:
                    out_w[hi - 1] = solver.y[1]
                filled = hi
        nfev += solver.nfev
        if not switched:
            t, y = solver.t, solver.y
    return {"time": grid, "w": out_w, "events": events, "final": float(out_w[-1]), "steps": steps,
            "rhs_evaluations": nfev}


#: How the exact cases' error is measured (the bench's table explains its columns with it).
EXACT_ERROR_TEXT = "CoastDown and StickSlip: max |w - w_exact| in rad/s on the output grid"


# ---------------------------------------------------------------------------
# The generated drive train
# ---------------------------------------------------------------------------


def drive_train_model(n: int, heat_ports: bool = False, stop_time: float = 1.0, interval=None) -> Model:
    """A drive train of ``n`` units Inertia–BearingFriction–SpringDamper in series.

    A sine torque (20 N.m, 2 Hz) drives the first inertia; every inertia
    (J = 1) starts at 10 rad/s and has a bearing (friction 0.5 N.m) whose
    flanges carry the train on to the next spring-damper (c = 1e3, d = 5).
    All bearings slide forward for the first seconds, so one discrete state
    is in force and the run measures the continuous part.  With
    ``heat_ports`` every bearing heats its own HeatCapacitor (C = 10).
    """

    class DriveTrain(Model):
        experiment = Experiment(start_time=0.0, stop_time=stop_time,
                                interval=interval if interval is not None else stop_time / 500)

        def build(self):
            from acausal.library.blocks import Sine
            from acausal.library.rotational import BearingFriction, Inertia, SpringDamper, Torque
            from acausal.library.thermal import HeatCapacitor

            self.sine = Sine(amplitude=20.0, f=2.0)
            self.torque = Torque()
            self.connect(self.sine.y, self.torque.tau)
            previous = self.torque.flange
            for i in range(1, n + 1):
                inertia = Inertia(J=1.0, phi=dict(start=0, fixed=True), w=dict(start=10.0, fixed=True))
                bearing = BearingFriction(tau_pos=[[0.0, 0.5]], peak=1.1, useHeatPort=heat_ports)
                setattr(self, f"inertia{i}", inertia)
                setattr(self, f"bearing{i}", bearing)
                self.connect(previous, inertia.flange_a)
                self.connect(inertia.flange_b, bearing.flange_a)
                if heat_ports:
                    housing = HeatCapacitor(C=10.0, T=dict(start=293.15, fixed=True))
                    setattr(self, f"housing{i}", housing)
                    self.connect(bearing.heatPort, housing.port)
                if i < n:
                    spring = SpringDamper(c=1e3, d=5.0)
                    setattr(self, f"spring{i}", spring)
                    self.connect(bearing.flange_b, spring.flange_a)
                    previous = spring.flange_b

    DriveTrain.__name__ = DriveTrain.__qualname__ = f"DriveTrain{n}{'Heat' if heat_ports else ''}"
    return DriveTrain()


# ---------------------------------------------------------------------------
# What the bench runs
# ---------------------------------------------------------------------------


def cases() -> list:
    """The work-precision cases (:class:`acausal.tools.bench.Case`), in table order."""
    from acausal.tools.bench import Case, reference_case

    return [
        Case("CoastDown", CoastDown, evaluate_coast_down, "rad/s",
             "BearingFriction coast-down, exact w(t) and stop at t*=4", CD_STOP),
        Case("StickSlip", StickSlip, evaluate_stick_slip, "rad/s",
             "sine-driven stick-slip, exact w(t) until the first stop", stick_slip_stop_time()),
        reference_case("First", "first", "Modelica.Mechanics.Rotational.Examples.First"),
        reference_case("TwoMasses", "two_masses", "Modelica.Thermal.HeatTransfer.Examples.TwoMasses"),
        reference_case("Friction", "friction", "Modelica.Mechanics.Rotational.Examples.Friction"),
        reference_case("CoupledClutches", "coupled_clutches",
                       "Modelica.Mechanics.Rotational.Examples.CoupledClutches"),
    ]


#: The cases of ``acausal bench --quick``.
QUICK_CASES = ("CoastDown", "StickSlip", "First", "Friction")


def effects_cases(n_units: int = 20) -> list[tuple]:
    """``(name, make, output)`` of the models the effects-on-demand section runs."""
    from acausal.tools.bench import example_factory

    return [
        ("BearingHeating", example_factory("bearing_heating", "BearingHeating"), "shaft.w"),
        (f"DriveTrain{n_units} (heat ports)", lambda: drive_train_model(n_units, heat_ports=True),
         f"inertia{n_units}.w"),
    ]


def scaling_model(n: int, stop_time: float) -> Model:
    """The scaling section's model of size ``n``: the drive train without heat ports."""
    return drive_train_model(n, heat_ports=False, stop_time=stop_time)


#: The scaling model in the words of the scaling table and plot.
SCALING_DESCRIPTION = ("Drive train of N units Inertia–BearingFriction–SpringDamper (no heat ports), "
                       "sine-driven, all bearings sliding")
SCALING_SIZE_LABEL = "N (units Inertia–BearingFriction–SpringDamper)"

def add_storm_unit(model: Model, k: int, f: float, names: tuple[str, str, str, str] = ("sine", "torque",
                   "inertia", "bearing"), w_fixed: bool = True) -> None:
    """Add unit ``k`` of a storm to ``model`` (in its ``build``): Sine(amplitude 2, ``f``) ->
    Torque -> Inertia(J = 1, at rest) -> BearingFriction(tau0 = 1, peak 1.2), its components
    named ``<names[i]><k>`` (the start speed not fixed with ``w_fixed=False``)."""
    from acausal.library.blocks import Sine
    from acausal.library.rotational import BearingFriction, Inertia, Torque

    sine = Sine(amplitude=2.0, f=f)
    torque = Torque()
    inertia = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=w_fixed))
    bearing = BearingFriction(tau_pos=[[0.0, 1.0]], peak=1.2)
    for name, component in zip(names, (sine, torque, inertia, bearing)):
        setattr(model, f"{name}{k}", component)
    model.connect(sine.y, torque.tau)
    model.connect(torque.flange, inertia.flange_a)
    model.connect(inertia.flange_b, bearing.flange_a)


def storm_model(n: int) -> Model:
    """``n`` independent units, each Sine -> Torque -> Inertia -> BearingFriction.

    Unit ``k`` (1..n) is driven by ``Sine(amplitude=2, f=1 + 0.13 k)``, so
    the units stick and slip at different instants: a storm of events, each
    changing the discrete state of one unit only.  Nothing couples the units,
    so the continuous equations fall into ``n`` independent parts (clusters);
    the whole model has ``3^n``-ish discrete states, of which a run visits a
    few dozen, while each part has only its own few modes.
    """

    class Storm(Model):
        experiment = Experiment(start_time=0.0, stop_time=STORM_STOP_TIME, interval=STORM_INTERVAL)

        def build(self):
            for k in range(1, n + 1):
                add_storm_unit(self, k, 1.0 + 0.13 * k)

    Storm.__name__ = Storm.__qualname__ = f"Storm{n}"
    return Storm()


#: How the storm section simulates :func:`storm_model`.
STORM_STOP_TIME, STORM_INTERVAL = 1.0, 0.01
#: The storm model in the words of the storm table and plot.
STORM_DESCRIPTION = ("N independent units Sine(amplitude 2, f = 1 + 0.13 k) -> Torque -> Inertia(J = 1, at rest) "
                     "-> BearingFriction(tau0 = 1, peak 1.2): every unit sticks and slips at its own instants, "
                     "so events come in a storm and each changes the discrete state of one unit")
STORM_SIZE_LABEL = "N (independent units Sine–Torque–Inertia–BearingFriction)"
#: Why the storm's events grow faster than N (the storm table's reading).
STORM_EVENTS_GROWTH = "unit k is driven at 1 + 0.13 k Hz, so the larger N, the faster its units stick and slip"
#: The variable whose final value every storm point records (with and without clusters alike).
STORM_WATCHED = "inertia1.w"

#: ``(case, example file)``: the ``acausal compare`` commands timed in a fresh process.
COMMAND_TARGETS = (("First", "examples/first.py"), ("TwoMasses", "examples/two_masses.py"),
                   ("CoupledClutches", "examples/coupled_clutches.py"))
#: ``(case, example file)``: the ``acausal simulate`` commands timed in a fresh process (the result's
#: CSV written into a folder of the bench's own).
SIMULATE_COMMAND_TARGETS = (("First", "examples/first.py"),)

# ---------------------------------------------------------------------------
# The targets each section states (measured, met or not, and why)
# ---------------------------------------------------------------------------

#: Where the targets below were set.
TARGETS_SOURCE = "issue 29"
#: The examples whose warm commands (``acausal simulate`` and ``acausal compare``, the compiled systems
#: loaded from the disk cache) have to run within ``WARM_COMMAND_MAX_X_IMPORT_NUMPY`` times the wall time
#: of ``python -c "import numpy"`` in a fresh process.
WARM_COMMAND_FILES = ("examples/first.py",)
WARM_COMMAND_MAX_X_IMPORT_NUMPY = 2.0
#: ``(N small, N large, ratio)``: the storm's integration+events seconds per event at N large within
#: ``ratio`` times that at N small (the cost of an event independent of the units not involved).
STORM_PER_EVENT_TARGET = (10, 100, 1.5)
#: ``(N, wall seconds)``: the storm model with clusters, translated and simulated in a fresh process.
STORM_WALL_TARGETS = ((200, 10.0), (1000, 60.0))
#: ``(N, seconds)``: the scaling model translated and initialized (flatten and partition, the event
#: evaluator, the first discrete states and the initialization systems compiled and solved).
SCALING_TIME_TARGETS = ((1000, 10.0), (10000, 100.0))
#: ``(N, kB)``: the scaling model's peak resident memory per equation at N.
SCALING_MEMORY_TARGET = (1000, 20.0)


def parameter_case() -> tuple:
    """``(name, make, parameter, values)``: a tunable parameter changed between runs."""
    from acausal.tools.bench import example_factory

    return ("CoupledClutches", example_factory("coupled_clutches", "CoupledClutches"), "clutch1.fn_max",
            (5.0, 10.0, 40.0, 80.0, 160.0))


def start_case() -> tuple:
    """``(state, values)``: a start value of ``parameter_case()``'s model changed between runs
    (CoupledClutches' J1.w starts at 10 rad/s)."""
    return "J1.w", (9.5, 10.5)


def soak_case() -> tuple:
    """``(name, make)``: the model the soak section simulates many times in one process."""
    from acausal.tools.bench import example_factory

    return "CoupledClutches", example_factory("coupled_clutches", "CoupledClutches")


def floor_case():
    """The floors section's hand-coded floor: :class:`StickSlip` on ``scipy.integrate.RK45``."""
    from acausal.tools.bench import FloorCase

    return FloorCase(
        case="StickSlip", floor=stick_slip_floor, output="inertia.w", unit="rad/s",
        agreement=1e-4,  # rad/s: the largest difference of the final speeds that counts as agreeing
        description=("The suite's StickSlip (sine torque on an inertia against Coulomb friction with sticking). "
                     "Floor: the same ODE and stick/slip switching written directly on `scipy.integrate.RK45` "
                     "(`stick_slip_floor` in `examples/benchmarks.py`): each step's dense output fills the "
                     "output grid and samples the switching function, a sign change is bisected on the dense "
                     "output, the solver restarted."),
        events_note=("acausal's events include the initial one and the intermediate start-of-sliding "
                     "(startForward, then mode = Forward once w > 0); the floor switches straight into a "
                     "sliding mode"),
        method="RK45",
        target_ratio=2.0)  # the warm run within twice the floor (TARGETS_SOURCE)


def table_models(rows: int) -> dict:
    """The models of the bench's *tables* section (acausal.tools.table_bench), with tables of
    about ``rows`` rows: ``{name: model class}``."""
    from acausal import Eq, Experiment, Model, Variable, der
    from acausal.library.blocks import CombiTable1Ds, CombiTable2Ds, CombiTimeTable, ContinuousClock, Smoothness

    u = np.linspace(-2.0, 2.0, rows)
    curve = np.column_stack([u, np.sin(u)]).tolist()
    t = np.linspace(0.0, 10.0, rows)
    signal = np.column_stack([t, np.sin(t)]).tolist()
    n = max(2, int(round(rows ** 0.5)))
    grid = np.linspace(-2.0, 2.0, n)
    surface = np.zeros((n + 1, n + 1))
    surface[0, 1:], surface[1:, 0] = grid, grid
    surface[1:, 1:] = np.sin(grid)[:, None] * np.cos(0.2 * grid)[None, :]

    class Loop1D(Model):
        experiment = Experiment(stop_time=10.0, interval=0.01)
        x = Variable(start=1.5, fixed=True)

        def build(self):
            self.f = CombiTable1Ds(table=curve)

        def equations(self):
            return [Eq(self.f.u, self.x), Eq(der(self.x), -self.f.y[1] + 0.5 * self.x)]

    class TimeAkima(Model):
        experiment = Experiment(stop_time=10.0, interval=0.01)
        x = Variable(start=0.0, fixed=True)

        def build(self):
            self.s = CombiTimeTable(table=signal, smoothness=Smoothness.ContinuousDerivative)

        def equations(self):
            return [Eq(der(self.x), self.s.y[1])]

    class Loop2D(Model):
        experiment = Experiment(stop_time=10.0, interval=0.01)
        x = Variable(start=1.5, fixed=True)

        def build(self):
            self.g = CombiTable2Ds(table=surface.tolist())
            self.clock = ContinuousClock()

        def equations(self):
            return [Eq(self.g.u1, self.x), Eq(self.g.u2, 0.2 * self.clock.y - 1.0),
                    Eq(der(self.x), -self.g.y + 0.5 * self.x)]

    return {"1-D in a loop": Loop1D, "time table, Akima": TimeAkima, "2-D in a loop": Loop2D}


def array_scaling_case():
    """The *scaling* section's array case: the heat rod of ``examples/heat_rod.py``."""
    from heat_rod import scaling_case

    return scaling_case()
