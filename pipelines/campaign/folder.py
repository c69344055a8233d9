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
from pathlib import Path

__all__ = ["atomic_folder", "SIDECAR", "file_identity", "same_input", "read_sidecar",
           "write_sidecar", "options_fingerprint"]

SIDECAR = ".roadscan-batch.json"


def atomic_folder(target):
    """Context manager yielding a fresh temporary folder beside ``target`` that replaces
    ``target`` when the block succeeds (:func:`roadscan.io.atomic.atomic_output_dir`: the
    target is always either the complete old set or the complete new one, even after
    ``kill -9``; on an exception, KeyboardInterrupt included, the temporary folder is removed
    and ``target`` is left as it was). An existing ``target`` that holds no roadscan output is
    refused (InputError), never replaced."""
    from roadscan.io.atomic import atomic_output_dir

    return atomic_output_dir(target)


def sha256_of(path, chunk=1 << 20):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(chunk), b""):
            h.update(block)
    return h.hexdigest()


def file_identity(path, with_hash=True):
    """``{"path", "size", "mtime_ns"[, "sha256"]}`` of an input file."""
    st = os.stat(path)
    out = {"path": str(Path(path).resolve()), "size": st.st_size, "mtime_ns": st.st_mtime_ns}
    if with_hash:
        out["sha256"] = sha256_of(path)
    return out


def same_input(path, recorded):
    """True when ``path`` is the input recorded: same size and, unless the mtime is also the
    same, the same SHA-256 (a copied or touched but unchanged file still counts as unchanged)."""
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
    """A stable hash of the options that change a scan's outputs (a dict of plain values)."""
    text = json.dumps(options, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def write_sidecar(folder, identity, fingerprint, records):
    data = {"input": identity, "options": fingerprint, "records": records}
    (Path(folder) / SIDECAR).write_text(json.dumps(data, default=_plain), encoding="utf-8")


def read_sidecar(folder):
    try:
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
