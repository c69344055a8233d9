"""Hypothesis strategies for odd input files (issue 14 fuzz suite): height files of every format
roadscan reads, spectra, rubber files, measured friction, raw DMA sweeps, manifests.

Each strategy gives a :class:`FileSpec` (name, bytes, a short description that hypothesis prints
for a failing case). Height data come from :func:`height_arrays`: rough fields and the odd ones
(constant, all-NaN, 2 measured points, inf, denormals, 1e300 spikes, 1-row/1-column/2x2/empty/3-D
grids, integer/bool/complex/string/object dtypes). Files are then often mutated: truncated,
bytes flipped, garbage appended or prepended, emptied, or replaced by random bytes.
"""

from __future__ import annotations

import io
import json
import re
import struct
import tempfile
import warnings
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from hypothesis import strategies as st

SAMPLES = Path(__file__).resolve().parents[1] / "sample_scans"


@dataclass(frozen=True)
class FileSpec:
    name: str
    data: bytes
    desc: str

    def write(self, folder):
        p = Path(folder) / self.name
        p.write_bytes(self.data)
        return p

    def __repr__(self):
        return f"FileSpec({self.name!r}, {len(self.data)} bytes: {self.desc})"


@dataclass(frozen=True)
class Arr:
    array: np.ndarray
    desc: str

    def __repr__(self):
        return f"Arr({self.desc})"


# ------------------------------------------------------------------------------ numbers
ODD_TOKENS = [
    "0",
    "-0",
    "-1",
    "1",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e-300",
    "5e-324",
    "2.2e-308",
    "1e300",
    "1e308",
    "1e309",
    "-1e309",
    "",
    " ",
    "abc",
    "1_000",
    "0x10",
    "1e",
    "1..2",
    "+5",
    " 7 ",
    "1,5",
    "½",
    "None",
    "True",
    "1e-12",
    "1e12",
    "-1e-9",
    "3.4e38",
]


def tokens(typical, odd_weight=1):
    """A flag value: one of ``typical`` (as often as the odd ones), an odd token, or a random
    float (any, including NaN, inf, denormals) printed by repr or %g."""
    odd = st.one_of(
        st.sampled_from(ODD_TOKENS),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.floats(-1e6, 1e6).map(lambda x: f"{x:.4g}"),
    )
    return st.one_of(*([st.sampled_from(list(typical))] * max(1, 3 - odd_weight)), odd)


ODD = st.one_of(
    st.sampled_from(ODD_TOKENS),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.floats(-1e6, 1e6).map(lambda x: f"{x:.4g}"),
)


def F(typical, odd=(), absent=2):
    """A flag for :func:`flagset`: typical values, flag-specific odd values (besides :data:`ODD`),
    and the weight of leaving it out (0: always given)."""
    return (list(typical), list(odd), absent)


@st.composite
def flagset(draw, specs, odd_counts=(0, 1, 1, 1, 2)):
    """Values for a command's flags: each present with a typical value or absent, then 0-2 of
    them (most often one) made odd, so that most cases reach past the first check."""
    vals = {}
    for k, (typ, _, absent) in specs.items():
        vals[k] = draw(st.sampled_from(typ)) if absent == 0 or draw(st.integers(0, absent)) == 0 else None
    n = min(draw(st.sampled_from(list(odd_counts))), len(specs))
    for k in draw(st.lists(st.sampled_from(sorted(specs)), min_size=n, max_size=n, unique=True)):
        typ, odd, _ = specs[k]
        if all(isinstance(t, bool) for t in typ):
            vals[k] = True
        else:
            vals[k] = draw(st.one_of(st.sampled_from(odd), ODD) if odd else ODD)
    return vals


def maybe(strategy, p_none=2):
    """None (flag absent) or a value; ``p_none`` None-branches against one value branch."""
    return st.one_of(*([st.none()] * p_none), strategy)


# ------------------------------------------------------------------------------ height data
def _rough(rng, shape):
    if len(shape) == 2 and min(shape) > 0:
        a = np.cumsum(rng.standard_normal(shape), axis=1) + np.cumsum(rng.standard_normal(shape[:1]))[:, None]
        a += 0.3 * np.cumsum(rng.standard_normal(shape), axis=0)
    else:
        a = np.cumsum(rng.standard_normal(shape)) if len(shape) == 1 else rng.standard_normal(shape)
    a = np.asarray(a, dtype=float)
    if a.size:
        a -= a.mean()
        s = a.std()
        a = a / s if s > 0 else a
    return a


SHAPES = st.one_of(
    st.tuples(st.integers(8, 48), st.integers(8, 48)),
    st.tuples(st.integers(8, 48), st.integers(8, 48)),
    st.tuples(st.integers(8, 48), st.integers(8, 48)),
    st.sampled_from(
        [(1, 40), (40, 1), (2, 2), (3, 3), (7, 9), (8, 8), (0, 5), (5, 0), (1, 1), (2, 64), (64, 2), (9, 7)]
    ),
    st.sampled_from([(40,), (3,), (0,), (200,), (), (3, 4, 5), (16, 16, 1)]),
)
VALUE_KINDS = ["rough"] * 6 + [
    "constant",
    "zero",
    "nan_most",
    "nan_all",
    "two_measured",
    "inf",
    "neg_inf",
    "spike",
    "denormal",
    "huge",
    "tiny",
    "steps",
    "ramp",
    "nan_rows",
    "one_value_off",
]
SCALES = [1e-4, 1e-4, 1e-4, 1e-3, 1e-5, 1e-6, 1.0, 30.0, 1e-12, 1e-300, 1e30, 5e-324]
DTYPES = ["<f8"] * 6 + ["<f4", "<f2", ">f8", "<i2", "<i4", "<i8", "|u1", "<u8", "|b1", "<c16", "<U4", "|O"]


