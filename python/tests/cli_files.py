"""Reading the analysis commands' CSV files (``#`` provenance lines, then a header, then
rows) and comparing numbers bit for bit."""

import numpy as np


def same_bits(a, b) -> bool:
    """Equal as float64 bit patterns (tells 0.0 from -0.0; NaN equals itself)."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def first_difference(a, b) -> str:
    """Where two arrays first differ, for assertion messages."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if a.shape != b.shape:
        return f"shapes {a.shape} vs {b.shape}"
    k = int(np.argmax(a.view(np.uint64) != b.view(np.uint64)))
    return f"first at {k}: CLI {a[k]!r} vs Python {b[k]!r}"


def read(path):
    """(provenance lines without '# ', header names, {name: float64 column}). Python's float
    parsing rounds correctly and the CSV holds shortest round-trip digits, so the columns are
    the command's f64 values exactly."""
    lines = path.read_text().splitlines()
    provenance = [l[2:] for l in lines if l.startswith("# ")]
    body = [l for l in lines if not l.startswith("#")]
    names = body[0].split(",")
    rows = [r.split(",") for r in body[1:]]
    columns = {}
    for k, n in enumerate(names):
        values = [r[k] for r in rows]
        try:
            columns[n] = np.array([float(v) for v in values], dtype=np.float64)
        except ValueError:
            columns[n] = values  # a text column (the verdict)
    return provenance, names, columns


def provenance_lines(p) -> "list[str]":
    """A provenance dict as the command's ``#`` lines (src/simulation/provenance.rs, `lines`),
    without the version line; the values here need no escaping."""
    lines = [f"model {p['model']['path']} sha256 {p['model']['sha256']}"]
    lines += [f"set {o}" for o in p["model"]["overrides"]]
    lines += [f"{k} = {v}" for k, v in sorted(p["settings"].items())]
    return lines


def without_version(lines):
    """The binary and the extension may be built at different commits of a working tree."""
    return [l for l in lines if not l.startswith("linkdyn ")]
