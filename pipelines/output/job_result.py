"""What a public job returns: the dict of its main JSON file, with this call's warnings and a
one-line repr (a notebook cell shows the key figures, not the whole file)."""

from __future__ import annotations

import functools
import numbers
from collections.abc import Callable
from typing import Any, TypeVar

from pipelines.checks.run_warnings import collecting

__all__ = ["JobResult", "returns_job_result"]

F = TypeVar("F", bound=Callable[..., Any])

#: longest repr [characters]
REPR_MAX = 480


class JobResult(dict):
    """The main JSON of one job run (``comparison.json``, ``combine.json``, ...) as a dict,
    equal to the file key for key.

    Attributes
    ----------
    job : str
        The job's name (``"compare"``, ``"dry_vs_wet"``...).
    warnings : list of str
        This call's warnings only, in the order first said (each was also issued as a
        :class:`roadscan.RoadscanWarning`).
    """

    def __init__(self, job: str, data: dict[str, Any], warnings: list[str] | None = None) -> None:
        super().__init__(data)
        self.job = job
        self.warnings = list(warnings or [])

    def __repr__(self) -> str:
        figures = []
        for key, value in self.items():
            if isinstance(value, bool) or value is None:
                continue
            if isinstance(value, numbers.Real):
                figures.append(f"{key}={float(value):.3g}")
            elif isinstance(value, str) and len(value) <= 40:
                figures.append(f"{key}={value!r}")
        keys = [k for k in self if not isinstance(self[k], (numbers.Real, str)) or isinstance(self[k], bool)]
        head = f"{type(self).__name__}({self.job!r}, "
        tail = f"warnings={len(self.warnings)})"
        body = ", ".join(figures[:8] + ([f"sections={keys[:6]}"] if keys else []))
        text = head + body + (", " if body else "") + tail
        if len(text) > REPR_MAX:
            text = head + body[: REPR_MAX - len(head) - len(tail) - 6] + "..., " + tail
        return text


def returns_job_result(name: str) -> Callable[[F], F]:
    """Decorator: the job's returned dict becomes a :class:`JobResult` carrying the warnings
    said during the call (one :func:`pipelines.checks.run_warnings.collecting` scope)."""

    def decorate(job: F) -> F:
        @functools.wraps(job)
        def run(*args: Any, **kwargs: Any) -> Any:
            with collecting() as said:
                data = job(*args, **kwargs)
            return JobResult(name, data, said.lines) if isinstance(data, dict) else data

        return run  # type: ignore[return-value]

    return decorate