@st.composite
def height_arrays(draw, shapes=SHAPES, kinds=VALUE_KINDS, dtypes=DTYPES, scales=SCALES):
    shape = tuple(draw(shapes))
    kind = draw(st.sampled_from(kinds))
    scale = draw(st.sampled_from(scales))
    dtype = draw(st.sampled_from(dtypes))
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    with np.errstate(all="ignore"):
        a = np.array(_rough(rng, shape) * scale, dtype=float)
        flat = a.reshape(-1)
        n = flat.size
        if kind == "constant":
            a[...] = scale
        elif kind == "zero":
            a[...] = 0.0
        elif kind == "nan_most" and n:
            flat[rng.random(n) < 0.97] = np.nan
        elif kind == "nan_all":
            a[...] = np.nan
        elif kind == "two_measured" and n:
            keep = flat[:2].copy()
            flat[:] = np.nan
            flat[rng.choice(n, min(2, n), replace=False)] = keep[: min(2, n)]
        elif kind in ("inf", "neg_inf") and n:
            flat[rng.integers(n)] = np.inf if kind == "inf" else -np.inf
        elif kind == "spike" and n:
            flat[rng.integers(n)] = 1e300
        elif kind == "denormal":
            a = np.where(rng.random(shape) < 0.5, 5e-324, 1e-310) if shape else np.float64(5e-324)
        elif kind == "huge":
            a = a / max(scale, 1e-300) * 1e300
        elif kind == "tiny":
            a = a / max(scale, 1e-300) * 1e-30
        elif kind == "steps":
            a = np.round(a / max(scale, 1e-300)) * scale
        elif kind == "ramp" and len(shape) == 2:
            a = a * 0 + np.arange(shape[1]) * scale
        elif kind == "nan_rows" and len(shape) == 2 and shape[0]:
            a[::2] = np.nan
        elif kind == "one_value_off" and n:
            a[...] = 1e-3
            flat = a.reshape(-1)
            flat[rng.integers(n)] = 2e-3
        if dtype[1] in "iub":
            a = np.nan_to_num(
                np.asarray(a) / (scale if scale > 1e-200 else 1.0) * 100, nan=0, posinf=0, neginf=0
            )
            a = np.clip(a, -1e4, 1e4)
        if dtype == "<U4":
            arr = np.asarray(a).astype(str).astype("<U4")
        elif dtype == "|O":
            arr = np.asarray(a).astype(object)
        elif dtype == "<c16":
            arr = np.asarray(a) + 1j * np.asarray(a)
        else:
            arr = np.asarray(a).astype(np.dtype(dtype))
    return Arr(arr, f"{kind} shape={shape} scale={scale:g} dtype={dtype} seed={seed}")


def good_arrays(side=(16, 40)):
    """Mostly analysable grids: rough float64 with odd scales/NaN patterns but valid shapes."""
    return height_arrays(
        shapes=st.tuples(st.integers(*side), st.integers(*side)),
        kinds=["rough"] * 8 + ["nan_rows", "steps", "spike", "one_value_off", "nan_most", "constant", "inf"],
        dtypes=["<f8"] * 6 + ["<f4", "<i4", ">f8"],
        scales=[1e-4, 1e-4, 3e-4, 1e-3, 1e-5, 2e-6, 1e-2],
    )


# ------------------------------------------------------------------------------ mutations
MUTATIONS = ["none"] * 6 + ["truncate", "flip", "append", "prepend", "empty", "random", "zero_tail"]


@st.composite
def mutate(draw, data, mutations=MUTATIONS):
    m = draw(st.sampled_from(mutations))
    n = len(data)
    if m == "none":
        return data, ""
    if m == "truncate":
        k = draw(st.integers(0, max(n - 1, 0)))
        return data[:k], f", truncated at {k}/{n}"
    if m == "flip" and n:
        b = bytearray(data)
        spots = draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=8))
        for i in spots:
            b[i] ^= draw(st.integers(1, 255))
        return bytes(b), f", bytes flipped at {spots}"
    if m == "append":
        return data + draw(st.binary(min_size=1, max_size=200)), ", garbage appended"
    if m == "prepend":
        return draw(st.binary(min_size=1, max_size=64)) + data, ", garbage prepended"
    if m == "empty":
        return b"", ", emptied"
    if m == "zero_tail" and n:
        k = draw(st.integers(0, n - 1))
        return data[:k] + bytes(n - k), f", zeroed from {k}"
    return draw(st.binary(min_size=1, max_size=2000)), ", random bytes"


# ------------------------------------------------------------------------------ height formats
def _npy_header(descr, fortran, shape):
    hdr = f"{{'descr': {descr!r}, 'fortran_order': {fortran!r}, 'shape': {shape!r}, }}"
    hdr += " " * ((64 - (10 + len(hdr) + 1) % 64) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(hdr)) + hdr.encode("latin1")


