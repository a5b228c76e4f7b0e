"""The ``acausal`` command line.

::

    acausal simulate examples/first.py --stop-time 2 --out first.csv --signals inertia3.w
    acausal compare  examples/first.py --plot plots/
    acausal explain  examples/first.py --out pictures/
    acausal check    examples/first.py
    acausal export   examples/first.py --modelica First.mo
    acausal simulate First.mo          (or Modelica.Mechanics.Rotational.Examples.First on MODELICAPATH)
    acausal show     library.blocks.Step
    acausal list     library.blocks

A model is named ``FILE.py`` (the one :class:`~acausal.Model` subclass the
file defines) or ``FILE.py:ClassName``; it is instantiated without
arguments.

Exit status: 0 on success; 1 when a simulation fails or a comparison does
not pass (or a result cannot be written after the run), a run stopped by
its budget (``--timeout``, ``--max-steps``) included; 2 for usage errors
(an output path that cannot be written is one, found before simulating) and
for models that cannot be loaded or translated (a model file that calls
``sys.exit()`` while imported is one); 130 when interrupted (Ctrl-C, SIGINT)
and 143 when terminated (SIGTERM, as ``timeout``, systemd, SLURM and CI
runners send): ``simulate`` still writes the result computed up to then;
141 when the reader of the output has gone (``acausal list | head -1``), as
for a program that SIGPIPE ends.

Files are written whole or not at all (:func:`acausal.fileio.atomic_write`):
a result that cannot be written leaves an earlier file of that name as it
was.
"""

from __future__ import annotations

import argparse
import gc
import importlib.util
import math
import os
import re
import signal
import sys
import threading
import time
import traceback
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

from ..errors import AcausalError, SolverError
from ..runtime.simulate import METHODS
from .collector import GC_THRESHOLD
from .modelfile import CommandError, load_model_class, reproducing_models

if TYPE_CHECKING:
    from ..language import Model

__all__ = ["main", "run", "load_model_class"]


#: Relative tolerance used by ``acausal compare`` unless given (or the experiment's is tighter).
COMPARE_RTOL = 1e-6


# Loading a model class from a file: acausal.tools.modelfile (check and catalog use it too)


def _instantiate(cls: type) -> Model:
    try:
        return cls()
    except AcausalError:
        raise
    except TypeError as exc:
        raise CommandError(f"cannot create {cls.__name__}() without arguments: {exc}") from exc
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - any failure of the user's __init__
        raise CommandError(f"cannot create {cls.__name__}(): {_describe_failure(exc, cls)}") from exc


def _model_code(cls: type, function, *args, **kwargs):
    """``function(*args, **kwargs)``, which runs the model's own code (``build()``, ``equations()``).

    An exception of that code that is not an acausal error becomes a one-line
    :class:`CommandError` (exit status 2) naming the class, the exception and
    where in the user's code it was raised; so does a ``sys.exit()`` there,
    which would otherwise end the command silently.
    """
    try:
        return function(*args, **kwargs)
    except AcausalError:
        raise
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - any failure of the user's model code
        if _user_frame(exc, cls) is None:
            raise  # not raised in the model's code: an internal error keeps its traceback
        raise CommandError(f"cannot translate {cls.__name__}: {_describe_failure(exc, cls)}") from exc


def _translate(model: Model, outputs=None, cache: bool = True, parameters=None):
    """``translate(model, outputs)``, with a failure of the model's own code as a CommandError."""
    from ..compiler.translate import translate

    return _model_code(type(model), translate, model, outputs, cache=cache, parameters=parameters)


def _parameters(pairs: Sequence[str], option: str = "--param") -> dict[str, float]:
    """``["a.b=1.5", ...]`` -> ``{"a.b": 1.5}`` (the values of ``option``, --param or --start)."""
    out = {}
    example = "component.parameter=2.5" if option == "--param" else "component.variable=3"
    for pair in pairs:
        name, sep, text = pair.partition("=")
        if not sep or not name.strip():
            raise CommandError(f"{option} {pair!r}: write NAME=VALUE, e.g. {example}")
        try:
            out[name.strip()] = float(text)
        except ValueError:
            raise CommandError(f"{option} {pair!r}: {text!r} is not a number") from None
    return out


def _describe_failure(exc: BaseException, cls: type) -> str:
    """``RuntimeError: boom (model.py:4, in build)``: on one line, with the user's frame."""
    text = " ".join(line.strip() for line in str(exc).splitlines() if line.strip())
    text = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    frame = _user_frame(exc, cls)
    if frame is not None:
        text += f" ({_show_path(frame.filename)}:{frame.lineno}, in {frame.name})"
    return text


def _user_frame(exc: BaseException, cls: type):
    """The innermost frame of ``exc`` in the file that defines ``cls``, else in any file
    that is neither acausal's nor Python's nor an installed package's (None if none)."""
    frames = traceback.extract_tb(exc.__traceback__)
    module_file = getattr(sys.modules.get(cls.__module__), "__file__", None)
    if module_file:
        own = [f for f in frames if _resolve(f.filename) == _resolve(module_file)]
        if own:
            return own[-1]
    system = [_resolve(p) for p in {sys.prefix, sys.base_prefix, sys.exec_prefix}]
    system += _engine_folders()
    for frame in reversed(frames):
        if frame.filename.startswith("<"):
            continue
        path = _resolve(frame.filename)
        if not any(path.is_relative_to(folder) for folder in system):
            return frame
    return None


