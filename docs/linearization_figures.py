"""The figures and numbers of docs/linearization.md.

Run from the repository root::

    python docs/linearization_figures.py

It writes ``docs/figures/linearize_bode_stuck.png``,
``docs/figures/linearize_bode_sliding.png`` and
``docs/figures/linearize_eigenvalues.png`` and prints the matrices,
eigenvalues and steady states the page quotes.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sys  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: examples/
from acausal import simulate, translate  # noqa: E402
from acausal.tools.linearize import linearize, steady_state  # noqa: E402
from examples.clutch_drive import ClutchDrive  # noqa: E402
from examples.fan_drive import FanDrive  # noqa: E402

FIGURES = Path(__file__).resolve().parent / "figures"


def frequency_response(lin, omega):
    """``C (j w I - A)^-1 B + D`` of the first input and output, at every ``omega``."""
    n = lin.A.shape[0]
    return np.array([(lin.C @ np.linalg.solve(1j * w * np.eye(n) - lin.A, lin.B) + lin.D)[0, 0]
                     for w in omega])


def bode(lin, other, title, path):
    omega = np.logspace(0, 2.5, 600)
    figure, (magnitude, phase) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 4.8))
    for item, style, label in ((other, dict(color="0.6", ls="--"), other.discrete_state),
                               (lin, dict(color="C0"), lin.discrete_state)):
        response = frequency_response(item, omega)
        magnitude.semilogx(omega, 20 * np.log10(np.abs(response)), label=label, **style)
        phase.semilogx(omega, np.degrees(np.unwrap(np.angle(response))), **style)
    magnitude.set_ylabel("|J2.w / torque.tau| [dB]")
    phase.set_ylabel("phase [deg]")
    phase.set_xlabel("angular frequency [rad/s]")
    magnitude.set_title(title)
    magnitude.legend(fontsize=8)
    for axis in (magnitude, phase):
        axis.grid(True, which="both", alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


def main() -> None:
    warnings.simplefilter("ignore")
    FIGURES.mkdir(exist_ok=True)
    translation = translate(ClutchDrive())
    result = simulate(translation).raise_for_status()
    times = sorted({0.0, *(float(e.time) for e in result.events), 2.0})
    found = {}
    for a, b in zip(times, times[1:]):
        if b - a > 2e-3:
            lin = linearize(translation, at=0.5 * (a + b), inputs=["torque.tau"], outputs=["J2.w"])
            found.setdefault(lin.discrete_state, lin)
    stuck = found["clutch: Stuck (locked)"]
    sliding = found["clutch: Forward"]
    with np.printoptions(precision=4, suppress=True, linewidth=100):
        for lin in (stuck, sliding):
            print(f"## {lin.discrete_state} at t = {lin.t:.4f}")
            print("states", lin.state_names)
            print("A =\n", lin.A)
            print("B =\n", lin.B.T)
            print("C =\n", lin.C)
            print("eigenvalues", lin.eigenvalues)
    bode(stuck, sliding, "clutch drive, stuck", FIGURES / "linearize_bode_stuck.png")
    bode(sliding, stuck, "clutch drive, sliding forward", FIGURES / "linearize_bode_sliding.png")

    figure, axis = plt.subplots(figsize=(5.2, 4.0))
    for lin, marker in ((stuck, "o"), (sliding, "x")):
        values = lin.eigenvalues
        axis.plot(values.real, values.imag, marker, ls="none", ms=8, mfc="none", label=lin.discrete_state)
    axis.axvline(0, color="0.5", lw=0.8)
    axis.set_xlabel("real part [1/s]")
    axis.set_ylabel("imaginary part [1/s]")
    axis.set_title("eigenvalues of A per discrete state")
    axis.grid(True, alpha=0.3)
    axis.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(FIGURES / "linearize_eigenvalues.png", dpi=110)
    plt.close(figure)

    found = steady_state(FanDrive(), guess={"J.w": 1.0})
    print("fan steady state", found.states, found.free, found.residual,
          "closed form", 10.0 * math.sqrt(3.0 / 1.5))
    lin = linearize(FanDrive(), at=found.states, outputs=["J.w"])
    print("fan A", lin.A, lin.state_names)


if __name__ == "__main__":
    main()
