"""Between a job's Python signature and the settings its builders read.

Every public job (:func:`pipelines.analyse`, :func:`pipelines.compare`, ...) has explicit
keyword-only parameters, named after the command's long flags with underscores, with the flag's
default. :func:`options_of` checks the values a caller gave against the parameter annotations
(numbers are numbers in SI; a string is accepted where the annotation admits ``str``, e.g. a
pressure with its unit ``"0.25MPa"``; ``Literal`` choices are checked) and hands the builders the
same :class:`argparse.Namespace` the command line's parser produces, so that both doors reach
one set of checks and one :class:`~pipelines.settings.friction.FrictionSettings`. No argv is
made and no parser is consulted on the way.

The command goes the other way with :func:`keywords_of`: the flags it parsed, as the keywords of
the job it calls.
"""

from __future__ import annotations

import argparse
import functools
import inspect
import math
import numbers
import os
import types
import typing
from collections.abc import Callable
from typing import Any, Literal

from roadscan.errors import InputError

__all__ = ["options_of", "keywords_of", "job_parameters"]


def job_parameters(job: Callable[..., Any]) -> dict[str, inspect.Parameter]:
    """The keyword-only parameters of ``job`` (its options), by name, in signature order."""
    sig = inspect.signature(job)
    return {n: p for n, p in sig.parameters.items() if p.kind is inspect.Parameter.KEYWORD_ONLY}


def _hint_parts(hint: Any) -> tuple[Any, ...]:
    origin = typing.get_origin(hint)
    if origin is typing.Union or origin is types.UnionType:
        return typing.get_args(hint)
    return (hint,)


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _check_value(job_name: str, name: str, value: Any, hint: Any) -> Any:
    """``value`` checked against the annotation ``hint`` of option ``name`` (InputError naming
    the flag when it is the wrong kind or outside its choices; a number given as text for a
    number-only option is read as a number)."""
    parts = _hint_parts(hint)
    if value is None:
        return None
    literals = [a for p in parts if typing.get_origin(p) is Literal for a in typing.get_args(p)]
    if literals:
        if value in literals:
            return value
        for lit in literals:  # "8" for Literal[4, 8]
            if isinstance(lit, int) and isinstance(value, str) and value.strip() == str(lit):
                return lit
        raise InputError(
            None, f"{_flag(name)} {value!r}: must be one of {', '.join(repr(a) for a in literals)}"
        )
    accepts_str = any(p is str for p in parts)
    wants_bool = any(p is bool for p in parts)
    wants_num = any(p in (float, int) for p in parts)
    if wants_bool and not wants_num:
        if isinstance(value, (bool, int)) and not isinstance(value, float):
            return bool(value)
        raise InputError(None, f"{_flag(name)}: {job_name}() takes True or False, not {value!r}")
    if wants_num and isinstance(value, numbers.Real) and not isinstance(value, bool):
        value = float(value) if float in parts else math.trunc(value)  # int(), typed for Real
        if isinstance(value, float) and not math.isfinite(value):
            raise InputError(None, f"{_flag(name)} {value!r}: must be a finite number")
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, str):
        if accepts_str:
            return value
        if wants_num:
            try:
                return float(value) if float in parts else int(value)
            except ValueError:
                raise InputError(None, f"{_flag(name)} {value!r}: expected a number (SI units)") from None
    return value  # arrays, pairs, rubber objects: the builder that reads it checks it


@functools.lru_cache(maxsize=64)
def _hints(job: Callable[..., Any]) -> dict[str, Any]:
    """The evaluated annotations of ``job`` (once per job). ``ArrayLike`` and friction's
    ``Rubber`` are imported by the job modules for type checkers only (numpy stays out of
    ``--help``): here each is any value (the builder that reads it checks it)."""
    return typing.get_type_hints(job, localns={"ArrayLike": Any, "Rubber": Any})


def options_of(job: Callable[..., Any], values: dict[str, Any]) -> argparse.Namespace:
    """The settings namespace of one call of ``job``: every keyword-only option with the value
    the caller gave (checked by :func:`_check_value` against its annotation) or its default.

    Parameters
    ----------
    job : callable
        The public job whose signature defines the options (``pipelines.analyse``, ...).
    values : dict
        The call's option values by parameter name (``locals()`` of the job is fine: names
        that are not options are ignored).

    Returns
    -------
    argparse.Namespace
        What the command's parser would give for the same settings, read by the same
        builders (``settings_from_args``, ``analysis_kwargs``, ``load_scan``...).
    """
    params = job_parameters(job)
    hints = _hints(job)
    ns = argparse.Namespace()
    for name, p in params.items():
        value = values.get(name, p.default)
        setattr(ns, name, _check_value(job.__name__, name, value, hints.get(name, Any)))
    return ns


def keywords_of(args: argparse.Namespace, job: Callable[..., Any]) -> dict[str, Any]:
    """The keyword arguments of ``job`` from a command's parsed flags: every option of the
    job's signature that the command parsed, under the same name.

    Parameters
    ----------
    args : argparse.Namespace
        The command's parsed flags.
    job : callable
        The public job the command calls.

    Returns
    -------
    dict
    """
    return {name: getattr(args, name) for name in job_parameters(job) if hasattr(args, name)}
