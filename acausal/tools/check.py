"""Check a model without simulating it, as Modelica's "check model" does.

:func:`check_model` flattens and partitions the model (:func:`~acausal.compiler.translate.translate`),
compiles the continuous and the initialization system of the discrete state it
starts in (which checks that equations and unknowns match, with the over- or
under-determined part named), and checks the units of every equation
(:func:`~acausal.compiler.units.check_units`).  Nothing is solved numerically:
a model that passes can still fail to initialize or to integrate.

:func:`main_check` is the command line, ``acausal check FILE.py[:Model] [--strict]``.

Examples
--------
>>> from acausal.tools.check import check_model
>>> from examples.first import First                          # doctest: +SKIP
>>> print(check_model(First()))                               # doctest: +SKIP
First: passed
  First: 75 continuous and 0 discrete variables, ...
"""

from __future__ import annotations

import argparse
import sys
import warnings
from dataclasses import dataclass

from ..errors import AcausalError, InitializationError, StructuralError, UnitWarning
from ..language import Component
from ..compiler.translate import Translation, translate
from ..compiler.units import UnitReport, check_units
from ..runtime.events import evaluator_for
from ..runtime.initialization import start_guess
from .modelfile import CommandError, load_model_class

__all__ = ["CheckProblem", "CheckReport", "check_model", "main_check"]


@dataclass(frozen=True)
class CheckProblem:
    """An error that stops the model from being simulated.

    Attributes
    ----------
    stage : str
        'definition' (declarations, equations, connections), 'structure'
        (equations and unknowns do not match) or 'initialization'.
    error : str
        The name of the exception class (``UnderDeterminedError``).
    message : str
        Its message, hint included.
    """

    stage: str
    error: str
    message: str


@dataclass(frozen=True)
class CheckReport:
    """What :func:`check_model` found.

    Attributes
    ----------
    model : str
        The model's class name.
    summary : str
        Counts of the flat model ('' if it could not be flattened).
    problems : tuple of CheckProblem
        Errors: the model cannot be simulated as it is.
    units : UnitReport or None
        The unit check (None if the model could not be flattened).
    notes : tuple of str
        Warnings given while compiling the start state (a picked split of a
        redundant constraint, start values used), for information.
    strict : bool
        Whether equations with inconsistent units count as errors.
    start_state : str
        The discrete state whose systems were compiled, in words.
    """

    model: str
    summary: str
    problems: tuple[CheckProblem, ...]
    units: UnitReport | None
    notes: tuple[str, ...] = ()
    strict: bool = False
    start_state: str = ""

    @property
    def unit_findings(self) -> int:
        return 0 if self.units is None else len(self.units.findings)

    @property
    def ok(self) -> bool:
        """No errors; with ``strict`` also no equation with inconsistent units."""
        return not self.problems and not (self.strict and self.unit_findings)

    def exit_code(self) -> int:
        """0 if the model passes, 1 if it does not (usage errors are 2, see :func:`main_check`)."""
        return 0 if self.ok else 1

    def __str__(self) -> str:
        if self.ok:
            verdict = "passed" + (f" with {self.unit_findings} unit warning(s)" if self.unit_findings else "")
        else:
            counts = [f"{len(self.problems)} error(s)"] if self.problems else []
            if self.unit_findings:
                counts.append(f"{self.unit_findings} equation(s) with inconsistent units")
            verdict = "FAILED: " + ", ".join(counts)
        lines = [f"{self.model}: {verdict}"]
        if self.summary:
            lines.append(f"  {self.summary}")
        if self.start_state:
            lines.append(f"  start state compiled: {self.start_state}")
        for problem in self.problems:
            body = problem.message.replace("\n", "\n    ")
            lines.append(f"  error ({problem.stage}) {problem.error}: {body}")
        if self.units is not None:
            label = "error" if self.strict else "warning"
            lines.append(f"  units: {self.units.checked} equations checked, "
                         f"{len(self.units.findings)} inconsistent")
            for finding in self.units.findings:
                lines.append(f"  {label} (units) {finding.message}")
                lines.append(f"    hint: {finding.hint}")
            for name, text in self.units.unparsed:
                lines.append(f"  note (units): unit of {name} not understood: {text!r} (not checked)")
        lines += [f"  note: {note}" for note in self.notes]
        return "\n".join(lines)


