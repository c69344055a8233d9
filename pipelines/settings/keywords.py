"""From a command's parsed flags to the keyword arguments of its ``pipelines`` function:
each command parses its argv, turns the flags it got into keywords (:func:`keywords_of`) and
calls the very function a Python caller calls, which parses them again with the same option
definitions (:func:`pipelines.settings.analyse.options_from_kwargs`), so that the command and
the API cannot disagree.
"""
from __future__ import annotations

__all__ = ["keywords_of"]


def keywords_of(args, add_options):
    """The keyword arguments of a ``pipelines`` function from a command's parsed flags:
    each option that ``add_options`` defines and whose value is not its default, under its
    keyword (the long flag with dashes as underscores). Passed back to the API, they parse
    (:func:`pipelines.settings.analyse.options_from_kwargs`) to the same values.

    Parameters
    ----------
    args : argparse.Namespace
        The command's parsed flags.
    add_options : callable
        ``add_options(parser)``: the option definitions shared by the command and the API.

    Returns
    -------
    dict
    """
    from pipelines.settings.analyse import _parser

    p = _parser(add_options)
    out = {}
    for action in p._actions:
        if not action.option_strings or not hasattr(args, action.dest):
            continue
        value = getattr(args, action.dest)
        if value is not None and value != p.get_default(action.dest):
            out[action.dest] = value
    return out
