"""Load isola's results into pandas with proper dtypes.

A session's results live in ``SESSION.results/``; each complete analysis ``A`` has its
main table ``A.csv``, the tables beside it (``A.points.csv``, ``A.outcomes.csv``,
``A.attractors.csv``, a sweep's ``A.jumps.csv``, ...) and ``A.manifest.json``, which lists every file with its
SHA-256 and records what the result was computed from.

    import isola_results
    tables = isola_results.load("sessions/fig04_response_adr06.results", "response")
    tables["response"]          # the periodic responses, one row each
    tables["points"]            # their stroboscopic points, one row per point
    tables["outcomes"]          # per omega: shares of periodic, non-periodic, collision
    tables.manifest["computed_from"]["model"]

Integers are pandas' nullable ``Int64``, flags ``boolean``, labels ``string``, the rest
``float64`` (empty cells are missing values). Only the standard library and pandas are
needed: copy this file next to a notebook, or put its folder on ``sys.path``.

A result is loaded only if it is what its session would compute now: with the session file
beside the folder (``S.toml`` for ``S.results``) and an ``isola`` executable (the ``ISOLA``
environment variable, else ``isola`` on the PATH), ``isola status`` is asked, and a result
whose analysis was edited since it was computed raises :class:`StaleResult`
(``current=False`` loads it anyway). Where isola cannot be asked, a warning says so.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import warnings
from pathlib import Path

import pandas as pd

# Columns that hold counts, numbers of things or ids.
INTEGER = {
    "attractor",
    "branch",
    "cells",
    "curve",
    "jump",
    "largest_ratio_excitation",
    "largest_ratio_response",
    "period",
    "period_forcing_periods",
    "point",
    "points",
    "ratio_excitation",
    "ratio_response",
    "response",
    "step",
    "steps",
    "window",
}
# Columns that hold true/false.
BOOLEAN = {
    "collision",
    "hidden",
    "located",
    "partly_hidden",
    "restarted",
    "seeded",
    "slack_i",
    "slack_ii",
    "steady",
    "subharmonic",
}
# Columns that hold labels.
TEXT = {
    "after",
    "at",
    "before",
    "class",
    "direction",
    "event",
    "kind",
    "largest_type",
    "of",
    "response_type",
    "response_type_after",
    "response_type_before",
    "verdict",
}


class Tables(dict):
    """The tables of one result by name (the main one under the analysis' name), with its
    manifest as ``.manifest``."""

    manifest: dict


def dtype_of(column: str, cells: pd.Series) -> str:
    """The dtype of a column, by its name, else by what it holds (``stable`` is a count of
    stable responses in a map, a flag on a continued branch; a column this reader does not
    know is a flag if it holds only true/false, else numbers, else labels)."""
    if column in TEXT:
        return "string"
    if column in BOOLEAN:
        return "boolean"
    if column in INTEGER:
        return "Int64"
    written = cells[cells != ""]
    if len(written) and set(written) <= {"true", "false"}:
        return "boolean"
    if column == "stable":
        return "Int64"
    numbers = pd.to_numeric(written, errors="coerce")
    return "float64" if numbers.notna().all() else "string"


def read_table(path: str | Path) -> pd.DataFrame:
    """One of isola's CSV files as a frame with the dtypes of :func:`dtype_of`."""
    raw = pd.read_csv(path, dtype=str, keep_default_na=False)
    frame = pd.DataFrame(index=raw.index)
    for column in raw.columns:
        cells = raw[column]
        dtype = dtype_of(column, cells)
        missing = cells == ""
        if dtype == "boolean":
            unknown = set(cells[~missing]) - {"true", "false"}
            if unknown:
                raise ValueError(f"{path}: column {column!r} holds {sorted(unknown)[:3]}")
            values = cells.map({"true": True, "false": False}).where(~missing, None)
            frame[column] = pd.array(values, dtype="boolean")
        elif dtype == "string":
            frame[column] = pd.array(cells.where(~missing, None), dtype="string")
        else:
            numbers = pd.to_numeric(cells.where(~missing, None), errors="raise")
            frame[column] = numbers.astype(dtype)
    return frame


# `load`'s default: ask isola for the session's status
_ASK = object()


class StaleResult(Exception):
    """A stored result its session no longer computes (its analysis was edited since)."""


def session_status(results: str | Path) -> dict[str, str] | None:
    """Each analysis' state as ``isola status`` tells it for the session beside the results
    folder (``complete``, ``stale``, ``missing``...), or None with a warning where there is
    no such session file or no isola to ask."""
    folder = Path(results)
    session = folder.with_suffix(".toml")
    isola = os.environ.get("ISOLA") or shutil.which("isola")
    if not session.exists() or not isola:
        warnings.warn(
            f"{folder}: not checked against its session ("
            + ("no isola executable: set ISOLA" if session.exists() else f"no {session.name}")
            + "); the result may be stale",
            stacklevel=3,
        )
        return None
    out = subprocess.run(
        [isola, "status", str(session), "--json"], capture_output=True, text=True
    )
    if out.returncode != 0:
        raise StaleResult(f"{session}: isola status failed: {out.stderr.strip()}")
    return {a["name"]: a["result"] for a in json.loads(out.stdout)["analyses"]}


def load(
    results: str | Path,
    analysis: str,
    verify: bool = True,
    current: bool = True,
    status=_ASK,
) -> Tables:
    """The tables of analysis ``analysis`` in the results folder ``results`` (as its
    manifest lists them), each checked against the manifest's SHA-256 unless ``verify`` is
    false. A result without a manifest is not complete and is refused; one its session
    would not compute now raises :class:`StaleResult` unless ``current`` is false
    (``status``: :func:`session_status`'s answer, None where it could not be asked; asked
    here if not given)."""
    folder = Path(results)
    manifest_path = folder / f"{analysis}.manifest.json"
    if not manifest_path.exists():
        raise FileNotFoundError(f"{manifest_path}: no complete result of {analysis!r}")
    if current:
        status = session_status(folder) if status is _ASK else status
        state = None if status is None else status.get(analysis, "not in the session")
        if state not in (None, "complete"):
            raise StaleResult(
                f"{manifest_path}: {analysis!r} is {state} for its session (edited since it "
                "was computed): run isola on the session, or load it with current=False"
            )
    manifest = json.loads(manifest_path.read_text())
    tables = Tables()
    tables.manifest = manifest
    for stored in manifest["files"]:
        path = folder / stored["name"]
        if verify:
            digest = hashlib.sha256(path.read_bytes()).hexdigest()
            if digest != stored["sha256"]:
                raise ValueError(f"{path}: checksum differs from the manifest's")
        name = stored["name"].removesuffix(".csv")
        key = analysis if name == analysis else name.removeprefix(analysis + ".")
        tables[key] = read_table(path)
    return tables


def load_all(
    results: str | Path, verify: bool = True, current: bool = True
) -> dict[str, Tables]:
    """Every complete analysis of a results folder, by name (with ``current``, each current
    for its session, as :func:`load` checks; the session is asked once)."""
    folder = Path(results)
    status = session_status(folder) if current else None
    return {
        m.name.removesuffix(".manifest.json"): load(
            folder, m.name.removesuffix(".manifest.json"), verify, current, status
        )
        for m in sorted(folder.glob("*.manifest.json"))
    }