def _engine_folders() -> list[Path]:
    """The folders of acausal and of the libraries installed with it."""
    folders = [Path(__file__).resolve().parents[1]]
    for name in ("acausal.library", "acausal.components"):
        try:
            spec = importlib.util.find_spec(name)
        except (ImportError, ValueError):
            continue
        if spec is not None and spec.submodule_search_locations:
            folders += [_resolve(p) for p in spec.submodule_search_locations]
    return folders


def _resolve(filename: str) -> Path:
    try:
        return Path(filename).resolve()
    except (OSError, RuntimeError):
        return Path(filename)


def _show_path(filename: str) -> str:
    """A file name relative to the current directory when it lies below it."""
    try:
        return str(_resolve(filename).relative_to(Path.cwd()))
    except (ValueError, OSError):
        return filename


# ---------------------------------------------------------------------------
# Output paths: checked before any work is done
# ---------------------------------------------------------------------------


def _unwritable(path: Path, folder: bool) -> str | None:
    """Why ``path`` (a file to write, or a folder to write into) cannot be written; None if it can.

    Nothing is created.  A missing folder is fine if the nearest existing
    one above it is a writable folder (the command creates the rest).
    """
    if path.exists():
        if folder:
            if not path.is_dir():
                return "it is not a directory"
            if not os.access(path, os.W_OK | os.X_OK):
                return "the directory is not writable"
        else:
            if path.is_dir():
                return "it is a directory"
            if not os.access(path, os.W_OK):
                return "the file is not writable"
        return None
    above = path.parent
    while not above.exists() and above.parent != above:
        above = above.parent
    if not above.exists():
        return f"{above} does not exist"
    if not above.is_dir():
        return f"{above} is not a directory"
    if not os.access(above, os.W_OK | os.X_OK):
        return f"the directory {above} is not writable"
    return None


def _check_writable(path: Path, what: str, folder: bool = False) -> None:
    """Raise a CommandError (exit status 2) if ``path`` cannot be written."""
    why = _unwritable(path, folder)
    if why is not None:
        raise CommandError(f"cannot write {what} {path}: {why}")


def _interrupted(result) -> bool:
    """True for a result whose run was stopped by Ctrl-C (status -2, message "interrupted ...").

    ``simulate()`` raises it attached to a KeyboardInterrupt, or returns it.
    """
    return getattr(result, "status", 0) == -2 or (
        not getattr(result, "success", True)
        and str(getattr(result, "message", "")).lower().startswith("interrupted"))


def _end_time(result) -> str:
    times = getattr(result, "time", ())
    return f"t = {float(times[-1]):.6g}" if len(times) else "the start"


def _spent_budget(result, args) -> str | None:
    """The option whose budget stopped the run, as given (``--max-steps 50``); None if none did.

    ``simulate()`` stops a run over budget with a SolverError whose message
    says which budget it used up ("... used its budget of 50 steps", "...
    used its time budget of 1 s").
    """
    if getattr(result, "success", True) or not isinstance(getattr(result, "error", None), SolverError):
        return None
    message = str(result.message)
    if args.max_steps is not None and f"its budget of {args.max_steps} steps" in message:
        return f"--max-steps {args.max_steps}"
    if args.timeout is not None and "its time budget" in message:
        return f"--timeout {args.timeout:g}"
    return None


# ---------------------------------------------------------------------------
# Signals: SIGTERM is Ctrl-C
# ---------------------------------------------------------------------------


class _Stop:
    """While a command runs, SIGTERM stops it as Ctrl-C does; remembers which of the two did.

    ``timeout``, systemd, SLURM and CI runners end a process with SIGTERM,
    whose default action kills it on the spot: a run's partial result would
    be lost.  Inside this context SIGTERM raises :class:`KeyboardInterrupt`
    (as SIGINT does), so that the commands keep what was computed on the
    path they take for Ctrl-C; :meth:`status` then turns their 130 into 143
    (128 + SIGTERM).  The handler is installed only in the main thread and
    only over the default action (a handler of an embedding program, or
    SIGTERM ignored by the parent, stays), and the earlier one is restored
    on leaving.
    """

    def __init__(self) -> None:
        self.terminated = False
        self._previous = None

    def __enter__(self) -> "_Stop":
        if (threading.current_thread() is threading.main_thread()
                and signal.getsignal(signal.SIGTERM) == signal.SIG_DFL):
            self._previous = signal.signal(signal.SIGTERM, self._handle)
        return self

    def __exit__(self, *exc_info) -> None:
        if self._previous is not None:
            signal.signal(signal.SIGTERM, self._previous)
            self._previous = None

    def _handle(self, signum, frame) -> None:
        self.terminated = True
        raise KeyboardInterrupt

    @property
    def word(self) -> str:
        """How the messages say the command was stopped."""
        return "terminated (SIGTERM)" if self.terminated else "interrupted"

    def status(self, status: int) -> int:
        """The exit status: 143 instead of 130 when SIGTERM stopped the command."""
        return 143 if status == 130 and self.terminated else status


def _stopped(args) -> str:
    """``interrupted`` (Ctrl-C) or ``terminated (SIGTERM)``, for the messages of a command."""
    stop = getattr(args, "stop", None)
    return stop.word if stop is not None else "interrupted"


# ---------------------------------------------------------------------------
# Argument parsing
# ---------------------------------------------------------------------------


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (value > 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be a positive number, not {text}")
    return value


def _finite_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, not {text}")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {text}")
    return value


def _add_budgets(command: argparse.ArgumentParser, each: str) -> None:
    """``--timeout`` and ``--max-steps``, passed to ``simulate()``."""
    command.add_argument("--timeout", type=_positive_float, metavar="SECONDS",
                         help=f"stop {each} after this many seconds of wall-clock time (the "
                              f"translation before it not counted); it fails, status 1")
    command.add_argument("--max-steps", type=_positive_int, metavar="N",
                         help=f"stop {each} after N integrator steps; it fails, status 1")


