"""The ``roadscan`` command: :func:`main` (in :mod:`pipelines.cli.app`), its "did you mean"
hints (:mod:`~pipelines.cli.hints`), its signal handling (:mod:`~pipelines.cli.signals`) and one
module per subcommand in ``commands/``. Run it as ``roadscan`` or ``python -m pipelines.cli``."""

from __future__ import annotations

from typing import Any

__all__ = ["main"]


def __getattr__(name: str) -> Any:
    # lazy, so that ``python -m pipelines.cli.app`` imports the command module only once
    if name == "main":
        from pipelines.cli.app import main

        return main
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
