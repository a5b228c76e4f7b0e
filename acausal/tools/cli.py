"""The ``acausal`` command line.

::

    acausal simulate examples/first.py --stop-time 2 --out first.csv --signals inertia3.w
    acausal compare  examples/first.py --plot plots/
    acausal explain  examples/first.py --out pictures/

A model is named ``FILE.py`` (the one :class:`~acausal.Model` subclass the
file defines) or ``FILE.py:ClassName``; it is instantiated without
arguments.

Exit status: 0 on success; 1 when a simulation fails or a comparison does
not pass; 2 for usage errors and for models that cannot be loaded or
translated.
"""

from __future__ import annotations

import argparse
import gc
import importlib.util
import math
import re
import sys
import traceback
from pathlib import Path
from typing import Sequence

from ..errors import AcausalError
from ..language import Model
from ..runtime.simulate import METHODS
from .collector import GC_THRESHOLD

__all__ = ["main", "run", "load_model_class"]


#: Relative tolerance used by ``acausal compare`` unless given (or the experiment's is tighter).
COMPARE_RTOL = 1e-6


class CommandError(Exception):
    """A usage error found after argument parsing (exit status 2)."""


# ---------------------------------------------------------------------------
# Loading a model class from a file
# ---------------------------------------------------------------------------


def _split_spec(spec: str) -> tuple[str, str | None]:
    """``'dir/file.py:Model'`` -> ``('dir/file.py', 'Model')``; no ``:Model`` -> None."""
    path, sep, name = spec.rpartition(":")
    if sep and path and name.isidentifier():
        return path, name
    return spec, None


def _module_name(path: Path) -> str:
    stem = re.sub(r"\W", "_", path.stem)
    return f"_acausal_model_{stem}"


def load_model_class(spec: str) -> type:
    """The model class named by ``FILE.py[:Model]``.

    The file is imported as a module with its own folder on ``sys.path``
    (so that it can import its neighbours).

    Raises
    ------
    CommandError
        If the file is missing or cannot be imported, or the class is not
        there or not a Model; the message lists the models the file defines.
    """
    filename, wanted = _split_spec(spec)
    path = Path(filename)
    if not path.is_file():
        if path.exists():
            raise CommandError(f"{filename} is not a file")
        raise CommandError(f"file not found: {filename}")
    path = path.resolve()
    folder = str(path.parent)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    name = _module_name(path)
    module_spec = importlib.util.spec_from_file_location(name, path)
    if module_spec is None or module_spec.loader is None:
        raise CommandError(f"cannot import {filename}: not a Python file")
    module = importlib.util.module_from_spec(module_spec)
    sys.modules[name] = module
    try:
        module_spec.loader.exec_module(module)
    except AcausalError:
        raise
    except BaseException as exc:  # noqa: BLE001 - any failure of the user's file
        sys.modules.pop(name, None)
        if isinstance(exc, (KeyboardInterrupt, SystemExit)):
            raise
        raise CommandError(f"cannot import {filename}: {_describe_exception(exc, path)}") from exc

    defined = sorted((obj for obj in vars(module).values()
                      if isinstance(obj, type) and issubclass(obj, Model) and obj is not Model
                      and obj.__module__ == module.__name__),
                     key=lambda c: c.__name__)
    listing = ", ".join(c.__name__ for c in defined) or "none"
    if wanted is not None:
        obj = getattr(module, wanted, None)
        if obj is None:
            raise CommandError(f"{filename} has no model {wanted!r}; models defined there: {listing}")
        if not (isinstance(obj, type) and issubclass(obj, Model)):
            raise CommandError(f"{wanted} in {filename} is not a Model subclass; models defined "
                               f"there: {listing}")
        return obj
    if len(defined) == 1:
        return defined[0]
    if not defined:
        classes = sorted(n for n, obj in vars(module).items()
                         if isinstance(obj, type) and obj.__module__ == module.__name__)
        there = f"classes defined there: {', '.join(classes)}" if classes else "it defines no classes"
        raise CommandError(f"{filename} defines no subclass of acausal.Model ({there})")
    raise CommandError(f"{filename} defines several models ({listing}); name one as "
                       f"{filename}:{defined[0].__name__}")


