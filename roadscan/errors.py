"""Errors and notes about bad input, structured so that each front end can word them.

roadscan never names a command-line flag: when a message must point at an option the caller
gave (the pixel spacing, the height unit, a channel...), it names it by its keyword, written
``{spacing}`` in the message, and lists the keyword in ``hint_option``. ``str()`` of the error
or note names the option as the keyword (``'spacing'``), the way a Python caller passes it;
the ``roadscan`` command renders the same message with its flag (``--spacing``) through
:meth:`InputError.render`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Sequence

__all__ = ["InputError", "OptionNote", "RoadscanWarning", "render_options"]


def _keys(hint_option):
    if hint_option is None:
        return ()
    if isinstance(hint_option, str):
        return (hint_option,)
    return tuple(str(k) for k in hint_option)


def _first_line(text):
    text = str(text).strip()
    return text.splitlines()[0] if text else "invalid input"


def _library_name(key):
    return repr(key)


def render_options(
    template: str, options: Iterable[str], name_option: Callable[[str], str] | None = None
) -> str:
    """``template`` with each ``{key}`` of ``options`` replaced by ``name_option(key)``.

    Parameters
    ----------
    template : str
        A message naming options as ``{key}`` (other braces are left as they are).
    options : sequence of str
        The option keywords the message names.
    name_option : callable or None
        ``key -> text``; default: the keyword quoted (``'spacing'``).

    Returns
    -------
    str
    """
    name_option = name_option or _library_name
    out = str(template)
    for key in options:
        out = out.replace("{" + key + "}", name_option(key))
    return out


class RoadscanWarning(UserWarning):
    """The one category of every warning roadscan, friction and pipelines issue.

    A result the code could compute but an engineer should not take at face value (a fit over
    less than half a decade, a units slip suspected, mu extrapolated beyond the measured band).
    Filter them as a group: ``warnings.simplefilter("ignore", roadscan.RoadscanWarning)``; each
    job's result also carries its own in ``.warnings`` (or the ``"warnings"`` key of its JSON).
    """


class InputError(ValueError):
    """Bad input: ``str(err)`` is one line naming the file and the problem.

    Parameters
    ----------
    path : str, Path or None
        The file at fault (None when the fault is an option's value).
    problem : str or OptionNote
        One line; may name options as ``{key}`` when ``hint_option`` lists ``key`` (an
        :class:`OptionNote` brings its own).
    hint_option : str, sequence of str or None
        The option keyword(s) the message points at (``"spacing"``, ``"units"``...), so that a
        front end can name them its own way (the command line: ``--spacing``).

    Attributes
    ----------
    file : str or None
        ``path`` as text (also ``path``).
    what : str
        The problem with options named by keyword (also ``problem``).
    hint_option : tuple of str
        The option keywords the problem names.
    template : str
        The problem with its ``{key}`` placeholders.
    """

    def __init__(
        self,
        path: str | os.PathLike[str] | None,
        problem: str,
        hint_option: str | Sequence[str] | None = None,
    ) -> None:
        if hint_option is None and isinstance(problem, OptionNote):
            hint_option = problem.hint_option
            problem = problem.template
        self.path = str(path) if path is not None else None
        self.hint_option = _keys(hint_option)
        self.template = _first_line(problem)
        self.problem = render_options(self.template, self.hint_option)
        super().__init__(self._join(self.problem))

    @property
    def file(self) -> str | None:
        """The file at fault, or None."""
        return self.path

    @property
    def what(self) -> str:
        """The problem, options named by keyword."""
        return self.problem

    def _join(self, text):
        return f"{self.path}: {text}" if self.path else text

    def render(self, name_option: Callable[[str], str] | None = None) -> str:
        """The one-line message with each option named by ``name_option(key)``."""
        return self._join(render_options(self.template, self.hint_option, name_option))

    def reworded(self, path: str | os.PathLike[str] | None = None, prefix: str = "") -> InputError:
        """A new error with the same options: ``prefix`` + this problem, at ``path`` (default:
        this error's file)."""
        return InputError(self.path if path is None else path, str(prefix) + self.template, self.hint_option)

    def __reduce__(self):  # across processes (Dask workers) with its options
        return (InputError, (self.path, self.template, self.hint_option))


class OptionNote(str):
    """A note (a warning line) that names options as :class:`InputError` does: its text names
    them by keyword; :meth:`render` names them another way.

    Parameters
    ----------
    template : str
        The note, naming options as ``{key}``.
    hint_option : str or sequence of str
        The option keywords it names.
    """

    template: str
    hint_option: tuple[str, ...]

    def __new__(cls, template: str, hint_option: str | Sequence[str] = ()) -> OptionNote:
        keys = _keys(hint_option)
        self = super().__new__(cls, render_options(template, keys))
        self.template = str(template)
        self.hint_option = keys
        return self

    def render(self, name_option: Callable[[str], str] | None = None) -> str:
        """The note with each option named by ``name_option(key)``."""
        return render_options(self.template, self.hint_option, name_option)

    def __reduce__(self):
        return (OptionNote, (self.template, self.hint_option))