def _method(text: str) -> str:
    for name in METHODS:
        if text.lower() == name.lower():
            return name
    raise argparse.ArgumentTypeError(f"unknown method {text!r}; choose one of {', '.join(METHODS)}")


#: The commands ``_parser`` declares with their options (the others parse their own arguments).
_PARSED_COMMANDS = ("simulate", "compare", "explain", "export")


def _parser(command: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser; with ``command`` (one of :data:`_PARSED_COMMANDS`) only that
    command's options are declared: a warm ``acausal simulate`` spends ~5 ms declaring the
    others (argparse looks up a translation of every help text), which only
    ``acausal --help`` shows."""
    from .. import __version__

    parser = argparse.ArgumentParser(
        prog="acausal",
        description="Simulate, compare and explain acausal models (Modelica-like, in Python).",
        epilog="MODEL is FILE.py (the one Model subclass the file defines) or FILE.py:ClassName.")
    parser.add_argument("--version", action="version", version=f"acausal {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    if command in (None, "simulate"):
        sim = commands.add_parser("simulate", help="simulate a model and write a CSV result",
                                  description="Simulate a model and write its result as CSV "
                                              "(time first, then every variable by dotted name).")
        sim.add_argument("model", metavar="MODEL", help="FILE.py or FILE.py:ClassName")
        sim.add_argument("--start-time", type=_finite_float, metavar="T",
                         help="default: the model's experiment")
        sim.add_argument("--stop-time", type=_finite_float, metavar="T",
                         help="default: the model's experiment")
        sim.add_argument("--interval", type=_positive_float, metavar="DT",
                         help="output interval; default: the model's experiment or 500 points")
        sim.add_argument("--method", type=_method, default=None, metavar="M",
                         help=f"integration method: {', '.join(METHODS)} (default: the model's experiment "
                              f"method, else RK45)")
        sim.add_argument("--rtol", type=_positive_float, metavar="R",
                         help="relative tolerance; default: the experiment's or 1e-6")
        sim.add_argument("--atol", type=_positive_float, metavar="A",
                         help="absolute tolerance; default: rtol times each state's nominal value")
        sim.add_argument("--out", metavar="FILE.csv", help="CSV file to write; default: <Model>.csv")
        sim.add_argument("--signals", metavar="a,b,...",
                         help="comma-separated variables to write; default: all")
        sim.add_argument("--display-unit", metavar="NAME=UNIT", action="append", default=[],
                         help="print NAME's final value in UNIT (repeatable), e.g. J1.w=rpm, T=degC, p=bar; "
                              "the CSV stays in the declared units")
        sim.add_argument("--param", metavar="NAME=VALUE", action="append", default=[],
                         help="a parameter's value for this run (repeatable), e.g. component.parameter=2.5; "
                              "a numeric one reuses the compiled systems, a structural one translates anew")
        sim.add_argument("--start", metavar="NAME=VALUE", action="append", default=[],
                         help="a variable's start value for this run (repeatable), e.g. J1.w=3; those of "
                              "states and fixed variables reuse the compiled systems")
        _add_budgets(sim, "the run (the CSV holds what it computed)")
        sim.add_argument("--no-disk-cache", action="store_true",
                         help="compile everything: neither load nor store compiled systems on disk "
                              "(as ACAUSAL_DISK_CACHE=off)")
        sim.set_defaults(run=_cmd_simulate)

    if command in (None, "compare"):
        cmp_ = commands.add_parser("compare", help="tube-test a model against the MSL reference results",
                                   description="Simulate a model with its experiment settings and "
                                               "tube-test every signal of the reference's "
                                               "comparisonSignals.txt (csv-compare's test).")
        cmp_.add_argument("models", metavar="MODEL", nargs="+",
                          help="FILE.py or FILE.py:ClassName (with modelica_class), or a folder (every such "
                               "model in its .py files); several may be given")
        cmp_.add_argument("--reference-dir", metavar="DIR",
                          help="folder of reference results (default: ACAUSAL_REFERENCE_DIR, else "
                               "the references bundled with acausal for its examples)")
        cmp_.add_argument("--plot", metavar="DIR",
                          help="write one PNG per model into DIR: a panel per compared signal, with the tube")
        cmp_.add_argument("--plot-per-signal", action="store_true",
                          help="with --plot, also write one PNG per compared signal")
        cmp_.add_argument("--method", type=_method, default=None, metavar="M",
                          help=f"integration method: {', '.join(METHODS)} (default: the model's experiment "
                               f"method, else RK45)")
        cmp_.add_argument("--rtol", type=_positive_float, metavar="R",
                          help=f"relative tolerance (default {COMPARE_RTOL:g}, or the experiment's "
                               f"if tighter)")
        _add_budgets(cmp_, "each model's run")
        cmp_.add_argument("-v", "--verbose", action="store_true",
                          help="with several models, also print each model's run summary and per-signal "
                               "table (without: a row per model in one table, the legend once)")
        cmp_.add_argument("--no-disk-cache", action="store_true",
                          help="compile everything: neither load nor store compiled systems on disk "
                               "(as ACAUSAL_DISK_CACHE=off)")
        cmp_.set_defaults(run=_cmd_compare)

    if command in (None, "explain"):
        exp = commands.add_parser("explain", help="show how the model is translated, stage by stage",
                                  description="Print what each translation stage does to the model "
                                              "and draw the incidence matrix in BLT order.")
        exp.add_argument("model", metavar="MODEL", help="FILE.py or FILE.py:ClassName")
        exp.add_argument("--out", metavar="DIR", help="folder for the pictures (default: current directory)")
        exp.add_argument("--html", metavar="DIR",
                         help="write a self-contained teaching page DIR/index.html (simulates the model for "
                              "its discrete states and events)")
        exp.set_defaults(run=_cmd_explain)

    if command in (None, "export"):
        export = commands.add_parser("export", help="write a model as Modelica text",
                                     description="Write the model as one Modelica model: library components "
                                                 "as their MSL classes with their modifiers, the model's own "
                                                 "classes with their equations, connects and the experiment.")
        export.add_argument("model", metavar="MODEL", help="FILE.py[:ClassName] (or FILE.mo[:Class])")
        export.add_argument("--modelica", metavar="OUT.mo", required=True,
                            help="the Modelica file to write ('-': standard output)")
        export.set_defaults(run=_cmd_export)

    if command is not None:
        return parser
    commands.add_parser("bench", help="work-precision benchmark (acausal bench --help)", add_help=False)
    commands.add_parser("show", help="a component's parameters, connectors and variables "
                                     "(acausal show Class, PACKAGE.Class, its Modelica name or "
                                     "FILE.py:Class)", add_help=False)
    commands.add_parser("list", help="the components of a package (acausal list PACKAGE)",
                        add_help=False)
    commands.add_parser("check", help="structural and unit checks without simulating (acausal check "
                                      "MODEL [--strict])", add_help=False)
    commands.add_parser("sweep", help="a parameter sweep on a process pool or a Dask cluster "
                                      "(acausal sweep --help)", add_help=False)
    return parser


# ---------------------------------------------------------------------------
# Commands
# ---------------------------------------------------------------------------


def _simulate(model, keep: list | None = None, **options):
    """Simulate after checking the times, which ``simulate`` would reject with a ValueError
    (``keep``: a list the translation and then the notes printed of it are appended to)."""
    from ..language import Experiment
    from ..runtime.simulate import simulate

    _check_times(getattr(model, "experiment", None) or Experiment(), options)
    # translated here, so that a failure of the model's own code is a model error (status 2)
    from ..compiler.translate import with_start_values

    parameters = with_start_values(options.pop("parameters", None), options.pop("start", None))
    translating = time.perf_counter()
    translation = _translate(model, options.pop("outputs", None), parameters=parameters)
    translating = time.perf_counter() - translating
    if keep is not None:
        keep.append(translation)
    from ..runtime.simulate import _structural_notes

    notes = _structural_notes(translation, parameters)
    for note in notes:
        print(f"note: {note}", file=sys.stderr)
    if keep is not None:
        keep.append(notes)
    try:
        result = simulate(translation, **options)
    except KeyboardInterrupt as exc:  # it may carry the partial result
        _count_translation(getattr(exc, "result", None), translating)
        raise
    _count_translation(result, translating)
    return result


def _count_translation(result, seconds: float) -> None:
    """Add the translation done before ``simulate()`` to the result's ``translate_seconds``."""
    stats = getattr(result, "stats", None)
    if isinstance(stats, dict) and "translate_seconds" in stats:
        stats["translate_seconds"] += seconds  # as if simulate() had translated the model


def _cmd_simulate(args) -> int:
    if args.out:
        _check_writable(Path(args.out), "--out")
    warm = _warm_simulate(args) if _warm_eligible(args) else None
    if warm is not None:
        return warm
    modules_before = set(sys.modules)
    cls = load_model_class(args.model)
    out = Path(args.out) if args.out else Path(f"{cls.__name__}.csv")
    if not args.out:
        _check_writable(out, "the result")
    model = _instantiate(cls)
    signals = None
    if args.signals is not None:
        signals = [s.strip() for s in args.signals.split(",") if s.strip()]
        if not signals:
            raise CommandError("--signals names no variable")
    display = _display_unit_pairs(args.display_unit)
    if signals is not None or display:
        from ..compiler.flatten import flatten

        flat = _model_code(cls, flatten, model)
        known = {v.name for v in flat.variables}
        if display:
            _check_display_units(display, flat, signals, cls.__name__)
        missing = [s for s in signals or () if s not in known]
        if missing:
            result = None
            import difflib

            hints = []
            for m in missing:
                close = difflib.get_close_matches(m, sorted(known), n=3)
                hints.append(f"{m}" + (f" (did you mean {', '.join(close)}?)" if close else ""))
            raise CommandError(f"not a variable of {cls.__name__}: {'; '.join(hints)}")
    # with --signals only what those signals need is computed (effects on demand)
    kept: list = []
    result = _run_keeping_partial(lambda: _simulate(
        _instantiate(cls), keep=kept, start_time=args.start_time, stop_time=args.stop_time, interval=args.interval,
        method=args.method, rtol=args.rtol, atol=args.atol, outputs=signals,
        parameters=_parameters(args.param) or None, start=_parameters(args.start, "--start") or None,
        max_steps=args.max_steps, timeout=args.timeout), args)
    if result is None:
        return 130
    if result.success and kept and _warm_eligible(args):
        _save_run(args.model, cls, kept[0], modules_before, _run_variant(args), kept[1])
    return _write_simulation(args, result, out, cls.__name__, signals, display)


def _write_simulation(args, result, out: Path, name: str, signals, display) -> int:
    """Write the result of ``acausal simulate`` and print its summary; the exit status."""
    earlier = out.exists()
    try:
        if out.parent != Path(""):
            out.parent.mkdir(parents=True, exist_ok=True)
        result.to_csv(out, signals)  # whole or not at all: a failure keeps the earlier file
    except OSError as exc:
        print(result.summary(signals, units=display))
        kept = f" ({out} is as it was before)" if earlier and out.is_file() else ""
        print(f"acausal simulate: error: cannot write {out}: {exc.strerror or exc}; "
              f"the result was not saved{kept}", file=sys.stderr)
        return 1
    print(result.summary(signals, units=display))
    print(f"wrote {out}")
    if _interrupted(result):
        print(f"acausal simulate: {_stopped(args)} at {_end_time(result)}; {out} holds the result "
              f"up to then", file=sys.stderr)
        return 130
    budget = _spent_budget(result, args)
    if budget is not None:
        print(f"error: {budget} stopped the simulation of {name} at {_end_time(result)}: "
              f"{result.message}\n  ({out} holds the result up to then)", file=sys.stderr)
        return 1
    if not result.success:
        print(f"error: the simulation of {name} failed: {result.message}\n"
              f"  (the CSV holds the result up to the failure)", file=sys.stderr)
        return 1
    return 0


# -- the warm command: a run saved whole, run without the compiler (acausal.compiler.saved) --------

#: The entry of a saved run in the persistent cache (under the key of its command, :func:`_run_key`).
_SAVED_RUN = "saved run"


def _warm_eligible(args) -> bool:
    """Whether this ``acausal simulate`` may load a saved run or save one: a run of every
    variable (no --signals, --display-unit) with the persistent cache on.  Runs with
    ``--param``/``--start`` are saved apart, one per set of those options (:func:`_run_variant`)."""
    from ..compiler.diskcache import disk_cache_enabled

    return (args.signals is None and not args.display_unit
            and not args.no_disk_cache and disk_cache_enabled())


def _run_variant(args) -> tuple[str, ...]:
    """The options of ``acausal simulate`` its translation depends on, as given
    (``--param``/``--start``): part of the key of its saved run."""
    return (*(f"--param {p}" for p in args.param or ()), *(f"--start {s}" for s in args.start or ()))


def _run_key(spec: str, variant: tuple[str, ...] = ()) -> str:
    """The key of a saved run: the model file's resolved path, the class asked for and the
    options the translation depends on (what the file and the modules it imported hold is
    checked against their digests on load; the engine's version is part of every entry of
    the cache)."""
    import hashlib

    filename, _, name = spec.partition(":")
    text = f"acausal saved run 1\n{sys.version}\n{Path(filename).resolve()}\n{name}\n" + "\n".join(variant)
    return hashlib.sha256(text.encode()).hexdigest()


def _digest(path: str) -> str | None:
    import hashlib

    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return None


def _load_saved(spec: str, variant: tuple[str, ...] = ()):
    """``(class name, its modelica_class, LoadedModel, notes)`` of the saved run of the model
    ``spec`` names (with the options ``variant``), or None when there is none, or the model's
    file or a module it imports has changed."""
    import base64
    import pickle

    from ..compiler.diskcache import DiskCache, cache_folder
    from ..compiler.saved import LoadedModel

    payload = DiskCache(cache_folder(), _run_key(spec, variant)).load(_SAVED_RUN)
    if payload is None or any(_digest(path) != digest for path, digest in payload["deps"]):
        return None
    # authenticated by the cache (an HMAC under the user's own key): trusted as its code is
    saved = pickle.loads(base64.b64decode(payload["model"]))

    def translate_model():
        # a discrete state the saved run did not visit: the model, translated as a cold command
        # does (with the values of its --param/--start options)
        from ..compiler.translate import with_start_values

        given = {option: [v.split(" ", 1)[1] for v in variant if v.startswith(option + " ")]
                 for option in ("--param", "--start")}
        parameters = with_start_values(_parameters(given["--param"]) or None,
                                       _parameters(given["--start"], "--start") or None)
        return _translate(_instantiate(load_model_class(spec)), parameters=parameters)

    return (payload["class"], payload.get("modelica_class"), LoadedModel(saved, translate_model),
            tuple(payload.get("notes", ())))


def _check_times(experiment, options: dict) -> None:
    """The start and stop times of a run (``options`` over the ``experiment``), checked
    before anything runs: ``simulate`` would reject them with a ValueError."""
    start = experiment.start_time if options.get("start_time") is None else options["start_time"]
    stop = experiment.stop_time if options.get("stop_time") is None else options["stop_time"]
    if not stop > start:
        raise CommandError(f"the stop time ({stop:g}) must be after the start time ({start:g})")


def _simulate_loaded(loaded, **options):
    """:func:`_simulate` for a saved run: the times checked, then the runtime alone."""
    from ..runtime.simulate import simulate

    _check_times(loaded.data.experiment, options)
    return simulate(loaded, **options)


def _run_keeping_partial(run: Callable[[], object], args):
    """``run()``; on Ctrl-C or SIGTERM the result ``simulate()`` attached to the interrupt,
    or None (said on standard error: nothing computed, nothing written)."""
    try:
        return run()
    except KeyboardInterrupt as exc:
        result = getattr(exc, "result", None)
        if result is None:
            print(f"acausal simulate: {_stopped(args)}; nothing written", file=sys.stderr)
        return result


def _warm_simulate(args) -> int | None:
    """Run a saved run of this command's model without the compiler (the exit status), or None
    when there is none, or the model's file or a module it imports has changed since."""
    found = _load_saved(args.model, _run_variant(args))
    if found is None:
        return None
    name, _modelica_class, loaded, notes = found
    for note in notes:  # what the cold command said of the translation (structural parameters)
        print(f"note: {note}", file=sys.stderr)
    out = Path(args.out) if args.out else Path(f"{name}.csv")
    if not args.out:
        _check_writable(out, "the result")
    result = _run_keeping_partial(lambda: _simulate_loaded(
        loaded, start_time=args.start_time, stop_time=args.stop_time, interval=args.interval, method=args.method,
        rtol=args.rtol, atol=args.atol, max_steps=args.max_steps, timeout=args.timeout), args)
    if result is None:
        return 130
    return _write_simulation(args, result, out, name, None, {})


def _save_run(spec: str, cls: type, translation, modules_before: set, variant: tuple[str, ...] = (),
              notes: Sequence[str] = ()) -> None:
    """Save the run of ``translation`` for the next ``acausal simulate`` of the same model
    (:meth:`~acausal.compiler.persist.PersistentSystems.saved`), with the digests of the model's
    file and of every module it imported outside acausal (acausal's own files are the
    engine's version)."""
    import base64
    import pickle

    from ..compiler.diskcache import DiskCache, cache_folder

    saved = translation.saved()
    if isinstance(saved, str):
        return  # the model needs the compiler at run time: every command translates it
    package = Path(__file__).resolve().parents[1]
    outside = {Path(p).resolve() for p in {sys.prefix, sys.base_prefix, sys.exec_prefix}}
    deps = []
    for module in sorted(set(sys.modules) - modules_before):
        filename = getattr(sys.modules.get(module), "__file__", None)
        if not filename:
            continue
        path = Path(filename).resolve()
        if package in path.parents or any(root in path.parents for root in outside):
            continue
        digest = _digest(str(path))
        if digest is None:
            return
        deps.append([str(path), digest])
    DiskCache(cache_folder(), _run_key(spec, variant)).store(_SAVED_RUN, {
        "class": cls.__name__, "modelica_class": getattr(cls, "modelica_class", None), "deps": deps,
        "notes": list(notes), "model": base64.b64encode(pickle.dumps(saved)).decode()})


def _display_unit_pairs(pairs: Sequence[str]) -> dict[str, str]:
    """``["J1.w=rpm", ...]`` -> ``{"J1.w": "rpm"}`` (the names and units are checked later)."""
    out = {}
    for pair in pairs:
        name, sep, unit = pair.partition("=")
        if not sep or not name.strip() or not unit.strip():
            raise CommandError(f"--display-unit {pair!r}: write NAME=UNIT, e.g. J1.w=rpm or T=degC")
        out[name.strip()] = unit.strip()
    return out


def _check_display_units(display: dict[str, str], flat, signals, model: str) -> None:
    """Each ``--display-unit`` names a Real variable or parameter (among ``--signals`` if given)
    whose unit converts to the one given: checked before the run, a CommandError (status 2) if not."""
    import difflib

    from ..runtime.result import convert_unit

    declared = {v.name: v.unit for v in flat.variables if not v.is_discrete}
    declared.update((p.name, p.unit) for p in flat.parameters)
    for name, unit in display.items():
        option = f"--display-unit {name}={unit}"
        if name not in declared:
            close = difflib.get_close_matches(name, sorted(declared), n=3)
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            raise CommandError(f"{option}: {name} is not a Real variable or parameter of {model}{hint}")
        if signals is not None and name not in signals:
            raise CommandError(f"{option}: {name} is not among --signals (the result holds only those)")
        try:
            convert_unit(1.0, declared[name], unit, name=name)
        except ValueError as exc:
            raise CommandError(f"{option}: {exc}") from None


def _reproduced(model: str, saved: dict | None = None) -> list[str]:
    """The FILE.py:Model specs ``model`` (a folder, a file or FILE.py:Model) stands for.

    A file with a saved run (:func:`_load_saved`, kept in ``saved`` by spec) defines
    one model: it stands for itself, and the file is not executed to find out."""
    path = Path(model)
    if path.is_dir():
        return reproducing_models(model)
    if path.is_file() and path.suffix == ".py":
        from ..compiler.diskcache import disk_cache_enabled

        found = _load_saved(model) if saved is not None and disk_cache_enabled() else None
        if found is not None:
            saved[model] = found
            return [model]
        specs = reproducing_models(model)
        if len(specs) > 1:
            return specs
    return [model]


def _cmd_compare(args) -> int:
    if args.plot:
        _check_writable(Path(args.plot), "the plots into", folder=True)
    # a folder stands for every model in it that names the Modelica class it reproduces, and
    # so does a file that defines several models
    saved: dict = {}  # spec -> the saved run found for it (see _load_saved)
    args.models = [spec for model in args.models for spec in _reproduced(model, saved)]
    args.saved_runs = saved
    statuses = []
    # several models: a row per model in one table and the legend once (--verbose: each model's
    # run summary and per-signal table too, the table of models at the end)
    report = None
    if len(args.models) > 1:
        from .compare import ComparisonReport, ModelOutcome

        report = ComparisonReport(args.models)
        if not args.verbose:
            print(report.header(), flush=True)
    for number, model in enumerate(args.models, 1):
        if report is not None:
            report.start(model)
            if args.verbose:
                print(f"== [{number}/{len(args.models)}] {model}", flush=True)
        try:
            statuses.append(_compare_one(args, model, len(args.models) > 1, report))
        except (CommandError, AcausalError) as exc:
            if len(args.models) == 1:
                raise
            # one model that cannot be compared does not stop the others
            kind = "" if isinstance(exc, CommandError) else f"{type(exc).__name__}: "
            print(f"acausal compare: error: {kind}{exc}", file=sys.stderr)
            statuses.append(2 if isinstance(exc, (CommandError, ValueError)) else 1)
            report.add(ModelOutcome(model, result="error", note=f"{kind}{exc}"))
        except KeyboardInterrupt:
            print(f"acausal compare: {_stopped(args)} while comparing {model}", file=sys.stderr)
            statuses.append(130)
            if report is not None:
                report.add(ModelOutcome(model, result="interrupted", note=_stopped(args)))
        if report is not None and not args.verbose:
            print(report.row(), flush=True)
        if statuses[-1] == 130:
            break
    if report is not None:
        if args.verbose:
            print(report.table())
        print(report.legend(signals=args.verbose))
    if len(args.models) > 1:
        passed = sum(s == 0 for s in statuses)
        left = len(args.models) - len(statuses)
        print(f"== {passed} of {len(args.models)} models match their reference results"
              + (f" ({_stopped(args)}; {left} not compared)" if left else ""))
    return 130 if 130 in statuses else max(statuses)


def _compare_one(args, model_spec: str, several: bool, report=None) -> int:
    """Compare one model; with several models, add its row to ``report`` (a ComparisonReport)
    and print its run summary and per-signal table only with ``--verbose``."""
    from .compare import ModelOutcome, compare_signals, load_reference, plot_comparison, signal_info

    # a saved run of the model (see _warm_simulate), else the model translated
    from ..compiler.diskcache import disk_cache_enabled

    found = getattr(args, "saved_runs", {}).pop(model_spec, None)
    if found is None and disk_cache_enabled():
        found = _load_saved(model_spec)
    kept: list = []
    if found is not None:
        name, modelica_class, loaded, _notes = found  # a model as declared: no notes
        experiment, described = loaded.data.experiment, loaded.data
    else:
        modules_before = set(sys.modules)
        cls = load_model_class(model_spec)
        name, modelica_class = cls.__name__, getattr(cls, "modelica_class", None)
        experiment, described = getattr(cls, "experiment", None), None
    if not modelica_class:
        raise CommandError(f"{name} has no modelica_class: nothing to compare with "
                           f"(set modelica_class = 'Modelica.…' on the class)")
    reference = load_reference(modelica_class, args.reference_dir)
    rtol = args.rtol
    if rtol is None:
        tolerance = getattr(experiment, "tolerance", None)
        rtol = min(COMPARE_RTOL, tolerance) if tolerance else COMPARE_RTOL
    try:
        if found is not None:
            result = _simulate_loaded(loaded, method=args.method, rtol=rtol, max_steps=args.max_steps,
                                      timeout=args.timeout)
        else:
            model = _instantiate(cls)
            described = model
            result = _simulate(model, keep=kept, method=args.method, rtol=rtol, max_steps=args.max_steps,
                               timeout=args.timeout)
            if result.success and kept and disk_cache_enabled():
                _save_run(model_spec, cls, kept[0], modules_before)
    except KeyboardInterrupt as exc:
        result = getattr(exc, "result", None)  # Ctrl-C or SIGTERM, perhaps with the result until then
        if result is None:
            raise
    tables = not several or args.verbose
    if tables:
        print(result.summary(values=False))
    if _interrupted(result):
        print(f"error: the simulation of {name} was {_stopped(args)} at {_end_time(result)}; "
              f"not compared", file=sys.stderr)
        if report is not None:
            report.add(ModelOutcome(model_spec, result="interrupted",
                                    note=f"{_stopped(args)} at {_end_time(result)}"))
        return 130
    info = signal_info(described, reference.compared)  # units, kinds and value names of the signals
    comparison = compare_signals(reference, result.time, result.columns, info=info)
    if tables:
        print(comparison.table(legend=not several))  # several models: the legend once, at the end
    plotted = True
    if args.plot:
        folder = Path(args.plot) / name if several else Path(args.plot)
        try:
            folder.mkdir(parents=True, exist_ok=True)
            for path in plot_comparison(reference, result.time, result.columns,
                                        folder / f"{_file_safe(name)}.png", info=info,
                                        per_signal=args.plot_per_signal):
                print(f"wrote {path}")
        except BrokenPipeError:
            raise  # the reader of the output has gone (see run()), not a plot that failed
        except OSError as exc:
            print(f"error: cannot write the plots into {folder}: {exc.strerror or exc}",
                  file=sys.stderr)
            plotted = False
    ok = comparison.passed and result.success and plotted
    budget = _spent_budget(result, args)
    if budget is not None:
        print(f"error: {budget} stopped the simulation of {name} at {_end_time(result)}: "
              f"{result.message}", file=sys.stderr)
    elif not result.success:
        print(f"error: the simulation of {name} failed: {result.message}", file=sys.stderr)
    elif not comparison.passed:
        failed = ", ".join(s.name for s in comparison.failures)
        print(f"error: {len(comparison.failures)} of {len(comparison.signals)} signals of "
              f"{name} outside the tube: {failed}", file=sys.stderr)
    if report is not None:
        stopped = budget or (result.message if not result.success else "")
        report.add(ModelOutcome(
            model_spec, comparison,
            "run failed" if not result.success else "FAIL" if not comparison.passed else
            "error" if not plotted else "pass",
            f"stopped: {stopped}" if stopped else "" if plotted else "the plots were not written"))
    return 0 if ok else 1


def _cmd_explain(args) -> int:
    from .explain import explain

    if args.out:
        _check_writable(Path(args.out), "the pictures into", folder=True)
    if args.html:
        _check_writable(Path(args.html), "the page into", folder=True)
    cls = load_model_class(args.model)
    model = _instantiate(cls)
    out = Path(args.out) if args.out else Path.cwd()
    # with --html alone the page holds the pictures: no PNG files unless --out asks for them
    pictures = bool(args.out) or not args.html
    if pictures and not args.out:
        _check_writable(out, "the pictures into", folder=True)
    translation = _translate(model, cache=False)
    try:
        explanation = explain(translation, out_dir=out, html=args.html, pictures=pictures)
    except OSError as exc:
        print(f"acausal explain: error: cannot write into {exc.filename or out}: "
              f"{exc.strerror or exc}", file=sys.stderr)
        return 1
    print(explanation.text, end="")
    print()
    for path in explanation.pictures:
        print(f"wrote {path}")
    if explanation.page:
        print(f"wrote {explanation.page}")
    return 0


def _cmd_export(args) -> int:
    from ..fileio import atomic_write
    from ..modelica import dump

    out = None if args.modelica == "-" else Path(args.modelica)
    if out is not None:
        _check_writable(out, "the Modelica file")
    model = _instantiate(load_model_class(args.model))
    text = dump(model)
    if out is None:
        print(text, end="")
        return 0
    atomic_write(out, lambda handle: handle.write(text), encoding="utf-8")
    print(f"wrote {out}")
    return 0


def _file_safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name)


