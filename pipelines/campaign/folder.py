"""Atomic per-scan output folders and the resume sidecar.

A scan's folder is built as a hidden temporary folder beside the target
(``DIR/.<name>.roadscan-tmp-<random>``) and swapped in as ``DIR/<name>`` only when every file is
written (:func:`roadscan.io.atomic.atomic_output_dir`):
an interrupted or failed scan never leaves a half-written ``DIR/<name>``, and a finished one is
never touched by a later interruption.

The sidecar ``DIR/<name>/.roadscan-batch.json`` records the input (absolute path, size, mtime
and SHA-256), a fingerprint of the analysis options and the campaign record(s) of the scan, so
``--resume`` can skip the scan without reading its outputs.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path

__all__ = [
    "atomic_folder",
    "SIDECAR",
    "file_identity",
    "same_input",
    "read_sidecar",
    "write_sidecar",
    "options_fingerprint",
    "campaign_leftovers",
    "recover_campaign",
    "earlier_campaign",
    "CAMPAIGN_FILES",
]

SIDECAR = ".roadscan-batch.json"
#: the campaign-level outputs in DIR (each written atomically: a kill while one is written
#: leaves its hidden temporary file ``.<stem>.XXXXXXXX<suffix>`` beside it)
CAMPAIGN_FILES = ("campaign.csv", "campaign_anisotropy.csv", "campaign.parquet", "report.html")
#: hidden files a killed campaign leaves in DIR: the temporary files of CAMPAIGN_FILES and the
#: report's figures (``.campaign_distributions.png``, embedded then deleted) and theirs
_TEMP_FILE = re.compile(
    r"^\.{1,2}(campaign[a-z_]*|report)(\.[a-z0-9_]{8})?\."
    r"(csv|parquet|html|png)$"
)


def atomic_folder(target):
    """Context manager yielding a fresh temporary folder beside ``target`` that replaces
    ``target`` when the block succeeds (:func:`roadscan.io.atomic.atomic_output_dir`: the
    target is always either the complete old set or the complete new one, even after
    ``kill -9``; on an exception, KeyboardInterrupt included, the temporary folder is removed
    and ``target`` is left as it was). An existing ``target`` that holds no roadscan output is
    refused (InputError), never replaced.

    Parameters
    ----------
    target : str or Path
        The folder to replace.

    Returns
    -------
    contextmanager
        Yielding the temporary folder.
    """
    from roadscan.io.atomic import atomic_output_dir

    return atomic_output_dir(target)


def campaign_leftovers(out):
    """What a campaign killed at any moment (``kill -9`` while its cluster starts, while workers
    write, while the table is written) can leave in ``out``: hidden temporary and set-aside scan
    folders (``.<name>.roadscan-tmp-*``, ``.<name>.roadscan-old-*``,
    :func:`roadscan.io.atomic.atomic_output_dir`), the temporary files of the campaign table
    and report (``.campaign.XXXXXXXX.csv``...) and the report's figures before they are
    embedded (``.campaign_distributions.png``). -> sorted list of paths.

    Parameters
    ----------
    out : str or Path
        The campaign folder.

    Returns
    -------
    list of Path
    """
    from roadscan.io.atomic import OLD_TAG, TMP_TAG

    out = Path(out)
    try:
        entries = list(out.iterdir())
    except OSError:
        return []
    found = []
    for p in entries:
        name = p.name
        if not name.startswith("."):
            continue
        if (TMP_TAG in name or OLD_TAG in name) and p.is_dir() and not p.is_symlink():
            found.append(p)
        elif _TEMP_FILE.match(name) and p.is_file() and not p.is_symlink():
            found.append(p)
    return sorted(found)


def _target_of(p):
    """``.s0.roadscan-tmp-ab12`` -> ``s0`` (the scan folder it was written for)."""
    from roadscan.io.atomic import OLD_TAG, TMP_TAG

    name = p.name[1:]
    for tag in (TMP_TAG, OLD_TAG):
        if tag in name:
            return p.parent / name.split(tag, 1)[0]
    return None


def recover_campaign(out):
    """Clean what a killed campaign left in ``out`` (:func:`campaign_leftovers`): a scan's old
    folder that was set aside and not yet replaced is put back, hidden temporary folders are
    deleted unless a live writer still holds them (``flock``), temporary files of the table and
    report are deleted. A half-written scan result is never kept: only a folder swapped in
    whole (with its sidecar) counts as done. -> list of the names removed or put back.

    Parameters
    ----------
    out : str or Path
        The campaign folder.

    Returns
    -------
    list
        What was done.
    """
    from roadscan.io.atomic import recover_output_dir

    done = []
    for p in campaign_leftovers(out):
        target = _target_of(p)
        try:
            if target is not None:
                recover_output_dir(target)
            else:
                p.unlink()
        except FileNotFoundError:
            pass
        except OSError:
            continue
        if not os.path.lexists(p):
            done.append(p.name)
    return done


def earlier_campaign(out):
    """True when ``out`` holds an earlier campaign, finished or killed: a scan folder with its
    sidecar, the campaign table roadscan writes, or nothing but what a killed campaign leaves
    (:func:`campaign_leftovers`: a campaign killed while its cluster started or its first scans
    were written has no finished scan yet).

    Parameters
    ----------
    out : str or Path
        The folder.

    Returns
    -------
    bool
    """
    out = Path(out)
    try:
        entries = list(out.iterdir())
    except OSError:
        return False
    if any((p / SIDECAR).is_file() for p in entries if p.is_dir()):
        return True
    from roadscan.io.overwrite_guard import untracked

    try:
        # our own earlier table, not an input: --resume replaces it (a campaign stopped before
        # any scan finished has no sidecar, only this; tracked, the read made the new
        # campaign.csv "replace an input": exit 2)
        with untracked(), open(out / "campaign.csv", encoding="utf-8") as fh:
            if fh.readline().startswith("file,label,chainage_m,status"):
                return True
    except (OSError, UnicodeDecodeError):
        pass
    left = set(campaign_leftovers(out))
    return bool(entries) and all(p in left for p in entries)


def sha256_of(path, chunk=1 << 20):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(chunk), b""):
            h.update(block)
    return h.hexdigest()


def file_identity(path, with_hash=True):
    """``{"path", "size", "mtime_ns"[, "sha256"]}`` of an input file.

    Parameters
    ----------
    path : str or Path
        The input file.
    with_hash : bool, optional
        Include its SHA-256.

    Returns
    -------
    dict
    """
    st = os.stat(path)
    out = {"path": str(Path(path).resolve()), "size": st.st_size, "mtime_ns": st.st_mtime_ns}
    if with_hash:
        out["sha256"] = sha256_of(path)
    return out


def same_input(path, recorded):
    """True when ``path`` is the input recorded: same size and, unless the mtime is also the
    same, the same SHA-256 (a copied or touched but unchanged file still counts as unchanged).

    Parameters
    ----------
    path : str or Path
        The input file now.
    recorded : dict
        Its :func:`file_identity` then.

    Returns
    -------
    bool
    """
    try:
        now = file_identity(path, with_hash=False)
    except OSError:
        return False
    if now["size"] != recorded.get("size"):
        return False
    if now["mtime_ns"] == recorded.get("mtime_ns"):
        return True
    return recorded.get("sha256") is not None and sha256_of(path) == recorded["sha256"]


def options_fingerprint(options):
    """A stable hash of the options that change a scan's outputs (a dict of plain values).

    Parameters
    ----------
    options : dict
        Plain values.

    Returns
    -------
    str
        16 hex digits.
    """
    text = json.dumps(options, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def write_sidecar(folder, identity, fingerprint, records):
    """Write a scan folder's sidecar (input identity, options fingerprint, records) for ``--resume``.

    Parameters
    ----------
    folder : str or Path
        The scan's folder.
    identity : dict
        :func:`file_identity` of the input.
    fingerprint : str
        :func:`options_fingerprint`.
    records : list of dict
        The scan's campaign rows.

    Returns
    -------
    None
    """
    data = {"input": identity, "options": fingerprint, "records": records}
    (Path(folder) / SIDECAR).write_text(json.dumps(data, default=_plain), encoding="utf-8")


def read_sidecar(folder):
    """The sidecar of a scan folder (see :func:`write_sidecar`), or None when missing or unreadable.

    Parameters
    ----------
    folder : str or Path
        The scan's folder.

    Returns
    -------
    dict or None
    """
    from roadscan.io.overwrite_guard import untracked

    try:
        with untracked():  # our own earlier output, not an input (a rerun replaces it)
            return json.loads((Path(folder) / SIDECAR).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _plain(obj):
    try:
        import numpy as np

        if isinstance(obj, np.generic):
            return obj.item()
    except ImportError:  # pragma: no cover
        pass
    return str(obj)