def _describe_exception(exc: BaseException, path: Path) -> str:
    """``SyntaxError: ... (file.py, line 3)`` — where in the user's file it failed."""
    text = f"{type(exc).__name__}: {exc}"
    if isinstance(exc, SyntaxError):
        return text
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if Path(f.filename).resolve() == path]
    if frames:
        text += f" (line {frames[-1].lineno})"
    return text


def _instantiate(cls: type) -> Model:
    try:
        return cls()
    except AcausalError:
        raise
    except TypeError as exc:
        raise CommandError(f"cannot create {cls.__name__}() without arguments: {exc}") from exc


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


def _method(text: str) -> str:
    for name in METHODS:
        if text.lower() == name.lower():
            return name
    raise argparse.ArgumentTypeError(f"unknown method {text!r}; choose one of {', '.join(METHODS)}")


def _parser() -> argparse.ArgumentParser:
    from .. import __version__

    parser = argparse.ArgumentParser(
        prog="acausal",
        description="Simulate, compare and explain acausal models (Modelica-like, in Python).",
        epilog="MODEL is FILE.py (the one Model subclass the file defines) or FILE.py:ClassName.")
    parser.add_argument("--version", action="version", version=f"acausal {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

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
    sim.add_argument("--method", type=_method, default="RK45", metavar="M",
                     help=f"integration method: {', '.join(METHODS)} (default RK45)")
    sim.add_argument("--rtol", type=_positive_float, metavar="R",
                     help="relative tolerance; default: the experiment's or 1e-6")
    sim.add_argument("--atol", type=_positive_float, metavar="A",
                     help="absolute tolerance; default: rtol times each state's nominal value")
    sim.add_argument("--out", metavar="FILE.csv", help="CSV file to write; default: <Model>.csv")
    sim.add_argument("--signals", metavar="a,b,...",
                     help="comma-separated variables to write; default: all")
    sim.set_defaults(run=_cmd_simulate)

    cmp_ = commands.add_parser("compare", help="tube-test a model against the MSL reference results",
                               description="Simulate a model with its experiment settings and "
                                           "tube-test every signal of the reference's "
                                           "comparisonSignals.txt (csv-compare's test).")
    cmp_.add_argument("models", metavar="MODEL", nargs="+",
                      help="FILE.py or FILE.py:ClassName (with modelica_class); several may be given")
    cmp_.add_argument("--reference-dir", metavar="DIR",
                      help="folder of reference results (default: ACAUSAL_REFERENCE_DIR, else "
                           "the references bundled with acausal for its examples)")
    cmp_.add_argument("--plot", metavar="DIR", help="write one PNG per compared signal into DIR")
    cmp_.add_argument("--method", type=_method, default="RK45", metavar="M",
                      help=f"integration method: {', '.join(METHODS)} (default RK45)")
    cmp_.add_argument("--rtol", type=_positive_float, metavar="R",
                      help=f"relative tolerance (default {COMPARE_RTOL:g}, or the experiment's "
                           f"if tighter)")
    cmp_.set_defaults(run=_cmd_compare)

    exp = commands.add_parser("explain", help="show how the model is translated, stage by stage",
                              description="Print what each translation stage does to the model "
                                          "and draw the incidence matrix in BLT order.")
    exp.add_argument("model", metavar="MODEL", help="FILE.py or FILE.py:ClassName")
    exp.add_argument("--out", metavar="DIR", help="folder for the pictures (default: current directory)")
    exp.set_defaults(run=_cmd_explain)
    commands.add_parser("bench", help="work-precision benchmark (acausal bench --help)", add_help=False)
    return parser


# ---------------------------------------------------------------------------
# Commands
# ---------------------------------------------------------------------------


def _simulate(model, **options):
    """Simulate after checking the times, which ``simulate`` would reject with a ValueError."""
    from ..language import Experiment
    from ..runtime.simulate import simulate

    experiment = getattr(model, "experiment", None) or Experiment()
    start = experiment.start_time if options.get("start_time") is None else options["start_time"]
    stop = experiment.stop_time if options.get("stop_time") is None else options["stop_time"]
    if not stop > start:
        raise CommandError(f"the stop time ({stop:g}) must be after the start time ({start:g})")
    return simulate(model, **options)


def _cmd_simulate(args) -> int:
    cls = load_model_class(args.model)
    model = _instantiate(cls)
    signals = None
    if args.signals is not None:
        signals = [s.strip() for s in args.signals.split(",") if s.strip()]
        if not signals:
            raise CommandError("--signals names no variable")
    if signals is not None:
        from ..compiler.flatten import flatten

        known = {v.name for v in flatten(model).variables}
        missing = [s for s in signals if s not in known]
        if missing:
            result = None
            import difflib

            hints = []
            for m in missing:
                close = difflib.get_close_matches(m, sorted(known), n=3)
                hints.append(f"{m}" + (f" (did you mean {', '.join(close)}?)" if close else ""))
            raise CommandError(f"not a variable of {cls.__name__}: {'; '.join(hints)}")
    # with --signals only what those signals need is computed (effects on demand)
    result = _simulate(_instantiate(cls), start_time=args.start_time, stop_time=args.stop_time,
                       interval=args.interval, method=args.method, rtol=args.rtol, atol=args.atol,
                       outputs=signals)
    out = Path(args.out) if args.out else Path(f"{cls.__name__}.csv")
    if out.parent != Path(""):
        out.parent.mkdir(parents=True, exist_ok=True)
    result.to_csv(out, signals)
    print(result.summary())
    print(f"wrote {out}")
    if not result.success:
        print(f"error: the simulation of {cls.__name__} failed: {result.message}\n"
              f"  (the CSV holds the result up to the failure)", file=sys.stderr)
        return 1
    return 0


def _cmd_compare(args) -> int:
    statuses = []
    for model in args.models:
        if len(args.models) > 1:
            print(f"== {model}")
        statuses.append(_compare_one(args, model, len(args.models) > 1))
    if len(args.models) > 1:
        passed = sum(s == 0 for s in statuses)
        print(f"== {passed} of {len(statuses)} models match their reference results")
    return max(statuses)


def _compare_one(args, model_spec: str, several: bool) -> int:
    from .compare import compare_signals, load_reference, plot_signal

    cls = load_model_class(model_spec)
    modelica_class = getattr(cls, "modelica_class", None)
    if not modelica_class:
        raise CommandError(f"{cls.__name__} has no modelica_class: nothing to compare with "
                           f"(set modelica_class = 'Modelica.…' on the class)")
    reference = load_reference(modelica_class, args.reference_dir)
    model = _instantiate(cls)
    experiment = getattr(cls, "experiment", None)
    rtol = args.rtol
    if rtol is None:
        tolerance = getattr(experiment, "tolerance", None)
        rtol = min(COMPARE_RTOL, tolerance) if tolerance else COMPARE_RTOL
    result = _simulate(model, method=args.method, rtol=rtol)
    print(result.summary())
    comparison = compare_signals(reference, result.time, result.columns)
    print(comparison.table())
    if args.plot:
        folder = Path(args.plot) / cls.__name__ if several else Path(args.plot)
        folder.mkdir(parents=True, exist_ok=True)
        for name in reference.compared:
            if name not in result:
                print(f"not plotted (missing from the result): {name}")
                continue
            path = folder / f"{_file_safe(name)}.png"
            plot_signal(reference, name, result.time, result.columns, path)
            print(f"wrote {path}")
    ok = comparison.passed and result.success
    if not result.success:
        print(f"error: the simulation of {cls.__name__} failed: {result.message}", file=sys.stderr)
    elif not comparison.passed:
        failed = ", ".join(s.name for s in comparison.failures)
        print(f"error: {len(comparison.failures)} of {len(comparison.signals)} signals outside the "
              f"tube: {failed}", file=sys.stderr)
    return 0 if ok else 1


def _cmd_explain(args) -> int:
    from .explain import explain

    cls = load_model_class(args.model)
    model = _instantiate(cls)
    out = Path(args.out) if args.out else Path.cwd()
    explanation = explain(model, out_dir=out)
    print(explanation.text, end="")
    print()
    for path in explanation.pictures:
        print(f"wrote {path}")
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
        0 success; 1 failed simulation or comparison; 2 usage or model error.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "bench":
        from .bench import main as bench_main

        return bench_main(argv[1:])
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help, --version or a usage error
        return exc.code if isinstance(exc.code, int) else 2
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        return args.run(args)
    except CommandError as exc:
        print(f"acausal {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except AcausalError as exc:
        print(f"acausal {args.command}: error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 2 if isinstance(exc, ValueError) else 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


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
        status = main()
    finally:
        sys.stdout.flush()
        gc.collect()
        gc.freeze()
    sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    run()