@st.composite
def npy_files(draw, arrays=height_arrays(), mutations=MUTATIONS, edits=True):
    a = draw(arrays)
    buf = io.BytesIO()
    np.save(buf, a.array, allow_pickle=True)
    data = buf.getvalue()
    edit = draw(st.sampled_from(["none"] * 4 + ["shape", "descr", "garbage_header"])) if edits else "none"
    desc = f"npy {a.desc}"
    if edit == "shape":
        shape = draw(
            st.sampled_from(
                [
                    (200000, 200000),
                    (2**40,),
                    (2**31, 2**31),
                    (-1, 4),
                    (0, 5),
                    (3,),
                    (1, 1),
                    (2, 2, 2),
                    (2**62, 4),
                    (65536, 65536),
                ]
            )
        )
        raw = np.ascontiguousarray(a.array).tobytes() if a.array.dtype != object else b""
        data = _npy_header(a.array.dtype.str if a.array.dtype != object else "|O", False, shape) + raw
        desc += f", header shape {shape}"
    elif edit == "descr":
        descr = draw(
            st.sampled_from(["<c16", "|O", "<U4", "|V8", ">f8", "<m8", "<M8[D]", "<f16", "xx", "<i1"])
        )
        raw = np.ascontiguousarray(a.array).tobytes() if a.array.dtype != object else b""
        data = _npy_header(descr, draw(st.booleans()), a.array.shape) + raw
        desc += f", header descr {descr}"
    elif edit == "garbage_header":
        junk = draw(
            st.sampled_from(
                [
                    "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), 'x': __import__('os')}",
                    "{'descr':",
                    "[1, 2]",
                    "{'descr': '<f8', 'shape': (3, 4)}",
                    "\x00\x01",
                ]
            )
        )
        data = b"\x93NUMPY\x01\x00" + struct.pack("<H", len(junk)) + junk.encode("latin1") + b"\0" * 96
        desc += f", header {junk[:30]!r}"
    data, how = draw(mutate(data, mutations))
    return FileSpec("scan.npy", data, desc + how)


SPACING_VALUES = [5e-5, 5e-5, 1e-4, 0.0, -1e-4, float("nan"), float("inf"), 1e-300, 1e300, 5e-324]


@st.composite
def npz_files(draw, arrays=height_arrays(), mutations=MUTATIONS, edits=True):
    a = draw(arrays)
    members = {"heights": a.array}
    desc = [f"npz {a.desc}"]
    for key in ("dx", "dy"):
        choice = draw(st.sampled_from(["value", "value", "absent", "array2", "string"])) if edits else "good"
        if choice == "good":
            members[key] = np.float64(5e-5)
        if choice == "value":
            members[key] = np.float64(draw(st.sampled_from(SPACING_VALUES)))
        elif choice == "array2":
            members[key] = np.array([5e-5, 6e-5])
        elif choice == "string":
            members[key] = np.array("5e-5")
        desc.append(f"{key}={members.get(key, 'absent')!r}"[:40])
    um = draw(
        st.sampled_from(
            ["absent", "absent", "ok", "wrong_shape", "float", "all"] if edits else ["absent", "ok"]
        )
    )
    shape = np.shape(a.array)
    if um == "ok":
        members["unmeasured"] = np.random.default_rng(1).random(shape) < 0.1
    elif um == "wrong_shape":
        members["unmeasured"] = np.zeros((3, 3), bool)
    elif um == "float":
        members["unmeasured"] = np.full(shape, 0.5)
    elif um == "all":
        members["unmeasured"] = np.ones(shape, bool)
    if edits and draw(st.booleans()):
        members.pop("heights")
        members["height"] = a.array
        desc.append("key 'height'")
    desc.append(f"unmeasured {um}")
    buf = io.BytesIO()
    (np.savez_compressed if draw(st.booleans()) else np.savez)(buf, **members)
    data, how = draw(mutate(buf.getvalue(), mutations))
    return FileSpec("scan.npz", data, ", ".join(desc) + how)


@st.composite
def tif_files(draw, arrays=height_arrays(dtypes=["<f8", "<f8", "<f4", "<i2", "|u1", "<u8", "<c16", "<f2"])):
    import tifffile

    a = draw(arrays)
    kw = {}
    meta = draw(st.sampled_from(["none", "roadscan", "odd", "tags", "tags_dpi"]))
    sp = draw(st.sampled_from(SPACING_VALUES))
    if meta == "roadscan":
        kw["metadata"] = {"dx_m": sp, "dy_m": 5e-5, "units": draw(st.sampled_from(["m", "mm", "furlong"]))}
    elif meta == "odd":
        kw["metadata"] = draw(
            st.sampled_from(
                [{"dx_m": "abc", "dy_m": None}, {"dx_m": [1, 2], "dy_m": 1}, {"dx_m": 5e-5}, {"units": "um"}]
            )
        )
    elif meta == "tags":
        kw["resolution"] = (draw(st.sampled_from([200.0, 1e-300, 1e300, 1.0])), 200.0)
        kw["resolutionunit"] = "CENTIMETER"
        kw["metadata"] = None
    elif meta == "tags_dpi":
        kw["resolution"] = (72.0, 72.0)
        kw["metadata"] = None
    buf = io.BytesIO()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tifffile.imwrite(buf, a.array, **kw)
        data = buf.getvalue()
    except Exception as exc:  # noqa: BLE001 - tifffile refuses some arrays: then garbage
        data = b"II*\x00" + bytes(64)
        meta += f" (tifffile refused: {type(exc).__name__})"
    data, how = draw(mutate(data))
    return FileSpec(
        draw(st.sampled_from(["scan.tif", "scan.tiff"])), data, f"tif {a.desc} meta={meta} sp={sp}{how}"
    )


