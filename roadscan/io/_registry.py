"""Readers and writers registered by file extension.

``READERS[".ext"]`` is ``reader(path, spacing=None, units=None) -> HeightMap | Profile``;
``WRITERS[".ext"]`` is ``writer(path, obj)`` writing to ``path`` (the caller makes it atomic).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["READERS", "WRITERS", "register_reader", "register_writer"]

READERS: dict[str, Callable[..., Any]] = {}
WRITERS: dict[str, Callable[..., Any]] = {}


def register_reader(*extensions):
    """Decorator registering a reader for lower-case extensions such as ``".npy"``.

    Parameters
    ----------
    *extensions : str
        Extensions with their dot.

    Returns
    -------
    callable
        The decorator.
    """

    def deco(func):
        for ext in extensions:
            READERS[ext.lower()] = func
        return func

    return deco


def register_writer(*extensions):
    """Decorator registering a writer for lower-case extensions.

    Parameters
    ----------
    *extensions : str
        Extensions with their dot.

    Returns
    -------
    callable
        The decorator.
    """

    def deco(func):
        for ext in extensions:
            WRITERS[ext.lower()] = func
        return func

    return deco
