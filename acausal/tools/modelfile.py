"""Loading a model class from a Python file, for the commands.

A model is named ``FILE.py`` (the one :class:`~acausal.Model` subclass the
file defines) or ``FILE.py:ClassName``.  The file is imported as a module
with its own folder on ``sys.path``, so that it can import its neighbours.
"""

from __future__ import annotations

import importlib.util
import os
import re
import sys
import traceback
from pathlib import Path

from ..errors import AcausalError

__all__ = ["CommandError", "load_model_class", "reproducing_models"]


class CommandError(Exception):
    """A usage error found after argument parsing (exit status 2)."""


def _split_spec(spec: str) -> tuple[str, str | None]:
    """``'dir/file.py:Model'`` -> ``('dir/file.py', 'Model')``; no ``:Model`` -> None."""
    path, sep, name = spec.rpartition(":")
    if sep and path and name.isidentifier():
        return path, name
    return spec, None


def _module_name(path: Path) -> str:
    stem = re.sub(r"\W", "_", path.stem)
    return f"_acausal_model_{stem}"


def _import_file(path: Path, filename: str):
    """Import a Python file as a module, with its own folder on ``sys.path``."""
    path = path.resolve()
    folder = str(path.parent)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    name = _module_name(path)
    loaded = sys.modules.get(name)
    if loaded is not None and getattr(loaded, "__file__", None) == str(path):
        return loaded  # already imported by this command (a folder, then its models)
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
        if isinstance(exc, KeyboardInterrupt):
            raise
        if isinstance(exc, SystemExit):
            # a script's sys.exit() would end the command, with status 0 for sys.exit(0), and
            # nothing written: the command did not do what was asked, which is an error
            raise CommandError(_exit_message(exc, path, filename)) from None
        raise CommandError(f"cannot import {filename}: {_describe_exception(exc, path)}") from exc
    return module


def _exit_message(exc: SystemExit, path: Path, filename: str) -> str:
    """``x.py called sys.exit(0) while being imported (line 7); ...``: what to change."""
    call = "sys.exit()" if exc.code is None else f"sys.exit({exc.code!r})"
    line = _user_line(exc, path)
    where = f" (line {line})" if line is not None else ""
    return (f"{filename} called {call} while being imported{where}; a model file is imported to "
            f"find its models, so code that runs a program belongs under "
            f"'if __name__ == \"__main__\":'")


def _models_defined(module) -> list[type]:
    """The Model subclasses a module defines (not those it imports), by name."""
    from ..language import Model  # a model file imports the language anyway

    return sorted((obj for obj in vars(module).values()
                   if isinstance(obj, type) and issubclass(obj, Model) and obj is not Model
                   and obj.__module__ == module.__name__),
                  key=lambda c: c.__name__)


def reproducing_models(folder: str) -> list[str]:
    """``FILE.py:Model`` of every model in a folder's Python files (or in one file) that
    declares ``modelica_class``."""
    specs = []
    paths = [Path(folder)] if Path(folder).is_file() else sorted(Path(folder).glob("*.py"))
    for path in paths:
        module = _import_file(path, str(path))
        specs += [f"{path}:{cls.__name__}" for cls in _models_defined(module)
                  if getattr(cls, "modelica_class", None)]
    if not specs:
        raise CommandError(f"no model in {folder}/*.py declares modelica_class: nothing to compare")
    return specs


def load_model_class(spec: str) -> type:
    """The model class named by ``FILE.py[:Model]``.

    The file is imported as a module with its own folder on ``sys.path``
    (so that it can import its neighbours).

    Raises
    ------
    CommandError
        If the file is missing or cannot be imported (an exception, or
        ``sys.exit()`` while it is imported), or the class is not there or
        not a Model; the message lists the models the file defines.
    """
    from ..language import Model  # a model file imports the language anyway

    filename, wanted = _split_spec(spec)
    path = Path(filename)
    if path.suffix == ".mo" or (not path.exists() and _is_class_name(spec)):
        return _load_modelica(spec, filename, wanted)
    if not path.is_file():
        if path.exists():
            raise CommandError(f"{filename} is not a file")
        raise CommandError(f"file not found: {filename}")
    module = _import_file(path, filename)
    defined = _models_defined(module)
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


def _is_class_name(spec: str) -> bool:
    """``Modelica.Mechanics.Rotational.Examples.First``: a dotted Modelica class name."""
    return bool(re.fullmatch(r"[A-Za-z_]\w*(\.[A-Za-z_]\w*)+", spec)) and not spec.endswith(".py")


def _load_modelica(spec: str, filename: str, wanted: str | None) -> type:
    """The model of ``FILE.mo[:Class]``, or of a dotted class name found on ``MODELICAPATH``."""
    from ..modelica import load
    from ..modelica.read import _package_file

    path = Path(filename)
    if path.suffix == ".mo":
        if not path.is_file():
            raise CommandError(f"file not found: {filename}")
        return load(path, wanted)
    found = _package_file(spec)
    if found is None:
        raise CommandError(f"{spec}: neither a file nor a class found on MODELICAPATH "
                           f"({os.environ.get('MODELICAPATH') or 'not set'})")
    # the file of the class itself (First.mo) or of the package that holds it
    for k in range(spec.count(".") + 1, 0, -1):
        candidate = _package_file(".".join(spec.split(".")[:k]))
        if candidate is not None:
            found = candidate
            break
    return load(found, spec)


def _describe_exception(exc: BaseException, path: Path) -> str:
    """``SyntaxError: ... (file.py, line 3)`` — where in the user's file it failed."""
    text = f"{type(exc).__name__}: {exc}"
    if isinstance(exc, SyntaxError):
        return text
    line = _user_line(exc, path)
    if line is not None:
        text += f" (line {line})"
    return text


def _user_line(exc: BaseException, path: Path) -> int | None:
    """The line of the file ``path`` where ``exc`` was raised (its innermost frame there)."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if Path(f.filename).resolve() == path]
    return frames[-1].lineno if frames else None