_X3P_EDITS = {
    "SizeX": ["0", "-5", "abc", "1e9", "100000", "3", "2.5", ""],
    "SizeY": ["0", "-5", "abc", "200000", "1", ""],
    "SizeZ": ["0", "2", "-1", "abc"],
    "Increment": ["0", "nan", "-1e-4", "inf", "1e300", "abc", "1e-300", ""],
    "DataType": ["I", "L", "F", "X", ""],
    "FeatureType": ["PRF", "PCL", "XXX", ""],
    "AxisType": ["A", "I", "X"],
}


@st.composite
def x3p_files(
    draw,
    arrays=height_arrays(
        dtypes=["<f8"],
        shapes=st.one_of(st.tuples(st.integers(1, 40), st.integers(1, 40)), st.sampled_from([(40,), (2, 2)])),
    ),
    mutations=MUTATIONS,
    edits=True,
):
    from roadscan.heightmap import HeightMap, Profile
    from roadscan.io.x3p import write_x3p

    a = draw(arrays)
    h = np.asarray(a.array, dtype=float)
    desc = f"x3p {a.desc}"
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "a.x3p"
        try:
            obj = HeightMap(h, 5e-5, 5e-5) if h.ndim == 2 else Profile(h, 5e-5)
            with warnings.catch_warnings():  # float32 of 1e300: inf on purpose
                warnings.simplefilter("ignore")
                write_x3p(p, obj, dtype=draw(st.sampled_from(["float64", "float32"])))
            files = {}
            with zipfile.ZipFile(p) as z:
                for n in z.namelist():
                    files[n] = z.read(n)
        except Exception as exc:  # noqa: BLE001
            files = {"main.xml": b"<x/>"}
            desc += f" (not written: {type(exc).__name__})"
    xml = files.get("main.xml", b"").decode("utf-8", "replace")
    xml = re.sub(r"<Date>[^<]*</Date>", "<Date>2021-10-11T00:00:00+00:00</Date>", xml)  # deterministic bytes
    tags = draw(st.lists(st.sampled_from(sorted(_X3P_EDITS)), max_size=3, unique=True)) if edits else []
    for tag in tags:
        val = draw(st.sampled_from(_X3P_EDITS[tag]))
        xml = xml.replace(f"<{tag}>", f"<{tag}>\x00", 1)
        head, _, rest = xml.partition(f"<{tag}>\x00")
        if rest:
            xml = head + f"<{tag}>{val}" + rest[rest.find("<") :]
        desc += f", {tag}={val!r}"
    files["main.xml"] = xml.encode("utf-8")
    if "md5checksum.hex" in files:
        import hashlib

        files["md5checksum.hex"] = f"{hashlib.md5(files['main.xml']).hexdigest()} *main.xml\n".encode()
    drop = (
        draw(st.sampled_from(["none", "none", "none", "md5checksum.hex", "bindata/data.bin", "half_data"]))
        if edits
        else "none"
    )
    if drop == "half_data" and "bindata/data.bin" in files:
        files["bindata/data.bin"] = files["bindata/data.bin"][: len(files["bindata/data.bin"]) // 2]
    elif drop in files:
        files.pop(drop)
    desc += f", dropped {drop}" if drop != "none" else ""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for n, b in files.items():
            z.writestr(zipfile.ZipInfo(n, date_time=(2021, 10, 11, 0, 0, 0)), b, zipfile.ZIP_DEFLATED)
    data, how = draw(mutate(buf.getvalue(), mutations))
    return FileSpec("scan.x3p", data, desc + how)


@st.composite
def gwy_files(
    draw,
    arrays=height_arrays(
        dtypes=["<f8"],
        shapes=st.one_of(
            st.tuples(st.integers(1, 40), st.integers(1, 40)), st.sampled_from([(2, 2), (1, 1)])
        ),
    ),
):
    from gwyfile.objects import GwyContainer, GwyDataField

    a = draw(arrays)
    h = np.ascontiguousarray(np.asarray(a.array, dtype=np.float64))
    xreal = draw(st.sampled_from([1e-3, 1e-3, 0.0, -1e-3, float("nan"), float("inf"), 1e300, 5e-324]))
    uxy = draw(st.sampled_from(["m", "m", "mm", "", "furlong", "µm"]))
    uz = draw(st.sampled_from(["m", "m", "um", "", "nm", "kg", "furlong"]))
    ch = draw(st.sampled_from([0, 0, 3, None]))
    c = GwyContainer()
    desc = f"gwy {a.desc} xreal={xreal} xy={uxy!r} z={uz!r} channel={ch}"
    try:
        if ch is not None:
            c[f"/{ch}/data"] = GwyDataField(
                h, xreal=xreal, yreal=1e-3, si_unit_xy=uxy or None, si_unit_z=uz or None
            )
            c[f"/{ch}/data/title"] = "Height"
        with tempfile.TemporaryDirectory() as d:
            p = Path(d) / "a.gwy"
            c.tofile(str(p))
            data = p.read_bytes()
    except Exception as exc:  # noqa: BLE001 - gwyfile refuses some fields: then garbage
        data = b"GWYP" + bytes(32)
        desc += f" (not written: {type(exc).__name__})"
    data, how = draw(mutate(data))
    return FileSpec("scan.gwy", data, desc + how)


NAN_TOKENS = ["nan", "NaN", "NA", "", "-", "--", "null", "1.#QNAN", "-9999", "*"]
ODD_CELL = ["abc", "1e999", "0x10", "1,5", "½", "∞", "1e", "--3", "١٢", "\x00"]


@st.composite
def _cells(draw, values, edits=True):
    fmt = draw(st.sampled_from(["%.6g", "%r", "%.3e", "%.12g"]))
    nan_tok = draw(st.sampled_from(NAN_TOKENS if edits else ["nan", "NaN"]))
    cells = []
    for v in np.ravel(values):
        v = float(v) if np.isrealobj(v) and np.asarray(v).dtype.kind in "fiub" else np.nan
        cells.append(nan_tok if not np.isfinite(v) else (repr(v) if fmt == "%r" else fmt % v))
    if edits and cells and draw(st.integers(0, 4)) == 0:
        i = draw(st.integers(0, len(cells) - 1))
        cells[i] = draw(st.sampled_from(ODD_CELL))
    return cells


@st.composite
def text_files(
    draw,
    arrays=height_arrays(
        dtypes=["<f8"],
        shapes=st.one_of(
            st.tuples(st.integers(1, 32), st.integers(1, 32)),
            st.sampled_from([(2, 2), (1, 6), (6, 1), (30,)]),
        ),
    ),
    mutations=("none",) * 8 + ("truncate", "flip", "append", "empty"),
    edits=True,
):
    a = draw(arrays)
    h = np.asarray(a.array, dtype=float)
    h2 = h if h.ndim == 2 else h.reshape(1, -1) if h.ndim == 1 else h.reshape(1, 1)
    layout = draw(st.sampled_from(["matrix", "matrix", "esri", "gwyddion", "xyz", "xz", "z"]))
    sep = draw(st.sampled_from([",", ";", "\t", " ", "  "]))
    cells = draw(_cells(h2, edits))
    ny, nx = h2.shape
    rows = [sep.join(cells[i * nx : (i + 1) * nx]) for i in range(ny)]
    header = []
    desc = f"text {layout} {a.desc} sep={sep!r}"
    if layout == "esri":
        ncols = draw(
            st.sampled_from(
                [str(nx)] * 3 + (["100000", "-3", "0", "1.5", "abc", "1e9", str(nx + 1)] if edits else [])
            )
        )
        nrows = draw(
            st.sampled_from([str(ny)] * 3 + (["100000", "-1", "0", "abc", "70000"] if edits else []))
        )
        cell = draw(
            st.sampled_from(
                ["5e-5", "5e-5"] + (["0", "-1", "nan", "abc", "1e300", "1e-300"] if edits else [])
            )
        )
        header = [f"ncols {ncols}", f"nrows {nrows}", "xllcorner 0", "yllcorner 0", f"cellsize {cell}"]
        if draw(st.booleans()):
            header.append(f"NODATA_value {draw(st.sampled_from(['-9999', 'nan', 'abc', '0']))}")
        rows = [" ".join(r.split(sep)) for r in rows]
        desc += f" ncols={ncols} nrows={nrows} cellsize={cell}"
    elif layout == "gwyddion":
        w = draw(
            st.sampled_from(["1.2", "1.2"] + (["0", "-1", "nan", "abc", "1e300", "1e-300"] if edits else []))
        )
        u = draw(st.sampled_from(["mm", "mm", "um", "µm", "m"] + (["furlong", ""] if edits else [])))
        vu = draw(st.sampled_from(["m", "m", "um", "mm"] + (["kg", ""] if edits else [])))
        header = ["# Channel: Height", f"# Width: {w} {u}", f"# Height: {w} {u}", f"# Value units: {vu}"]
        desc += f" width={w} {u} values {vu}"
    elif layout in ("xyz", "xz", "z"):
        step = draw(st.sampled_from([5e-5, 5e-5] + ([0.0, 1e-300, 1e300] if edits else [])))
        jitter = draw(st.sampled_from([0.0, 0.0] + ([0.1, 0.6] if edits else [])))
        rng = np.random.default_rng(3)
        pts = []
        if layout == "xyz":
            for i in range(ny):
                for j in range(nx):
                    pts.append((j * step * (1 + jitter * rng.random()), i * step, h2[i, j]))
            order = draw(st.sampled_from(["rows", "shuffled", "reversed", "dup", "drop_half"]))
        else:
            for j, v in enumerate(h2.ravel()):
                pts.append((j * step * (1 + jitter * rng.random()), v) if layout == "xz" else (v,))
            order = draw(st.sampled_from(["rows", "shuffled", "reversed", "dup"]))
        if order == "shuffled":
            rng.shuffle(pts)
        elif order == "reversed":
            pts = pts[::-1]
        elif order == "dup" and pts:
            pts = pts + pts[:3]
        elif order == "drop_half":
            pts = pts[::2]
        csep = "," if sep in (",", ";") else " "
        rows = [csep.join(draw(_cells(np.array(p), edits))) for p in pts]
        title = draw(
            st.sampled_from(
                [
                    "",
                    "",
                    "x (mm), y (mm), z (um)",
                    "x,y,z",
                    "distance (mm), height (mm)",
                    "x (furlong), z (m)",
                    "z",
                ]
            )
        )
        if title:
            header = [title]
        desc += f" step={step} jitter={jitter} order={order} title={title!r}"
    eol = draw(st.sampled_from(["\n", "\r\n", "\r"]))
    text = eol.join(header + rows) + eol
    if draw(st.integers(0, 6)) == 0:
        text = "\ufeff" + text
    data = text.encode("utf-8")
    data, how = draw(mutate(data, list(mutations)))
    ext = draw(st.sampled_from([".txt", ".csv", ".asc", ".xyz"]))
    return FileSpec("scan" + ext, data, desc + how)


@st.composite
def captif_files(draw):
    n = draw(st.sampled_from([0, 1, 2, 5, 40, 200, 300]))
    rng = np.random.default_rng(draw(st.integers(0, 999)))
    step = draw(st.sampled_from([0.0375, 0.0375, 0.0, -0.0375, 1e-9, 1e300]))
    dist = np.arange(n) * step
    depth = np.cumsum(rng.standard_normal(n)) * draw(st.sampled_from([0.05, 0.05, 0.0, 1e300, 1e-300]))
    odd = draw(
        st.sampled_from(
            [
                "none",
                "none",
                "nan_some",
                "nan_all",
                "swap",
                "dup",
                "irregular",
                "text",
                "missing_col",
                "extra_col",
                "huge_number",
                "no_title",
            ]
        )
    )
    rows = []
    for i in range(n):
        d, z = dist[i], depth[i]
        if odd == "nan_some" and rng.random() < 0.3:
            z = float("nan")
        if odd == "nan_all":
            z = float("nan")
        if odd == "irregular":
            d = d + rng.random() * step
        rows.append([f"{i + 1:.3f}", f"{d:.3f}", f"{z:.3f}" if np.isfinite(z) else "NaN"])
    if odd == "swap" and n > 3:
        rows[1], rows[2] = rows[2], rows[1]
        rows[1][1], rows[2][1] = rows[2][1], rows[1][1]
    if odd == "dup" and n > 3:
        rows.insert(2, list(rows[2]))
    if odd == "text" and n:
        rows[n // 2][2] = "abc"
    if odd == "missing_col" and n:
        rows[n // 2] = rows[n // 2][:2]
    if odd == "extra_col" and n:
        rows[n // 2] = rows[n // 2] + ["7"]
    if odd == "huge_number" and n:
        rows[n // 2][1] = "1e308"
    head = ["Road Name\tCAPTIF\t", "Ref Station\t0\t", "Date\t11/10/2021\t", "*****DATA*****\t\t"]
    if odd != "no_title":
        head.append("Data Point No:\tDistance (mm)\tDepth (mm)")
    eol = draw(st.sampled_from(["\r\n", "\n"]))
    data = (eol.join(head + ["\t".join(r) for r in rows]) + eol).encode()
    data, how = draw(mutate(data, ["none"] * 8 + ["truncate", "flip", "append"]))
    return FileSpec("station.dat", data, f"captif n={n} step={step} odd={odd}{how}")


VENDOR_EXTS = [
    ".plu",
    ".plux",
    ".sur",
    ".sdf",
    ".vk4",
    ".opd",
    ".al3d",
    ".zmg",
    ".datx",
    ".zon",
    ".os3d",
    ".nms",
    ".tmd",
    ".sflz",
    ".lext",
    ".oir",
    ".hdat",
    ".fits",
    ".dat",
    ".di",
    ".ibw",
    ".mi",
    ".opdx",
    ".sdf",
    ".x3d",
]
_VENDOR_SAMPLES = Path("/work/shared/data/formats")


@st.composite
def vendor_files(draw):
    """Garbage bytes (or a real vendor file cut short) with a vendor extension."""
    ext = draw(st.sampled_from(VENDOR_EXTS))
    real = (
        sorted(p for p in _VENDOR_SAMPLES.glob("*") if p.suffix in VENDOR_EXTS)
        if _VENDOR_SAMPLES.is_dir()
        else []
    )
    if real and draw(st.booleans()):
        src = draw(st.sampled_from(real))
        raw = src.read_bytes()
        k = draw(st.integers(0, min(len(raw), 4096)))
        data = raw[:k]
        return FileSpec("scan" + src.suffix, data, f"vendor {src.name} cut at {k}")
    data = draw(st.binary(min_size=0, max_size=3000))
    return FileSpec("scan" + ext, data, f"vendor garbage {len(data)} bytes")


def any_height_file():
    return st.one_of(
        npy_files(),
        npz_files(),
        tif_files(),
        x3p_files(),
        gwy_files(),
        text_files(),
        captif_files(),
        vendor_files(),
    )


def analysable_height_file():
    """Height files that mostly read: odd data in valid containers, mutated rarely."""
    rare = ["none"] * 12 + ["truncate", "flip"]
    return st.one_of(
        npy_files(arrays=good_arrays(), mutations=rare, edits=False),
        npz_files(arrays=good_arrays(), mutations=rare, edits=False),
        x3p_files(arrays=good_arrays(), mutations=rare, edits=False),
        text_files(arrays=good_arrays((8, 24)), mutations=rare, edits=False),
    )


# ------------------------------------------------------------------------------ other inputs
def _csv(draw, header, rows, name, desc):
    eol = draw(st.sampled_from(["\n", "\n", "\r\n"]))
    text = eol.join(([header] if header else []) + rows) + eol
    if draw(st.integers(0, 6)) == 0:
        text = "\ufeff" + text
    data, how = draw(mutate(text.encode(), ["none"] * 10 + ["truncate", "flip", "append", "empty"]))
    return FileSpec(name, data, desc + how)


ROW_EDITS = ["none"] * 4 + [
    "negative",
    "nan",
    "zero",
    "inf",
    "dup_x",
    "reverse",
    "one_row",
    "two_rows",
    "text",
    "huge",
    "tiny",
    "extra_col",
    "missing_col",
    "blank_lines",
    "rising",
]


def _edit_rows(draw, table, rng):
    edit = draw(st.sampled_from(ROW_EDITS))
    t = [list(r) for r in table]
    n = len(t)
    i = int(rng.integers(n)) if n else 0
    col = int(rng.integers(1, len(t[0]))) if n and len(t[0]) > 1 else 0
    if not n:
        return t, edit
    if edit == "negative":  # a cell may already be text (a generator's)
        v = t[i][col]
        t[i][col] = -abs(v) if isinstance(v, (int, float)) else f"-{v}"
    elif edit == "nan":
        t[i][col] = float("nan")
    elif edit == "zero":
        t[i][col] = 0.0
    elif edit == "inf":
        t[i][col] = float("inf")
    elif edit == "dup_x" and n > 2:
        t[i + 1 if i + 1 < n else i - 1][0] = t[i][0]
    elif edit == "reverse":
        t = t[::-1]
    elif edit == "one_row":
        t = t[:1]
    elif edit == "two_rows":
        t = t[:2]
    elif edit == "text":
        t[i][col] = "abc"
    elif edit == "huge":
        t[i][col] = 1e300
    elif edit == "tiny":
        t[i][col] = 1e-300
    elif edit == "extra_col":
        t[i] = t[i] + [1.0]
    elif edit == "missing_col":
        t[i] = t[i][:-1]
    elif edit == "blank_lines":
        t.insert(i, [])
    elif edit == "rising" and len(t[0]) >= 2:
        t = [[r[0], 1e-30 * float(r[0]) ** 3] + list(r[2:]) if not isinstance(r[0], str) else r for r in t]
    return t, edit


def _fmt_rows(table):
    return [",".join(str(c) for c in r) for r in table]


@st.composite
def psd_csv_files(draw):
    rng = np.random.default_rng(draw(st.integers(0, 999)))
    n = draw(st.sampled_from([30, 30, 8, 3, 2, 1, 0]))
    q = np.geomspace(1e3, 1e5, n) if n else np.array([])
    H = draw(st.sampled_from([0.8, 0.8, 0.5, 0.0, 1.5, -0.5]))
    C = 1e-22 * (q / 1e3) ** (-2 * (1 + H)) * np.exp(0.1 * rng.standard_normal(n))
    table, edit = _edit_rows(draw, [[a, b] for a, b in zip(q, C)], rng)
    header = draw(
        st.sampled_from(["q_per_m,C_m4"] * 4 + ["q,C", "", "q_per_m;C_m4", "C_m4,q_per_m", "a,b,c"])
    )
    return _csv(draw, header, _fmt_rows(table), "psd.csv", f"psd n={n} H={H} edit={edit} header={header!r}")


@st.composite
def measured_csv_files(draw):
    rng = np.random.default_rng(draw(st.integers(0, 999)))
    n = draw(st.sampled_from([20, 20, 12, 5, 3, 1, 0]))
    one_speed = draw(st.integers(0, 5)) == 0
    v = np.full(n, 0.01) if one_speed else np.geomspace(1e-4, 1e1, n)
    mu = 0.3 + 0.5 * np.exp(-(np.log10(v / 1e-2) ** 2)) + 0.02 * rng.standard_normal(n)
    cols = draw(
        st.sampled_from(["v_m_per_s,mu", "v_m_per_s,mu", "v_m_per_s,mu,T0_C,sigma0_Pa,condition", "v,mu"])
    )
    extra = cols.count(",") - 1
    table = [[a, b] + ([20.0, 2e5, "dry"] if extra else []) for a, b in zip(v, mu)]
    table, edit = _edit_rows(draw, table, rng)
    return _csv(
        draw, cols, _fmt_rows(table), "measured.csv", f"measured n={n} one_speed={one_speed} edit={edit}"
    )


def _sample_rows(path, skip):
    lines = path.read_text(encoding="utf-8-sig").splitlines()
    head, body = lines[:skip], lines[skip:]
    table = []
    for ln in body:
        parts = [p.strip() for p in ln.split(",")]
        try:
            table.append([float(p) for p in parts])
        except ValueError:
            continue
    return head, table


@st.composite
def master_curve_files(draw):
    head, table = _sample_rows(SAMPLES / "rubbers" / "freq_user_master.csv", 2)
    rng = np.random.default_rng(draw(st.integers(0, 999)))
    table = table[:: draw(st.sampled_from([1, 4, 16]))]
    table, edit = _edit_rows(draw, table, rng)
    hdr = draw(
        st.sampled_from(
            ["\n".join(head)] * 3
            + ["f,E_stor,E_loss", "f_Hz,E_stor_MPa,E_loss_MPa", "f, E_stor, E_loss\nHz, kg, MPa", ""]
        )
    )
    return _csv(draw, hdr, _fmt_rows(table), "master.csv", f"master curve edit={edit} header={hdr[:30]!r}")


@st.composite
def shift_table_files(draw):
    kind = draw(st.sampled_from(["table", "table", "wlf_row"]))
    rng = np.random.default_rng(draw(st.integers(0, 999)))
    if kind == "wlf_row":
        vals = [
            draw(st.sampled_from(["8.86", "8.86", "0", "-5", "nan", "1e300", "abc"])),
            draw(st.sampled_from(["51.5", "51.5", "0", "-51.5", "nan", "inf"])),
            draw(st.sampled_from(["20", "20", "-300", "nan", "1e6"])),
        ]
        return _csv(draw, "C1,C2_K,T_s_C", [",".join(vals)], "shift.csv", f"shift wlf {vals}")
    head, table = _sample_rows(SAMPLES / "rubbers" / "freq_user_master__shift_factors.csv", 2)
    table, edit = _edit_rows(draw, table, rng)
    hdr = draw(st.sampled_from(["\n".join(head)] * 3 + ["T_C,aT", "T_C,log10_aT", "T [K],log10_aT", "x,y"]))
    return _csv(draw, hdr, _fmt_rows(table), "shift.csv", f"shift table edit={edit} header={hdr[:20]!r}")


@st.composite
def raw_dma_files(draw):
    head, table = _sample_rows(SAMPLES / "rubbers" / "freq_user_raw.csv", 2)
    rng = np.random.default_rng(draw(st.integers(0, 999)))
    sub = draw(st.sampled_from(["all", "all", "one_T", "two_T", "few"]))
    if sub == "one_T":
        table = [r for r in table if r[4] == table[0][4]]
    elif sub == "two_T":
        sets = sorted({r[4] for r in table})[:2]
        table = [r for r in table if r[4] in sets]
    elif sub == "few":
        table = table[::25]
    table, edit = _edit_rows(draw, table, rng)
    hdr = draw(
        st.sampled_from(
            ["\n".join(head)] * 3
            + ["f,E_stor,E_loss,T,Set", "f,E_stor,E_loss,T,Set\nHz, kg, MPa, C, -", "f,E_stor,E_loss"]
        )
    )
    return _csv(draw, hdr, _fmt_rows(table), "raw.csv", f"raw DMA {sub} edit={edit} header={hdr[:25]!r}")


def _toml_value(draw, typical):
    return draw(
        st.sampled_from(
            list(typical) * 3 + ["0", "-1", "nan", "inf", "-inf", "1e300", "1e-300", '"abc"', "[]", "true"]
        )
    )


@st.composite
def rubber_toml_files(draw):
    model = draw(st.sampled_from(["sls", "sls", "prony", "master_curve", "unknown"]))
    lines = [f'model = "{model}"']
    if draw(st.integers(0, 3)):
        lines.append(f"T_ref_C = {_toml_value(draw, ['60.0', '20'])}")
    if model in ("sls", "unknown"):
        lines.append("[sls]")
        for k, typ in (("E1_Pa", ["1e9"]), ("a1", ["1000.0"]), ("tau_s", ["1e-3"])):
            if draw(st.integers(0, 5)):
                lines.append(f"{k} = {_toml_value(draw, typ)}")
    elif model == "prony":
        moduli = ["[3.0e7, 2.0e8, 5.0e8]"] * 3 + ["[]", "[1e7]", "[-1e7, 1e8, 1e9]", "[nan, 1, 2]"]
        times = ["[1e-2, 1e-5, 1e-8]"] * 3 + ["[1e-2]", "[0, 1, 2]", "[inf, 1, 2]"]
        lines += [
            "[prony]",
            f"E_inf_Pa = {_toml_value(draw, ['1.0e6'])}",
            f"E_i_Pa = {draw(st.sampled_from(moduli))}",
            f"tau_i_s = {draw(st.sampled_from(times))}",
        ]
    else:
        lines += [
            "[master_curve]",
            f'file = "{draw(st.sampled_from(["master.csv", "missing.csv", "../master.csv", ""]))}"',
        ]
    shift = draw(st.sampled_from(["absent", "wlf", "wlf", "none", "table", "odd"]))
    if shift == "wlf":
        lines += [
            "[shift]",
            'kind = "wlf"',
            f"C1 = {_toml_value(draw, ['8.86'])}",
            f"C2_K = {_toml_value(draw, ['51.5'])}",
            f"T_s_C = {_toml_value(draw, ['20.0'])}",
        ]
        if draw(st.booleans()):
            lines.append(f"T_g_C = {_toml_value(draw, ['-30.0'])}")
    elif shift == "none":
        lines += ["[shift]", 'kind = "none"']
    elif shift == "table":
        lines += [
            "[shift]",
            'kind = "table"',
            f"T_C = {draw(st.sampled_from(['[-20, -5, 20, 50]', '[20]', '[20, 20, 30]', '[]']))}",
            f"log10_aT = {draw(st.sampled_from(['[2.58, 0, -3.5, -6.9]', '[0]', '[0, 1, nan]', '[1, 2]']))}",
        ]
    elif shift == "odd":
        lines += ["[shift]", f'kind = "{draw(st.sampled_from(["wlf2", "", "table"]))}"']
    if draw(st.integers(0, 4)) == 0:
        lines += [
            "[thermal]",
            f"rho_kg_m3 = {_toml_value(draw, ['1200.0'])}",
            f"c_v_J_kgK = {_toml_value(draw, ['1500.0'])}",
            f"conductivity_W_mK = {_toml_value(draw, ['0.25'])}",
        ]
    if draw(st.integers(0, 8)) == 0:
        lines.append(draw(st.sampled_from(["unknown_key = 1", "[sls", "model = ", "= 3"])))
    text = "\n".join(lines) + "\n"
    data, how = draw(mutate(text.encode(), ["none"] * 12 + ["truncate", "flip"]))
    return FileSpec("rubber.toml", data, f"rubber {model} shift={shift}: " + " | ".join(lines[1:6]) + how)


def json_dumps_safe(obj):
    return json.dumps(obj, default=str)
