"""Explicit Runge-Kutta pairs in numpy: Dormand-Prince 5(4) and 8(5,3).

The explicit methods of :func:`acausal.simulate` (``'RK45'``, ``'DOP853'``)
need nothing but numpy: this module holds them, so that scipy is imported only
for the implicit methods.  The solvers keep the contract of scipy's
``scipy.integrate.OdeSolver`` and ``DenseOutput`` -- the same attributes
(``t``, ``y``, ``t_old``, ``t_bound``, ``direction``, ``status``, ``step_size``,
``nfev``, ``njev``, ``nlu``, ``f``) and methods (``step()``, ``dense_output()``)
with the same meanings -- so a loop written for scipy's solvers drives these
unchanged.

They take the same steps as scipy's ``RK45`` and ``DOP853`` (scipy 1.17): the
initial step of Hairer, Norsett & Wanner (II.4), the RMS error norm of
``err / (atol + rtol * max(|y|, |y_new|))``, a new step of
``0.9 * err**(-1/(q+1))`` times the old one, bounded to [0.2, 10] and not
growing after a rejection, ``max_step`` and ``first_step``, the last step
shortened to land exactly on ``t_bound``, integration backwards when
``t_bound < t0``.  The arithmetic is done with the same numpy operations in the
same order, so the accepted steps, the states and the dense output are those
of scipy, as a rule bit for bit (``tests/runtime/test_explicit_rk.py`` checks
them against scipy).

Differences from scipy, none of which changes a step:

* real states only (scipy's explicit solvers accept complex ones);
* a step's interpolant is built once: calling ``dense_output()`` again for the
  same step returns the same object (scipy's ``DOP853`` evaluates its three
  extra stages again, and counts them in ``nfev`` again);
* the dense output of ``RK45`` called with an array of instants gives, column
  by column, what it gives called with each instant alone (scipy's is one
  matrix product, whose rounding differs in the last bits).

References
----------
.. [1] J. R. Dormand and P. J. Prince, "A family of embedded Runge-Kutta
       formulae", Journal of Computational and Applied Mathematics 6 (1),
       pp. 19-26, 1980.
.. [2] L. F. Shampine, "Some practical Runge-Kutta formulas", Mathematics of
       Computation 46 (173), pp. 135-150, 1986.
.. [3] E. Hairer, S. P. Norsett and G. Wanner, "Solving Ordinary Differential
       Equations I: Nonstiff Problems", 2nd ed., Springer, 1993: Sec. II.4
       (automatic step size control, starting step size), II.5 (Table 5.2,
       the Dormand-Prince 5(4) pair), II.6 (dense output), II.10 (DOP853).
.. [4] E. Hairer and G. Wanner, ``dop853.f`` (Fortran code of DOP853, version
       of 1993 and later), https://www.unige.ch/~hairer/software.html.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

__all__ = ["OdeSolver", "DenseOutput", "ConstantDenseOutput", "RungeKutta", "RK45", "DOP853", "QuarticDenseOutput",
           "Dop853DenseOutput"]

EPS = float(np.finfo(float).eps)

#: Step-size control (as scipy's, [3]_ II.4): a new step is ``SAFETY * err**(-1/(q+1))``
#: times the last, and never less than ``MIN_FACTOR`` nor more than ``MAX_FACTOR`` times it.
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0


# -- the contract ----------------------------------------------------------------------------------

class OdeSolver:
    """A one-step ODE solver, stepped by its caller: scipy's ``OdeSolver`` contract.

    Subclasses implement ``_step_impl()``, returning ``(success, message)``,
    and ``_dense_output_impl()``, returning the :class:`DenseOutput` of the
    last step; this class does the bookkeeping around them (``t_old``,
    ``status``, a system of no equations, a zero-length interval, counting the
    evaluations of the right-hand side made through :attr:`fun`).

    Parameters
    ----------
    fun : callable
        The right-hand side ``fun(t, y)`` of ``dy/dt = f(t, y)``; ``y`` has
        shape ``(n,)`` and so has what ``fun`` returns (any array-like).
    t0 : float
        Initial time.
    y0 : array_like, shape (n,)
        Initial state; real and finite.
    t_bound : float
        Boundary time: the integration stops there, and its sign relative to
        ``t0`` is the direction of integration.
    vectorized : bool
        Whether ``fun`` takes states as columns, ``fun(t, Y)`` with ``Y`` of
        shape ``(n, k)``; these solvers then call it with one column.
    support_complex : bool, optional
        Accepted for the signature of scipy's class; complex states are
        refused all the same.

    Attributes
    ----------
    n : int
        Number of equations.
    status : str
        ``'running'``, ``'finished'`` (``t_bound`` reached) or ``'failed'``.
    t_bound : float
        Boundary time.
    direction : float
        +1.0 forwards, -1.0 backwards (+1.0 when ``t_bound == t0``).
    t : float
        Current time.
    y : ndarray, shape (n,)
        Current state.
    t_old : float or None
        Time before the last step; None before the first.
    step_size : float or None
        ``|t - t_old|``, the size of the last step; None before the first.
    nfev, njev, nlu : int
        Evaluations of the right-hand side, of the Jacobian, LU decompositions.
    fun : callable
        ``fun(t, y)`` as an ndarray of floats, counted in ``nfev``.
    fun_single : callable
        The same, not counted.

    References
    ----------
    .. [1] E. Hairer, S. P. Norsett and G. Wanner, "Solving Ordinary
           Differential Equations I: Nonstiff Problems", 2nd ed., Springer,
           1993.
    """

    #: The message of a step that would be below the resolution of the time axis.
    TOO_SMALL_STEP = "Required step size is less than spacing between numbers."

    def __init__(self, fun, t0, y0, t_bound, vectorized, support_complex=False):
        y0 = np.asarray(y0)
        if np.iscomplexobj(y0):
            raise ValueError("`y0` is complex: these solvers integrate real states only.")
        y0 = y0.astype(float, copy=False)
        if y0.ndim != 1:
            raise ValueError("`y0` must be 1-dimensional.")
        if not np.isfinite(y0).all():
            raise ValueError("All components of the initial state `y0` must be finite.")
        self.t_old = None
        self.t = float(t0)
        self.y = y0
        self.t_bound = float(t_bound)
        self.vectorized = bool(vectorized)
        self.direction = 1.0 if self.t_bound >= self.t else -1.0
        self.n = y0.size
        self.status = "running"
        self.nfev = 0
        self.njev = 0
        self.nlu = 0

        if vectorized:
            def single(t, y):
                return np.asarray(fun(t, y[:, None]), dtype=float).ravel()

            def counted(t, y):
                self.nfev += 1
                return np.asarray(fun(t, y[:, None]), dtype=float).ravel()
        else:
            def single(t, y):
                return np.asarray(fun(t, y), dtype=float)

            def counted(t, y):
                self.nfev += 1
                return np.asarray(fun(t, y), dtype=float)
        self.fun_single = single
        self.fun = counted

    @property
    def step_size(self):
        """``|t - t_old|``: the size of the last step (None before the first)."""
        return None if self.t_old is None else abs(self.t - self.t_old)

    def step(self):
        """Take one step.

        Returns
        -------
        message : str or None
            Why the step failed (``status`` is then ``'failed'``), else None.

        Raises
        ------
        RuntimeError
            If the solver has already finished or failed.
        """
        if self.status != "running":
            raise RuntimeError("Attempt to step on a failed or finished solver.")
        if self.n == 0 or self.t == self.t_bound:
            # nothing to integrate: jump to the end
            self.t_old = self.t
            self.t = self.t_bound
            self.status = "finished"
            return None
        t = self.t
        success, message = self._step_impl()
        if not success:
            self.status = "failed"
            return message
        self.t_old = t
        if self.direction * (self.t - self.t_bound) >= 0:
            self.status = "finished"
        return message

    def dense_output(self):
        """The interpolant of the last step.

        Returns
        -------
        DenseOutput
            Defined on ``[t_old, t]`` (evaluating outside it extrapolates).

        Raises
        ------
        RuntimeError
            Before the first step.
        """
        if self.t_old is None:
            raise RuntimeError("Dense output is available after a successful step was made.")
        if self.n == 0 or self.t == self.t_old:
            return ConstantDenseOutput(self.t_old, self.t, self.y)
        return self._dense_output_impl()

    def _step_impl(self):
        raise NotImplementedError

    def _dense_output_impl(self):
        raise NotImplementedError


class DenseOutput:
    """An interpolant over one step: scipy's ``DenseOutput`` contract.

    Subclasses implement ``_call_impl(t)`` for ``t`` a 0-d or 1-d ndarray.

    Parameters
    ----------
    t_old, t : float
        The ends of the step (``t < t_old`` backwards).

    Attributes
    ----------
    t_old, t : float
        The ends of the step.
    t_min, t_max : float
        The smaller and the larger of them.
    """

    def __init__(self, t_old, t):
        self.t_old = t_old
        self.t = t
        self.t_min = min(t, t_old)
        self.t_max = max(t, t_old)

    def __call__(self, t):
        """Evaluate the interpolant.

        Parameters
        ----------
        t : float or array_like, shape (m,)
            Instants; ones outside ``[t_min, t_max]`` are extrapolated.

        Returns
        -------
        ndarray, shape (n,) or (n, m)
            The state at ``t``, or at each instant as a column.
        """
        t = np.asarray(t)
        if t.ndim > 1:
            raise ValueError("`t` must be a float or a 1-D array.")
        return self._call_impl(t)

    def _call_impl(self, t):
        raise NotImplementedError


class ConstantDenseOutput(DenseOutput):
    """The interpolant of a step of zero length, or of a system of no equations."""

    def __init__(self, t_old, t, value):
        super().__init__(t_old, t)
        self.value = value

    def _call_impl(self, t):
        if t.ndim == 0:
            return self.value
        out = np.empty((self.value.shape[0], t.shape[0]))
        out[:] = self.value[:, None]
        return out


# -- the coefficients of DOP853 ([3]_, II.10; the constants of dop853.f [4]_) --------------------

# Nodes c_1 .. c_16 (HNW, and the constants C2 .. C16 of dop853.f); stages 14 .. 16
# are evaluated only for the dense output.
_DOP853_NODES = (
    0.0, 0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01, 0.118350341907227396726757197510,
    0.281649658092772603273242802490, 0.333333333333333333333333333333,
    0.25, 0.307692307692307692307692307692,
    0.651282051282051282051282051282, 0.6,
    0.857142857142857142857142857142, 1.0,
    1.0, 0.1,
    0.2, 0.777777777777777777777777777778,
)

# The non-zero a_ij of row i (0-based i, j) as {j: a_ij}.  Row 12 holds the
# weights b_j of the 8th-order solution (stage 13 is f at the new point).
_DOP853_ROWS = (
    {},
    {
        0: 5.26001519587677318785587544488e-2,
    },
    {
        0: 1.97250569845378994544595329183e-2,
        1: 5.91751709536136983633785987549e-2,
    },
    {
        0: 2.95875854768068491816892993775e-2,
        2: 8.87627564304205475450678981324e-2,
    },
    {
        0: 2.41365134159266685502369798665e-1,
        2: -8.84549479328286085344864962717e-1,
        3: 9.24834003261792003115737966543e-1,
    },
    {
        0: 3.7037037037037037037037037037e-2,
        3: 1.70828608729473871279604482173e-1,
        4: 1.25467687566822425016691814123e-1,
    },
    {
        0: 3.7109375e-2,
        3: 1.70252211019544039314978060272e-1,
        4: 6.02165389804559606850219397283e-2,
        5: -1.7578125e-2,
    },
    {
        0: 3.70920001185047927108779319836e-2,
        3: 1.70383925712239993810214054705e-1,
        4: 1.07262030446373284651809199168e-1,
        5: -1.53194377486244017527936158236e-2,
        6: 8.27378916381402288758473766002e-3,
    },
    {
        0: 6.24110958716075717114429577812e-1,
        3: -3.36089262944694129406857109825,
        4: -8.68219346841726006818189891453e-1,
        5: 2.75920996994467083049415600797e1,
        6: 2.01540675504778934086186788979e1,
        7: -4.34898841810699588477366255144e1,
    },
    {
        0: 4.77662536438264365890433908527e-1,
        3: -2.48811461997166764192642586468,
        4: -5.90290826836842996371446475743e-1,
        5: 2.12300514481811942347288949897e1,
        6: 1.52792336328824235832596922938e1,
        7: -3.32882109689848629194453265587e1,
        8: -2.03312017085086261358222928593e-2,
    },
    {
        0: -9.3714243008598732571704021658e-1,
        3: 5.18637242884406370830023853209,
        4: 1.09143734899672957818500254654,
        5: -8.14978701074692612513997267357,
        6: -1.85200656599969598641566180701e1,
        7: 2.27394870993505042818970056734e1,
        8: 2.49360555267965238987089396762,
        9: -3.0467644718982195003823669022,
    },
    {
        0: 2.27331014751653820792359768449,
        3: -1.05344954667372501984066689879e1,
        4: -2.00087205822486249909675718444,
        5: -1.79589318631187989172765950534e1,
        6: 2.79488845294199600508499808837e1,
        7: -2.85899827713502369474065508674,
        8: -8.87285693353062954433549289258,
        9: 1.23605671757943030647266201528e1,
        10: 6.43392746015763530355970484046e-1,
    },
    {
        0: 5.42937341165687622380535766363e-2,
        5: 4.45031289275240888144113950566,
        6: 1.89151789931450038304281599044,
        7: -5.8012039600105847814672114227,
        8: 3.1116436695781989440891606237e-1,
        9: -1.52160949662516078556178806805e-1,
        10: 2.01365400804030348374776537501e-1,
        11: 4.47106157277725905176885569043e-2,
    },
    {
        0: 5.61675022830479523392909219681e-2,
        6: 2.53500210216624811088794765333e-1,
        7: -2.46239037470802489917441475441e-1,
        8: -1.24191423263816360469010140626e-1,
        9: 1.5329179827876569731206322685e-1,
        10: 8.20105229563468988491666602057e-3,
        11: 7.56789766054569976138603589584e-3,
        12: -8.298e-3,
    },
    {
        0: 3.18346481635021405060768473261e-2,
        5: 2.83009096723667755288322961402e-2,
        6: 5.35419883074385676223797384372e-2,
        7: -5.49237485713909884646569340306e-2,
        10: -1.08347328697249322858509316994e-4,
        11: 3.82571090835658412954920192323e-4,
        12: -3.40465008687404560802977114492e-4,
        13: 1.41312443674632500278074618366e-1,
    },
    {
        0: -4.28896301583791923408573538692e-1,
        5: -4.69762141536116384314449447206,
        6: 7.68342119606259904184240953878,
        7: 4.06898981839711007970213554331,
        8: 3.56727187455281109270669543021e-1,
        12: -1.39902416515901462129418009734e-3,
        13: 2.9475147891527723389556272149,
        14: -9.15095847217987001081870187138,
    },
)

# Weights of the 5th-order error estimate, E5 (ER1, ER6 .. ER12 of dop853.f).
_DOP853_ERR5 = {
    0: 0.1312004499419488073250102996e-1,
    5: -0.1225156446376204440720569753e+1,
    6: -0.4957589496572501915214079952,
    7: 0.1664377182454986536961530415e+1,
    8: -0.3503288487499736816886487290,
    9: 0.3341791187130174790297318841,
    10: 0.8192320648511571246570742613e-1,
    11: -0.2235530786388629525884427845e-1,
}

# The weights bhh_j of the embedded 3rd-order solution (BHH1 .. BHH3 of dop853.f).
_DOP853_BHH = {
    0: 0.244094488188976377952755905512,
    8: 0.733846688281611857341361741547,
    11: 0.220588235294117647058823529412e-1,
}

# Coefficients d_4j .. d_7j of the dense output (D4* .. D7* of dop853.f).
_DOP853_DENSE = (
    {
        0: -0.84289382761090128651353491142e+1,
        5: 0.56671495351937776962531783590,
        6: -0.30689499459498916912797304727e+1,
        7: 0.23846676565120698287728149680e+1,
        8: 0.21170345824450282767155149946e+1,
        9: -0.87139158377797299206789907490,
        10: 0.22404374302607882758541771650e+1,
        11: 0.63157877876946881815570249290,
        12: -0.88990336451333310820698117400e-1,
        13: 0.18148505520854727256656404962e+2,
        14: -0.91946323924783554000451984436e+1,
        15: -0.44360363875948939664310572000e+1,
    },
    {
        0: 0.10427508642579134603413151009e+2,
        5: 0.24228349177525818288430175319e+3,
        6: 0.16520045171727028198505394887e+3,
        7: -0.37454675472269020279518312152e+3,
        8: -0.22113666853125306036270938578e+2,
        9: 0.77334326684722638389603898808e+1,
        10: -0.30674084731089398182061213626e+2,
        11: -0.93321305264302278729567221706e+1,
        12: 0.15697238121770843886131091075e+2,
        13: -0.31139403219565177677282850411e+2,
        14: -0.93529243588444783865713862664e+1,
        15: 0.35816841486394083752465898540e+2,
    },
    {
        0: 0.19985053242002433820987653617e+2,
        5: -0.38703730874935176555105901742e+3,
        6: -0.18917813819516756882830838328e+3,
        7: 0.52780815920542364900561016686e+3,
        8: -0.11573902539959630126141871134e+2,
        9: 0.68812326946963000169666922661e+1,
        10: -0.10006050966910838403183860980e+1,
        11: 0.77771377980534432092869265740,
        12: -0.27782057523535084065932004339e+1,
        13: -0.60196695231264120758267380846e+2,
        14: 0.84320405506677161018159903784e+2,
        15: 0.11992291136182789328035130030e+2,
    },
    {
        0: -0.25693933462703749003312586129e+2,
        5: -0.15418974869023643374053993627e+3,
        6: -0.23152937917604549567536039109e+3,
        7: 0.35763911791061412378285349910e+3,
        8: 0.93405324183624310003907691704e+2,
        9: -0.37458323136451633156875139351e+2,
        10: 0.10409964950896230045147246184e+3,
        11: 0.29840293426660503123344363579e+2,
        12: -0.43533456590011143754432175058e+2,
        13: 0.96324553959188282948394950600e+2,
        14: -0.39177261675615439165231486172e+2,
        15: -0.14972683625798562581422125276e+3,
    },
)


# -- helpers ---------------------------------------------------------------------------------------

def _rms(x) -> np.float64:
    """The RMS norm ``sqrt(sum(x**2) / n)``, computed as ``||x||_2 / sqrt(n)``.

    A numpy float, so that what is computed from it divides by zero or
    overflows as numpy does (inf or NaN, with a warning), not with an exception.
    """
    return np.float64(math.sqrt(float(np.dot(x, x)))) / x.size ** 0.5


def _check_tolerances(rtol, atol, n):
    """``(rtol, atol)`` made usable: rtol at least ``100 * eps`` (with a warning),
    atol a non-negative scalar or an array of shape ``(n,)``."""
    # (the methods of the arrays rather than np.any: a solver is made at every event)
    if (np.asarray(rtol) < 100 * EPS).any():
        warnings.warn(f"At least one element of `rtol` is too small. Setting `rtol = np.maximum(rtol, "
                      f"{100 * EPS})`.", stacklevel=4)
        rtol = np.maximum(rtol, 100 * EPS)
    rtol = float(rtol) if np.ndim(rtol) == 0 else np.asarray(rtol, dtype=float)
    atol = np.asarray(atol, dtype=float)
    if atol.ndim > 0 and atol.shape != (n,):
        raise ValueError("`atol` has wrong shape.")
    if (atol < 0).any():
        raise ValueError("`atol` must be positive.")
    return rtol, (float(atol) if atol.ndim == 0 else atol)


def _initial_step(fun, t0, y0, f0, t_bound, max_step, direction, q, rtol, atol) -> float:
    """The size of the first step, chosen as in [1]_ (II.4, "Starting step size").

    A step ``h0`` from the sizes of the state and of its derivative, one
    explicit Euler step of that size to estimate the second derivative, and
    the step ``h1`` whose local error of order ``q + 1`` that estimate puts
    at the tolerance; the result is the least of ``100 * h0``, ``h1``, the
    length of the interval and ``max_step``.  Costs one evaluation of ``fun``.

    Parameters
    ----------
    fun : callable
        The right-hand side (an evaluation counted by the solver).
    t0 : float
        Initial time.
    y0, f0 : ndarray, shape (n,)
        Initial state and derivative.
    t_bound : float
        Boundary time.
    max_step : float
        Largest step.
    direction : float
        +1.0 or -1.0.
    q : int
        Order of the error estimate (the local error goes as ``h**(q + 1)``).
    rtol, atol : float or ndarray
        Tolerances.

    Returns
    -------
    float
        The absolute size of the first step.

    References
    ----------
    .. [1] E. Hairer, S. P. Norsett and G. Wanner, "Solving Ordinary
           Differential Equations I: Nonstiff Problems", 2nd ed., Springer,
           1993, Sec. II.4.
    """
    if y0.size == 0:
        return math.inf
    span = abs(t_bound - t0)
    if span == 0.0:
        return 0.0
    scale = atol + np.abs(y0) * rtol
    d0 = _rms(y0 / scale)
    d1 = _rms(f0 / scale)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, span)  # the Euler step stays inside the interval
    f1 = fun(t0 + h0 * direction, y0 + h0 * direction * f0)
    d2 = _rms((f1 - f0) / scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1 / (q + 1))
    return min(100 * h0, h1, span, max_step)


def _sparse_rows(rows, width):
    """A dense matrix of ``len(rows)`` rows from rows given as ``{column: value}``."""
    out = np.zeros((len(rows), width))
    for i, row in enumerate(rows):
        for j, value in row.items():
            out[i, j] = value
    return out


# -- explicit Runge-Kutta pairs --------------------------------------------------------------------

class RungeKutta(OdeSolver):
    """An embedded explicit Runge-Kutta pair with local extrapolation and FSAL.

    Each step evaluates the stages ``k_i = f(t + c_i h, y + h sum_j a_ij k_j)``
    (``k_1`` the derivative at the step's start), advances with the weights
    ``b`` of the higher order, evaluates ``f`` at the new point (the first
    stage of the next step: "first same as last") and estimates the local
    error with the difference of the two solutions of the pair.  A step whose
    error norm is below one is accepted; the next step is the present one
    times ``SAFETY * err**(-1/(q+1))``, bounded to ``[MIN_FACTOR, MAX_FACTOR]``
    and at most one after a rejection in the same step ([1]_, II.4).

    Subclasses give the tableau (``C``, ``A``, ``B``), ``order``,
    ``error_estimator_order`` (``q``), ``n_stages``, the error estimate
    (``_error_norm``) and the dense output (``_dense_output_impl``).

    Parameters
    ----------
    fun : callable
        Right-hand side ``fun(t, y)``, ``y`` of shape ``(n,)``.
    t0 : float
        Initial time.
    y0 : array_like, shape (n,)
        Initial state (real, finite).
    t_bound : float
        Boundary time; the last step ends exactly on it.  ``t_bound < t0``
        integrates backwards.
    max_step : float, optional
        Largest step size (> 0); default unbounded.
    rtol, atol : float or array_like, optional
        Relative and absolute tolerances (atol a scalar or of shape ``(n,)``):
        the error of each component is held below ``atol + rtol * |y|`` in
        the RMS norm.  Defaults 1e-3 and 1e-6; rtol is raised to ``100 * eps``
        at least.
    vectorized : bool, optional
        ``fun`` takes states as columns (it is then called with one column).
    first_step : float, optional
        Size of the first step (> 0, at most ``|t_bound - t0|``); default
        chosen as in [1]_ (II.4).
    **extraneous
        Other keywords are ignored, with a warning.

    Attributes
    ----------
    f : ndarray, shape (n,)
        The derivative at ``(t, y)``.
    y_old : ndarray or None
        The state at ``t_old``.
    h_abs : float
        The size proposed for the next step.
    h_previous : float or None
        The last step, signed.
    max_step, rtol, atol
        As given (validated).

    See Also
    --------
    OdeSolver : the attributes common to all solvers.

    References
    ----------
    .. [1] E. Hairer, S. P. Norsett and G. Wanner, "Solving Ordinary
           Differential Equations I: Nonstiff Problems", 2nd ed., Springer,
           1993.
    """

    C: np.ndarray
    A: np.ndarray
    B: np.ndarray
    order: int
    error_estimator_order: int
    n_stages: int
    #: rows of the stage array ``K`` (the stages, the derivative at the new point, extra stages)
    n_stored_stages: int

    def __init__(self, fun, t0, y0, t_bound, max_step=np.inf, rtol=1e-3, atol=1e-6, vectorized=False,
                 first_step=None, **extraneous):
        if extraneous:
            warnings.warn("The following arguments have no effect for a chosen solver: "
                          f"{', '.join(f'`{name}`' for name in extraneous)}.", stacklevel=2)
        super().__init__(fun, t0, y0, t_bound, vectorized)
        if max_step <= 0:
            raise ValueError("`max_step` must be positive.")
        self.max_step = max_step
        self.rtol, self.atol = _check_tolerances(rtol, atol, self.n)
        self.y_old = None
        self.f = self.fun(self.t, self.y)
        if first_step is None:
            self.h_abs = _initial_step(self.fun, self.t, self.y, self.f, self.t_bound, max_step,
                                       self.direction, self.error_estimator_order, self.rtol, self.atol)
        else:
            if first_step <= 0:
                raise ValueError("`first_step` must be positive.")
            if first_step > abs(self.t_bound - self.t):
                raise ValueError("`first_step` exceeds bounds.")
            self.h_abs = first_step
        self.K = K = np.empty((self.n_stored_stages, self.n))
        # views of the stages each stage combines, made once: (row, c_s, K[:s].T, a_s[:s])
        self._stages = tuple((K[s], c, K[:s].T, a) for s, c, a in self._plan)
        self._K_main_T = K[:self.n_stages].T
        self.error_exponent = -1 / (self.error_estimator_order + 1)
        self.h_previous = None
        self._dense = None  # the last step's interpolant, built on demand

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "A" in cls.__dict__:
            # stage s combines the s stages before it: (s, c_s, a_s[:s]) for s = 1 .. n_stages-1
            cls._plan = tuple((s, float(cls.C[s]), np.ascontiguousarray(cls.A[s, :s]))
                              for s in range(1, cls.n_stages))

    def _advance(self, t, y, h):
        """One attempt: fill the stages ``K`` for the step ``h`` from ``(t, y)``.

        Returns ``(y_new, f_new)``: the higher-order solution at ``t + h`` and
        the derivative there (also stored as stage ``n_stages``).
        """
        K = self.K
        fun = self.fun
        K[0] = self.f
        for row, c, previous, a in self._stages:
            row[:] = fun(t + c * h, y + np.dot(previous, a) * h)
        y_new = y + h * np.dot(self._K_main_T, self.B)
        f_new = fun(t + h, y_new)
        K[self.n_stages] = f_new
        return y_new, f_new

    def _error_norm(self, h, scale) -> float:
        """The RMS norm of the local error estimate of the last attempt, divided by ``scale``."""
        raise NotImplementedError

    def _step_impl(self):
        t = self.t
        y = self.y
        direction = self.direction
        max_step = self.max_step
        # ten spacings of floating-point numbers at t: no step can be smaller
        min_step = 10 * abs(math.nextafter(t, direction * math.inf) - t)
        if self.h_abs > max_step:
            h_abs = max_step
        elif self.h_abs < min_step:
            h_abs = min_step
        else:
            h_abs = self.h_abs

        rejected = False
        while True:
            if h_abs < min_step:
                return False, self.TOO_SMALL_STEP
            t_new = t + h_abs * direction
            if direction * (t_new - self.t_bound) > 0:
                t_new = self.t_bound  # land exactly on the boundary
            h = t_new - t
            h_abs = abs(h)
            y_new, f_new = self._advance(t, y, h)
            # atol + rtol * max(|y|, |y_new|), in place
            scale = np.abs(y_new)
            np.maximum(scale, np.abs(y), out=scale)
            scale *= self.rtol
            scale += self.atol
            error_norm = self._error_norm(h, scale)
            if error_norm < 1:
                if error_norm == 0:
                    factor = MAX_FACTOR
                else:
                    factor = min(MAX_FACTOR, SAFETY * error_norm ** self.error_exponent)
                if rejected:
                    factor = min(1, factor)
                h_abs *= factor
                break
            h_abs *= max(MIN_FACTOR, SAFETY * error_norm ** self.error_exponent)
            rejected = True

        self.h_previous = h
        self.y_old = y
        self.t = t_new
        self.y = y_new
        self.f = f_new
        self.h_abs = h_abs
        self._dense = None
        return True, None

    def _dense_output_impl(self):
        if self._dense is None:
            self._dense = self._build_dense_output()
        return self._dense

    def _build_dense_output(self):
        raise NotImplementedError


class RK45(RungeKutta):
    """The Dormand-Prince 5(4) pair ("DOPRI5"), with its free 4th-order interpolant.

    Seven stages, the last the derivative at the new point (FSAL: six new
    evaluations per step); the step advances with the 5th-order solution and
    the error is estimated against the embedded 4th-order one, ``q = 4``
    ([1]_; [3]_, II.5, Table 5.2).  The dense output is the quartic of
    Shampine [2]_ (the continuous extension of [3]_, II.6, with his optimal
    choice of the free parameter), a free by-product of the stages.

    Parameters and attributes are those of :class:`RungeKutta`.

    References
    ----------
    .. [1] J. R. Dormand and P. J. Prince, "A family of embedded Runge-Kutta
           formulae", Journal of Computational and Applied Mathematics 6 (1),
           pp. 19-26, 1980.
    .. [2] L. F. Shampine, "Some practical Runge-Kutta formulas", Mathematics
           of Computation 46 (173), pp. 135-150, 1986.
    .. [3] E. Hairer, S. P. Norsett and G. Wanner, "Solving Ordinary
           Differential Equations I: Nonstiff Problems", 2nd ed., Springer,
           1993.
    """

    order = 5
    error_estimator_order = 4
    n_stages = 6
    n_stored_stages = 7
    C = np.array([0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1])
    A = np.array([
        [0, 0, 0, 0, 0, 0],
        [1 / 5, 0, 0, 0, 0, 0],
        [3 / 40, 9 / 40, 0, 0, 0, 0],
        [44 / 45, -56 / 15, 32 / 9, 0, 0, 0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0, 0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0],
    ])
    #: weights of the 5th-order solution (the 7th stage, f at the new point, has weight 0)
    B = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84])
    #: weights of the error estimate: the 4th-order weights minus the 5th-order ones, over all 7 stages
    E = np.array([-71 / 57600, 0, 71 / 16695, -71 / 1920, 17253 / 339200, -22 / 525, 1 / 40])
    #: the dense output: ``y(t_old + x h) = y_old + h sum_j (K.T @ P)[:, j] x**(j+1)`` (Shampine's quartic)
    P = np.array([
        [1, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
        [0, 0, 0, 0],
        [0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
        [0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
        [0, 127303824393 / 49829197408, -318862633887 / 49829197408, 701980252875 / 199316789632],
        [0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
        [0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
    ])

    def _error_norm(self, h, scale):
        error = np.dot(self.K.T, self.E)
        error *= h
        error /= scale
        return _rms(error)

    def _build_dense_output(self):
        return QuarticDenseOutput(self.t_old, self.t, self.y_old, np.dot(self.K.T, self.P))


class QuarticDenseOutput(DenseOutput):
    """The quartic interpolant of a Dormand-Prince 5(4) step ([2]_ of :class:`RK45`).

    ``y(t_old + x h) = y_old + h Q @ (x, x**2, x**3, x**4)``.  Called with an
    array of instants it makes, instant by instant, the same matrix-vector
    product as called with one (so each column is bit for bit what the call
    at that instant alone gives).

    Parameters
    ----------
    t_old, t : float
        The ends of the step.
    y_old : ndarray, shape (n,)
        The state at ``t_old``.
    Q : ndarray, shape (n, 4)
        The coefficients of the powers of ``x``, times ``1/h``.

    Attributes
    ----------
    h : float
        ``t - t_old``.
    order : int
        3: the powers of ``x`` are 1 .. order + 1.
    """

    def __init__(self, t_old, t, y_old, Q):
        super().__init__(t_old, t)
        self.h = t - t_old
        self.Q = Q
        self.order = Q.shape[1] - 1
        self.y_old = y_old

    def _call_impl(self, t):
        if t.ndim == 0:
            x = (float(t) - self.t_old) / self.h
            powers = [x]
            for _ in range(self.order):
                powers.append(powers[-1] * x)
            y = self.h * np.dot(self.Q, np.array(powers))
            y += self.y_old
            return y
        x = (t.astype(float) - self.t_old) / self.h
        powers = np.empty((len(x), self.order + 1))
        powers[:, 0] = x
        for j in range(1, self.order + 1):
            np.multiply(powers[:, j - 1], x, out=powers[:, j])
        # one matrix-vector product per instant (a stack), not one matrix product
        y = self.h * np.matmul(self.Q, powers[:, :, None])[:, :, 0]
        y += self.y_old
        return y.T


class DOP853(RungeKutta):
    """The Dormand-Prince 8(5,3) pair of Hairer and Wanner's DOP853, with its 7th-order dense output.

    Twelve stages and the derivative at the new point (FSAL); the step
    advances with the 8th-order solution, and the error estimate combines
    the embedded 5th- and 3rd-order ones as DOP853 does ([1]_, II.10;
    [2]_): with ``e5``, ``e3`` the two differences divided by the scale,
    ``err = |h| ||e5||^2 / sqrt(n (||e5||^2 + 0.01 ||e3||^2))``, taken as of
    order ``q = 7``.  The dense output of degree 7 costs three more
    evaluations of ``fun`` per step that asks for it (counted in ``nfev``).

    Parameters and attributes are those of :class:`RungeKutta`.

    References
    ----------
    .. [1] E. Hairer, S. P. Norsett and G. Wanner, "Solving Ordinary
           Differential Equations I: Nonstiff Problems", 2nd ed., Springer,
           1993, Sec. II.5, II.6, II.10.
    .. [2] E. Hairer and G. Wanner, ``dop853.f``, Fortran code of DOP853,
           https://www.unige.ch/~hairer/software.html.
    .. [3] P. J. Prince and J. R. Dormand, "High order embedded Runge-Kutta
           formulae", Journal of Computational and Applied Mathematics 7 (1),
           pp. 67-75, 1981.
    """

    order = 8
    error_estimator_order = 7
    n_stages = 12
    n_stored_stages = 16
    C = np.array(_DOP853_NODES[:12])
    A = _sparse_rows(_DOP853_ROWS[:12], 12)
    B = _sparse_rows(_DOP853_ROWS[12:13], 12)[0]
    #: the 8th-order weights minus the 5th-order ones, over the 13 stages
    E5 = _sparse_rows([_DOP853_ERR5], 13)[0]
    #: the 8th-order weights minus the 3rd-order ones, over the 13 stages
    E3 = np.append(B, 0.0)
    for _j, _bhh in _DOP853_BHH.items():
        E3[_j] -= _bhh
    del _j, _bhh
    #: the coefficients of the 4th to 7th terms of the dense output, over the 16 stages
    D = _sparse_rows(_DOP853_DENSE, 16)
    #: the three stages of the dense output: (s, c_s, a_s[:s]) for s = 13, 14, 15
    _extra_plan = tuple((s, _DOP853_NODES[s], np.array([_DOP853_ROWS[s].get(j, 0.0) for j in range(s)]))
                        for s in range(13, 16))

    def _error_norm(self, h, scale):
        K = self.K[:self.n_stages + 1]
        e5 = np.dot(K.T, self.E5) / scale
        e3 = np.dot(K.T, self.E3) / scale
        # the squared 2-norms, as the square of the 2-norm (the rounding of scipy's DOP853)
        s5 = math.sqrt(float(np.dot(e5, e5))) ** 2
        s3 = math.sqrt(float(np.dot(e3, e3))) ** 2
        if s5 == 0 and s3 == 0:
            return 0.0
        return abs(h) * s5 / math.sqrt((s5 + 0.01 * s3) * len(scale))

    def _build_dense_output(self):
        K = self.K
        h = self.h_previous
        t_old, y_old = self.t_old, self.y_old
        for s, c, a in self._extra_plan:
            K[s] = self.fun(t_old + c * h, y_old + np.dot(K[:s].T, a) * h)
        f_old = K[0]
        dy = self.y - y_old
        F = np.empty((7, self.n))
        F[0] = dy
        F[1] = h * f_old - dy
        F[2] = 2 * dy - h * (self.f + f_old)
        F[3:] = h * np.dot(self.D, K)
        return Dop853DenseOutput(t_old, self.t, y_old, F)


class Dop853DenseOutput(DenseOutput):
    """The interpolant of degree 7 of a DOP853 step ([1]_, II.6; ``CONTD8`` of [2]_ of :class:`DOP853`).

    With ``x = (t - t_old)/h`` and ``x1 = 1 - x``::

        y = y_old + x (F0 + x1 (F1 + x (F2 + x1 (F3 + x (F4 + x1 (F5 + x F6))))))

    evaluated element by element, so an array of instants gives, column by
    column, bit for bit what one instant gives.

    Parameters
    ----------
    t_old, t : float
        The ends of the step.
    y_old : ndarray, shape (n,)
        The state at ``t_old``.
    F : ndarray, shape (7, n)
        The coefficients ``F0 .. F6``.

    Attributes
    ----------
    h : float
        ``t - t_old``.
    """

    def __init__(self, t_old, t, y_old, F):
        super().__init__(t_old, t)
        self.h = t - t_old
        self.F = F
        self.y_old = y_old

    def _call_impl(self, t):
        if t.ndim == 0:
            x = (float(t) - self.t_old) / self.h
            F = self.F
            y_old = self.y_old
        else:
            x = ((t.astype(float) - self.t_old) / self.h)[None, :]
            F = self.F[:, :, None]
            y_old = self.y_old[:, None]
        x1 = 1 - x
        y = F[6] * x
        for k, factor in ((5, x1), (4, x), (3, x1), (2, x), (1, x1), (0, x)):
            y += F[k]
            y *= factor
        y += y_old
        return y
