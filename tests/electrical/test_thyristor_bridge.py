"""The hard case of the ideal thyristor: a fully controlled single-phase bridge over 1,000 periods.

230 V, 50 Hz through 0.1 Ohm and 2 mH into a two-pulse bridge of four
``IdealThyristor`` (T1, T2 fired at alpha = 60 degrees, T3, T4 half a period
later) feeding 10 Ohm in series with 0.1 H: the load angle atan(wL/R) = 72
degrees exceeds alpha, so the load current never stops, and the source
inductance makes every commutation an overlap in which all four thyristors
conduct until the outgoing pair's current reaches zero (a state event).

Checked against an independent computation: the circuit's nodal equations
written by hand for each conduction state (each thyristor on its conducting
or blocking line, ``Ron``, ``Goff``, ``Vknee`` included), each a linear ODE
with a sinusoidal input solved in closed form, the turn-off instants found
by ``brentq`` where the outgoing thyristor's path parameter ``s`` reaches
zero, and the periodic steady state as the fixed point of the period map.
That closed-form solution is itself checked against scipy's ``solve_ivp``
of the same equations.  See docs/hard-cases.md.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

from acausal import Eq, Experiment, Model, Variable, der, simulate
from acausal.library.blocks import BooleanPulse, Not
from acausal.library.electrical import Ground, Inductor, Resistor, SineVoltage
from acausal.library.electrical.ideal import IdealThyristor

V_AMPL, F_SRC, R_SRC, L_SRC = 230 * np.sqrt(2), 50.0, 0.1, 2e-3
RON, GOFF, VKNEE = 1e-3, 1e-5, 0.7
R_LOAD, L_LOAD = 10.0, 0.1
ALPHA = np.pi / 3                       # delay angle
OMEGA, T = 2 * np.pi * F_SRC, 1 / F_SRC
T_FIRE = ALPHA / OMEGA                  # T1, T2 fired at T_FIRE + k*T; T3, T4 at T/2 + T_FIRE + k*T
PERIODS = 1000


class FullBridge(Model):
    """The two-pulse thyristor bridge with wide firing pulses; energy meters and a charge meter as states.

    Nodes: ``a`` (after the source impedance), ``b`` (the source's return,
    grounded), ``p`` and ``n`` (the DC side).  T1: a -> p, T2: n -> b,
    T3: b -> p, T4: n -> a.  Each pair's gate is held for half a period
    from its firing instant: one ``BooleanPulse`` (50 %) fires T1, T2 and its
    negation T3, T4, so a period has exactly two time events (the negation
    also gates T3, T4 before the first firing, while they are reverse biased).
    """

    # Radau: while one pair blocks, the inductors' difference current runs through the blocking
    # thyristors' Goff (-2.6e7 1/s); rtol 1e-5 keeps 1,000 periods within about 17 s of CPU
    # (1e-6: 27 s), rows at the period starts and middles only
    experiment = Experiment(stop_time=PERIODS * T, interval=T / 2, method="Radau", tolerance=1e-5)

    E_source = Variable(unit="J", start=0.0, fixed=True)
    E_load = Variable(unit="J", start=0.0, fixed=True)
    E_losses = Variable(unit="J", start=0.0, fixed=True)
    Q_load = Variable(unit="C", start=0.0, fixed=True)

    def build(self):
        self.src = SineVoltage(V=V_AMPL, f=F_SRC)
        self.Rs = Resistor(R=R_SRC)
        self.Ls = Inductor(L=L_SRC, i=dict(start=0, fixed=True))
        thyristor = dict(Ron=RON, Goff=GOFF, Vknee=VKNEE)
        self.T1, self.T2, self.T3, self.T4 = (IdealThyristor(**thyristor) for _ in range(4))
        self.R = Resistor(R=R_LOAD)
        self.L = Inductor(L=L_LOAD, i=dict(start=0, fixed=True))
        self.fire12 = BooleanPulse(period=T, width=50, startTime=T_FIRE)
        self.fire34 = Not()
        self.g = Ground()
        self.connect(self.src.p, self.Rs.p)
        self.connect(self.Rs.n, self.Ls.p)
        self.connect(self.Ls.n, self.T1.p)      # node a
        self.connect(self.Ls.n, self.T4.n)
        self.connect(self.T1.n, self.R.p)       # node p
        self.connect(self.T3.n, self.R.p)
        self.connect(self.R.n, self.L.p)
        self.connect(self.L.n, self.T2.p)       # node n
        self.connect(self.L.n, self.T4.p)
        self.connect(self.T2.n, self.g.p)       # node b
        self.connect(self.T3.p, self.g.p)
        self.connect(self.src.n, self.g.p)
        self.connect(self.fire12.y, self.fire34.u)
        self.connect(self.fire12.y, self.T1.fire)
        self.connect(self.fire12.y, self.T2.fire)
        self.connect(self.fire34.y, self.T3.fire)
        self.connect(self.fire34.y, self.T4.fire)

    def equations(self):
        thyristors = self.T1.LossPower + self.T2.LossPower + self.T3.LossPower + self.T4.LossPower
        return [Eq(der(self.E_source), self.src.v * self.Ls.i),
                Eq(der(self.E_load), self.R.LossPower),
                Eq(der(self.E_losses), self.Rs.LossPower + thyristors),
                Eq(der(self.Q_load), self.L.i)]


# --------------------------------------------------------------------------
# the independent computation: nodal analysis per conduction state, by hand

NODE_A, NODE_P, NODE_N = 0, 1, 2        # the unknown potentials; node b is ground (None)
THYRISTORS = {"T1": (NODE_A, NODE_P), "T2": (NODE_N, None), "T3": (None, NODE_P), "T4": (NODE_N, NODE_A)}


def _conduction_state(on: tuple[str, ...]):
    """The linear ODE of one conduction state: x = [i_s, i_L], ``x' = A x + b u + c`` (u the source voltage).

    A conducting thyristor is the line ``i = (v - Vknee)/Ron + Goff*Vknee``
    (its ``s = i - Goff*Vknee``), a blocking one ``i = Goff*v`` (its
    ``s = v - Vknee``).  The potentials of a, p, n follow from Kirchhoff's
    current law, linear in ``(i_s, i_L, u)``; returns ``A, b, c`` and, per
    thyristor, ``s`` as a linear function ``(coefficients of (i_s, i_L, u), constant)``.
    """
    G, J, j0, lines = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros(3), {}
    for name, (anode, cathode) in THYRISTORS.items():
        e = np.zeros(3)             # the thyristor's voltage is e @ (va, vp, vn)
        if anode is not None:
            e[anode] += 1
        if cathode is not None:
            e[cathode] -= 1
        g, i0 = (1 / RON, GOFF * VKNEE - VKNEE / RON) if name in on else (GOFF, 0.0)
        lines[name] = (e, g, i0)
        G += g * np.outer(e, e)     # i = g*v + i0 leaves the anode, enters the cathode
        j0 -= i0 * e
    J[NODE_A, 0] = 1.0              # the source current enters a
    J[NODE_P, 1], J[NODE_N, 1] = -1.0, 1.0   # the load current leaves p and returns at n
    K = np.linalg.solve(G, np.column_stack([J, j0]))
    Kx, k0 = K[:, :3], K[:, 3]      # (va, vp, vn) = Kx @ (i_s, i_L, u) + k0
    A, b, c = np.zeros((2, 2)), np.zeros(2), np.zeros(2)
    # Ls*di_s/dt = u - Rs*i_s - va;  L*di_L/dt = vp - vn - R*i_L
    A[0], b[0], c[0] = (-Kx[NODE_A, :2] - [R_SRC, 0]) / L_SRC, (1 - Kx[NODE_A, 2]) / L_SRC, -k0[NODE_A] / L_SRC
    dv = Kx[NODE_P] - Kx[NODE_N]
    A[1], b[1], c[1] = (dv[:2] - [0, R_LOAD]) / L_LOAD, dv[2] / L_LOAD, (k0[NODE_P] - k0[NODE_N]) / L_LOAD
    s = {}
    for name, (e, g, i0) in lines.items():
        v_coef, v_const = e @ Kx, e @ k0
        s[name] = (g * v_coef, g * v_const + i0 - GOFF * VKNEE) if name in on else (v_coef, v_const - VKNEE)
    return A, b, c, s


class ConductionState:
    """One conduction state's ODE and its solution in closed form.

    ``x(t) = xp(t) + exp(A (t - t0)) (x0 - xp(t0))`` with the periodic
    particular solution ``xp = Im(Z exp(iwt)) - A^-1 c = P sin(wt) + Q cos(wt) - A^-1 c``,
    ``(iw - A) Z = b V``, ``P + iQ = Z``.  ``exp(A t)`` by the
    eigendecomposition (two real eigenvalues: the load's and, with two
    thyristors blocking, the leakage loop's, -2.6e7 1/s).
    """

    def __init__(self, on: tuple[str, ...]):
        self.A, self.b, self.c, self.s = _conduction_state(on)
        amplitude = np.linalg.solve(1j * OMEGA * np.eye(2) - self.A, self.b * V_AMPL)
        self.P, self.Q = amplitude.real, amplitude.imag
        self.x_const = -np.linalg.solve(self.A, self.c)
        lam, V = np.linalg.eig(self.A)
        assert np.all(np.isreal(lam)) and np.all(lam.real < 0)
        self.lam, self.V = lam.real, V.real
        self.V_inv = np.linalg.inv(self.V)

    def rhs(self, t: float, x: np.ndarray) -> np.ndarray:
        return self.A @ x + self.b * V_AMPL * np.sin(OMEGA * t) + self.c

    def particular(self, t: float) -> np.ndarray:
        return self.P * np.sin(OMEGA * t) + self.Q * np.cos(OMEGA * t) + self.x_const

    def x(self, t0: float, x0: np.ndarray, t: float) -> np.ndarray:
        return self.particular(t) + self.V @ (np.exp(self.lam * (t - t0)) * (self.V_inv @ (x0 - self.particular(t0))))

    def path_parameter(self, name: str, x: np.ndarray, t: float) -> float:
        coef, const = self.s[name]
        return coef[:2] @ x + coef[2] * V_AMPL * np.sin(OMEGA * t) + const


STATES = {"T1T2": ConductionState(("T1", "T2")), "T3T4": ConductionState(("T3", "T4")),
          "overlap": ConductionState(("T1", "T2", "T3", "T4"))}


def _turn_off(state: ConductionState, t0: float, x0: np.ndarray, name: str, t_max: float) -> float:
    """The first instant after ``t0`` where thyristor ``name``'s ``s`` falls through zero."""
    def s(t):
        return state.path_parameter(name, state.x(t0, x0, t), t)
    grid = np.linspace(t0, t_max, 400)
    k = next(k for k in range(1, len(grid)) if s(grid[k]) < 0)
    return brentq(s, grid[k - 1], grid[k], xtol=1e-16, rtol=4 * np.finfo(float).eps)


def independent_period(x0: np.ndarray):
    """One period from ``x0`` at t = 0 (T3, T4 conducting): x(T), the turn-off instants, the pieces.

    T1, T2 fire at T_FIRE (forward biased: their ``s > 0`` is checked), all
    four conduct until T3's ``s`` reaches zero (T4's at the same instant, by
    the bridge's symmetry: checked), T1, T2 conduct until T3, T4 fire, and
    the same with the pairs exchanged.
    """
    pair12, pair34, overlap = STATES["T1T2"], STATES["T3T4"], STATES["overlap"]
    t_a, t_b = T_FIRE, T / 2 + T_FIRE
    x_a = pair34.x(0.0, x0, t_a)
    assert pair34.path_parameter("T1", x_a, t_a) > 0 and pair34.path_parameter("T2", x_a, t_a) > 0
    t1 = _turn_off(overlap, t_a, x_a, "T3", t_b)
    assert abs(_turn_off(overlap, t_a, x_a, "T4", t_b) - t1) < 1e-12
    x1 = overlap.x(t_a, x_a, t1)
    x_b = pair12.x(t1, x1, t_b)
    assert pair12.path_parameter("T3", x_b, t_b) > 0 and pair12.path_parameter("T4", x_b, t_b) > 0
    t2 = _turn_off(overlap, t_b, x_b, "T1", T)
    assert abs(_turn_off(overlap, t_b, x_b, "T2", T) - t2) < 1e-12
    x2 = overlap.x(t_b, x_b, t2)
    pieces = [(pair34, 0.0, x0, t_a), (overlap, t_a, x_a, t1), (pair12, t1, x1, t_b),
              (overlap, t_b, x_b, t2), (pair34, t2, x2, T)]
    return pair34.x(t2, x2, T), (t1, t2), pieces


def periodic_steady_state():
    """The fixed point of the period map (it contracts by exp(-R*T/L) = 0.14 a period)."""
    x = np.array([-10.0, 10.0])
    for _ in range(60):
        x_next, switches, pieces = independent_period(x)
        if np.max(np.abs(x_next - x)) < 1e-12:
            return x_next, switches, pieces
        x = x_next
    raise AssertionError("the period map did not converge")


def _per_period(pieces):
    """The source's energy and the load's charge over one period of the independent solution."""
    energy = charge = 0.0
    for state, t0, x0, t1 in pieces:
        energy += quad(lambda t: V_AMPL * np.sin(OMEGA * t) * state.x(t0, x0, t)[0], t0, t1,
                       epsabs=1e-12, epsrel=1e-13, limit=200)[0]
        charge += quad(lambda t: state.x(t0, x0, t)[1], t0, t1, epsabs=1e-14, epsrel=1e-13, limit=200)[0]
    return energy, charge


# --------------------------------------------------------------------------
# the tests


def test_independent_solution_matches_solve_ivp():
    """The closed-form solution of each conduction state is scipy's solution of the same ODE."""
    x_star, switches, pieces = periodic_steady_state()
    assert np.allclose(np.degrees(OMEGA * np.array(switches)) % 180, 61.0975, atol=1e-3)  # a 1.1 degree overlap
    for state, t0, x0, t1 in pieces:
        sol = solve_ivp(state.rhs, (t0, t1), x0, method="Radau", rtol=1e-11, atol=1e-11, jac=state.A)
        assert sol.success
        assert np.allclose(sol.y[:, -1], state.x(t0, x0, t1), rtol=0, atol=1e-10)


def test_thyristor_bridge_thousand_periods():
    """Two firings and two turn-offs a period, no drift, the independent steady state, energy balanced."""
    x_star, switches, pieces = periodic_steady_state()
    energy_per_period, charge_per_period = _per_period(pieces)

    r = simulate(FullBridge())
    assert r.success, r.message
    state_events = [e for e in r.events if e.kind == "state"]
    time_events = [e for e in r.events if e.kind == "time"]
    # the pulse's rise and fall at the firing instants, no other time event
    firings = np.sort(np.concatenate([T_FIRE + T * np.arange(PERIODS), T / 2 + T_FIRE + T * np.arange(PERIODS)]))
    assert np.allclose([float(e.time) for e in time_events], firings, rtol=0, atol=1e-12)
    # each overlap ends in one state event for the outgoing pair (both of its thyristors at once):
    # two a period, exactly; the first half period has no overlap (the bridge starts without current)
    per_period = np.bincount([int(float(e.time) // T) for e in state_events], minlength=PERIODS)
    assert per_period[0] == 1 and np.all(per_period[1:] == 2) and len(per_period) == PERIODS
    # (their two crossings coincide up to round-off: the event names one or both relations)
    outgoing = [{("T1.off", False, True), ("T2.off", False, True)}, {("T3.off", False, True), ("T4.off", False, True)}]
    assert all(set(e.changes) == outgoing[k % 2] for k, e in enumerate(state_events))
    # no drift: the currents at the start of each of the last 900 periods are the independent
    # periodic steady state, with no trend
    ks = np.arange(100, PERIODS + 1)
    starts = np.column_stack([r.at(ks * T, "Ls.i"), r.at(ks * T, "L.i")])
    assert np.max(np.abs(starts - x_star)) < 5e-5        # of 12.4 A
    for column in starts.T:
        assert abs(np.polyfit(ks, column, 1)[0]) * len(ks) < 1e-5
    # the turn-off instants of the last period are the independent ones
    last = sorted(float(e.time) - (PERIODS - 1) * T for e in state_events[-2:])
    assert np.allclose(last, switches, rtol=0, atol=1e-8)
    # the last period's source energy and load charge (mean load voltage R*Q/T) are the independent ones
    energy, charge = (r.at(PERIODS * T, name) - r.at((PERIODS - 1) * T, name) for name in ("E_source", "Q_load"))
    assert abs(energy - energy_per_period) < 2e-5 * energy_per_period
    assert abs(charge - charge_per_period) < 1e-6 * charge_per_period
    # energy: what the source delivered = the load's and the losses + the inductors' stored energy
    stored = L_SRC / 2 * r["Ls.i"][-1] ** 2 + L_LOAD / 2 * r["L.i"][-1] ** 2
    source, load, losses = r["E_source"][-1], r["E_load"][-1], r["E_losses"][-1]
    assert source > 0 and abs(source - load - losses - stored) < 2e-6 * source
