""" "Did you mean ...?" for a mistyped command or option (``analyze`` -> ``analyse``,
``--output`` -> ``--out``), the version string of ``roadscan --version``, and the flag names of
the options roadscan's errors and notes point at (:func:`flag_of`, :func:`flag_text`).

Suggestions come from :func:`difflib.get_close_matches` (Ratcliff/Obershelp similarity, cutoff
0.6) over the parser's own command names and option strings, so they follow the parser as it
grows; a few common spellings that are too far for the ratio (``--output``) are mapped by
prefix: an unknown option that starts with a known one (or the reverse) is suggested too.
"""

from __future__ import annotations

import argparse
import difflib

__all__ = ["flag_of", "flag_text", "hint", "package_version", "subparsers"]


def package_version():
    """The installed package's version (``importlib.metadata``), ``unknown`` when not installed.

    Parameters
    ----------
    None

    Returns
    -------
    str
    """
    from importlib import metadata

    try:
        return metadata.version("roadscan")
    except metadata.PackageNotFoundError:
        return "unknown"


def flag_of(key):
    """The command-line flag of a library option keyword: ``"max_pixels"`` -> ``"--max-pixels"``.

    Parameters
    ----------
    key : str
        Option keyword.

    Returns
    -------
    str
    """
    return "--" + str(key).replace("_", "-")


def flag_text(message):
    """A message for the command line: an :class:`roadscan.errors.InputError` or
    :class:`roadscan.errors.OptionNote` with its options named by their flags (``'spacing'`` ->
    ``--spacing``); anything else as ``str()``.

    Parameters
    ----------
    message : object
        An error or note.

    Returns
    -------
    str
    """
    render = getattr(message, "render", None)
    if callable(render) and getattr(message, "hint_option", None) is not None:
        return render(flag_of)
    return str(message)


def subparsers(parser):
    """The sub-command parsers of ``parser`` by name (empty when it has none).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser.

    Returns
    -------
    dict
    """
    for action in parser._actions:  # argparse has no public API
        if isinstance(action, argparse._SubParsersAction):
            return action.choices
    return {}


def _options(parser):
    return [o for o in parser._option_string_actions if o.startswith("--")]


def _close(word, choices):
    best = difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
    if best:
        return best[0]
    stem = word.split("=", 1)[0]
    pre = [c for c in choices if len(c) > 3 and (stem.startswith(c) or c.startswith(stem))]
    return min(pre, key=lambda c: abs(len(c) - len(stem))) if pre else None


def _chosen(parser, argv):
    """The deepest subcommand parser ``argv`` selects (the parser itself when none)."""
    p = parser
    for tok in argv:
        subs = subparsers(p)
        if tok in subs:
            p = subs[tok]
    return p


def hint(parser, message, argv):
    """A ``"; did you mean X?"`` suffix for an argparse error ``message`` (empty when none).

    ``argv`` are the command-line words. An invalid command choice is matched against the
    command names; an unknown option (or a missing required one, when the user typed something
    close to it) against the options of the command the words select.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser.
    message : str
        Argparse's error.
    argv : list of str
        The command-line words.

    Returns
    -------
    str
    """
    argv = [str(a) for a in (argv or [])]
    if "invalid choice:" in message:
        word = message.split("invalid choice:", 1)[1].strip().split(" ", 1)[0].strip("'\"")
        names = list(subparsers(parser))
        flag = message.split("argument ", 1)[-1].split(":", 1)[0].split("/")[0].strip()
        for action in parser._actions:  # an option's own choices
            if action.choices and flag in action.option_strings:
                names = [str(c) for c in action.choices]
        best = _close(word, names) if names else None
        return f"; did you mean '{best}'?" if best else ""
    target = _chosen(parser, argv)
    known = _options(target)
    words = [a.split("=", 1)[0] for a in argv if a.startswith("--")]
    unknown = [w for w in words if not any(k.startswith(w) for k in known)]  # abbreviations pass
    for word in unknown:
        best = _close(word, known)
        if best:
            return f"; did you mean {best}?"
    return ""