def _problem(exc: AcausalError) -> CheckProblem:
    if isinstance(exc, StructuralError):
        stage = "structure"
    elif isinstance(exc, InitializationError):
        stage = "initialization"
    else:
        stage = "definition"
    return CheckProblem(stage, type(exc).__name__, str(exc))


def _start_key(translation: Translation) -> tuple:
    """The discrete state initialization starts from (start values, every relation
    false, initial() true), found without solving anything."""
    discrete, relations = start_guess(translation)
    return evaluator_for(translation).key(discrete, discrete, relations, True)


def check_model(model: Component, strict: bool = False) -> CheckReport:
    """Check ``model`` without simulating it: definition, structure and units.

    Parameters
    ----------
    model : Model
        An instance.
    strict : bool
        Count equations with inconsistent units as errors (the report's
        :attr:`~CheckReport.ok` and exit code), not as warnings.

    Returns
    -------
    CheckReport
        Model problems are reported, not raised; ``str(report)`` is for
        reading, :meth:`CheckReport.exit_code` for a command line.  No
        :class:`~acausal.errors.UnitWarning` is issued: the findings are in
        :attr:`CheckReport.units`.
    """
    name = type(model).__name__
    try:
        translation = translate(model)
    except AcausalError as exc:
        return CheckReport(name, "", (_problem(exc),), None, strict=strict)
    flat = translation.flat
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)
        units = check_units(flat, strict=False)
    problems: list[CheckProblem] = []
    state = ""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            key = _start_key(translation)
            state = translation.describe(key) if key else ""
            translation.system(key)
            translation.initial_system(key)
        except AcausalError as exc:
            problems.append(_problem(exc))
    notes = tuple(dict.fromkeys(str(w.message) for w in caught if not issubclass(w.category, DeprecationWarning)))
    return CheckReport(name, flat.summary(), tuple(problems), units, notes, strict, state)


def main_check(argv: list[str]) -> int:
    """``acausal check FILE.py[:Model] [--strict]``: check a model, print the report.

    Parameters
    ----------
    argv : list of str
        The arguments after ``check``.

    Returns
    -------
    int
        0 the model passes (unit warnings allowed unless ``--strict``); 1 it
        does not; 2 usage error (no such file or model, it cannot be imported
        or created).
    """
    parser = argparse.ArgumentParser(
        prog="acausal check",
        description="Check a model without simulating it: equations and connections, balance "
                    "of the start state's systems, and the units of every equation.")
    parser.add_argument("model", help="FILE.py or FILE.py:Model")
    parser.add_argument("--strict", action="store_true",
                        help="equations with inconsistent units are errors (exit status 1)")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help or a usage error
        return exc.code if isinstance(exc.code, int) else 2
    try:
        cls = load_model_class(args.model)
    except CommandError as exc:
        print(f"acausal check: error: {exc}", file=sys.stderr)
        return 2
    try:
        model = cls()
    except AcausalError as exc:
        report = CheckReport(cls.__name__, "", (_problem(exc),), None, strict=args.strict)
        print(report)
        return report.exit_code()
    except Exception as exc:  # noqa: BLE001 - any failure of the user's constructor
        print(f"acausal check: error: cannot create {cls.__name__}(): {type(exc).__name__}: {exc}",
              file=sys.stderr)
        return 2
    try:
        report = check_model(model, strict=args.strict)
    except Exception as exc:  # noqa: BLE001 - a failure of the model's own build() or equations()
        print(f"acausal check: error: cannot check {cls.__name__}: {type(exc).__name__}: {exc}",
              file=sys.stderr)
        return 2
    print(report)
    return report.exit_code()