# ---------------------------------------------------------------------------
# Entry point
# ---------------------------------------------------------------------------


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        0 success; 1 failed simulation or comparison; 2 usage or model error;
        130 interrupted (Ctrl-C); 143 terminated (SIGTERM).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "sweep":
        # its process pool and Dask cluster have their own handling of signals (acausal.tools.sweep)
        from .sweep import main_sweep

        return main_sweep(argv[1:])
    with _Stop() as stop:
        try:
            status = _command(argv, stop)
        except KeyboardInterrupt:
            # Ctrl-C or SIGTERM where the command does not catch it (bench, show, list, check)
            print(f"acausal {argv[0]}: {stop.word}" if argv else f"acausal: {stop.word}",
                  file=sys.stderr)
            status = 130
    return stop.status(status)


def _command(argv: list[str], stop: _Stop) -> int:
    """Run the command ``argv`` names; returns the exit status (130 when interrupted)."""
    if argv and argv[0] == "bench":
        from .bench import main as bench_main

        return bench_main(argv[1:])
    if argv and argv[0] in ("show", "list"):
        from . import catalog

        return (catalog.main_show if argv[0] == "show" else catalog.main_list)(argv[1:])
    if argv and argv[0] == "check":
        from .check import main_check

        return main_check(argv[1:])
    parser = _parser(argv[0] if argv and argv[0] in _PARSED_COMMANDS else None)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help, --version or a usage error
        return exc.code if isinstance(exc.code, int) else 2
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    args.stop = stop  # how the messages say the command was stopped
    disk_cache = os.environ.get("ACAUSAL_DISK_CACHE")
    if getattr(args, "no_disk_cache", False):
        os.environ["ACAUSAL_DISK_CACHE"] = "off"
    try:
        return args.run(args)
    except CommandError as exc:
        print(f"acausal {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except AcausalError as exc:
        print(f"acausal {args.command}: error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 2 if isinstance(exc, ValueError) else 1
    except KeyboardInterrupt:
        print(f"acausal {args.command}: {stop.word}", file=sys.stderr)
        return 130
    finally:
        if disk_cache is None:
            os.environ.pop("ACAUSAL_DISK_CACHE", None)
        else:
            os.environ["ACAUSAL_DISK_CACHE"] = disk_cache


def run() -> None:
    """Entry point of the ``acausal`` script and of ``python -m acausal``.

    A command is one short process whose sympy expressions and compiled
    systems live until it ends, so the cyclic garbage collector finds little
    to free: it runs less often here (as mypy does).  At exit one collection
    finalizes the garbage there is (a model file's objects included), and
    what is left is frozen, so that the interpreter's teardown does not
    traverse it all again.  Together that is about 0.1 s of a one-second
    command.  :func:`main` itself leaves the collector alone, for callers in a
    long-running process.
    """
    gc.set_threshold(*GC_THRESHOLD)
    try:
        try:
            status = main()
        finally:
            sys.stdout.flush()
    except BrokenPipeError:
        status = _reader_gone()
    finally:
        gc.collect()
        gc.freeze()
    sys.exit(status)


#: The exit status when the reader of the output has gone: 128 + SIGPIPE, what a shell reports
#: for ``cat``, ``grep`` or ``seq`` ended by SIGPIPE in ``... | head -1``.
CLOSED_PIPE_STATUS = 141


def _reader_gone() -> int:
    """End quietly when the reader of standard output has closed it (``acausal list | head -1``).

    Python ignores SIGPIPE, so a write to a closed pipe raises BrokenPipeError
    instead of ending the process as it ends ``cat``.  Restoring SIGPIPE's
    default action would kill the process in any write to a pipe or socket,
    the sweep's workers included, so the error is caught here instead: the
    output still buffered is sent to ``os.devnull`` (flushing it at exit would
    raise again, with a message), and the status is the one a shell reports for
    a program SIGPIPE ended.  Without ``set -o pipefail`` a pipeline's status
    is the last program's; with it, an output cut short shows, as for ``cat``.
    Whatever the command wrote to files (``simulate --out``) is written:
    commands print their summary after writing.
    """
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    finally:
        os.close(devnull)
    return CLOSED_PIPE_STATUS


if __name__ == "__main__":  # pragma: no cover
    run()
