"""INPUTS of ``roadscan batch`` -> one job per input, in input order.

An input is a height file, a glob pattern (``*``, ``?``, ``[...]``, ``**`` recursive; its
matches in sorted order), or a manifest CSV: a ``.csv`` whose header row names only the
columns ``file``, ``chainage_m`` and ``label`` (``file`` required, any order). Manifest paths
are relative to the manifest's folder; ``chainage_m`` is metres along the road.

A missing file, a pattern matching nothing or a manifest row with a bad chainage becomes a job
that carries its error (a row of ``campaign.csv`` with status ``error``), never the end of the
campaign. An unreadable manifest is refused as a whole (InputError naming it).
"""

from __future__ import annotations

import glob
import math
from dataclasses import dataclass
from pathlib import Path

from roadscan.errors import InputError

__all__ = ["Job", "expand_inputs", "is_manifest", "MANIFEST_COLUMNS"]

MANIFEST_COLUMNS = ("file", "chainage_m", "label")
_GLOB_CHARS = set("*?[")


@dataclass
class Job:
    """One input of the campaign (``error`` set: it failed before any reading).

    Attributes
    ----------
    file : str
        The input path.
    label : str
        Its label.
    chainage_m : float or None
        Its chainage [m].
    error : str or None
        Why it failed before reading.
    subdir : str or None
        Its output folder name.
    """

    file: str
    label: str = ""
    chainage_m: float | None = None
    error: str | None = None
    subdir: str | None = None  # output folder name under DIR, set by :func:`assign_subdirs`


def _header_cells(path):
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as fh:
            for line in fh:
                s = line.strip()
                if s and not s.startswith("#"):
                    return [c.strip().lower() for c in s.split(",")]
    except OSError:
        return None
    return None


def is_manifest(path):
    """True for a ``.csv`` whose header holds ``file`` and only manifest column names.

    Parameters
    ----------
    path : str or Path
        A file.

    Returns
    -------
    bool
    """
    path = Path(path)
    if path.suffix.lower() != ".csv" or not path.is_file():
        return False
    cells = _header_cells(path)
    return bool(cells) and "file" in cells and set(cells) <= set(MANIFEST_COLUMNS)


def read_manifest(path):
    """Jobs of a manifest CSV (header ``file[,chainage_m][,label]``)."""
    from pipelines.output.csv_files import read_csv_rows

    path = Path(path)
    head, body = read_csv_rows(path, "a header file[,chainage_m][,label]")
    head = [h.lower() for h in head]
    if len(set(head)) != len(head):
        raise InputError(path, f"repeated column in manifest header {','.join(head)!r}")
    col = {name: head.index(name) for name in MANIFEST_COLUMNS if name in head}
    jobs = []
    for n, row in enumerate(body, start=2):
        cell = {k: (row[i] if i < len(row) else "") for k, i in col.items()}
        name = cell["file"]
        label = cell.get("label", "")
        if not name:
            jobs.append(Job(f"{path}:row{n}", label, None, f"{path}: row {n} has no file name"))
            continue
        f = Path(name).expanduser()
        f = f if f.is_absolute() else path.parent / f
        chain, err = None, None
        text = cell.get("chainage_m", "")
        if text:
            try:
                chain = float(text)
                if not math.isfinite(chain):
                    raise ValueError
            except ValueError:
                chain, err = None, f"{path}: row {n}: chainage_m {text!r} is not a number of metres"
        jobs.append(Job(str(f), label, chain, err))
    return jobs


def expand_inputs(items):
    """Files, glob patterns and manifests -> list of :class:`Job` in input order.

    The output folder of each job is ``subdir`` (the file's stem; ``stem_2``, ``stem_3``... when
    stems repeat, numbered in input order as ``roadscan analyse`` does).

    Parameters
    ----------
    items : iterable of str
        Files, glob patterns and manifests.

    Returns
    -------
    list of Job
    """
    jobs = []
    for item in items:
        item = str(item)
        if is_manifest(item):
            jobs.extend(read_manifest(item))
        elif _GLOB_CHARS & set(item) and not Path(item).exists():
            hits = sorted(glob.glob(item, recursive=True))
            hits = [h for h in hits if not Path(h).is_dir()]
            if not hits:
                jobs.append(Job(item, error=f"{item}: pattern matches no file"))
            for h in hits:
                jobs.extend(read_manifest(h) if is_manifest(h) else [Job(h)])
        else:
            jobs.append(Job(item))
    assign_subdirs(jobs)
    return jobs


def assign_subdirs(jobs):
    """Unique output folder names from the file stems, in input order."""
    seen = {}
    taken = set()
    for job in jobs:
        stem = Path(job.file).stem or "scan"
        n = seen.get(stem, 0) + 1
        name = stem if n == 1 else f"{stem}_{n}"
        while name in taken:  # "a_2" given as a file stem and as a repeat of "a"
            n += 1
            name = f"{stem}_{n}"
        seen[stem] = n
        taken.add(name)
        job.subdir = name
    return jobs
