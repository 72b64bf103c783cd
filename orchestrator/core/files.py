"""Files the whole package shares: the folders shipped with it, JSON read and written whole.

Every writer here writes beside the target and renames, so a reader (or a run stopped
half-way) never sees half a file.
"""
from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from orchestrator.core.jsonio import json_default

#: The installed package's folder (orchestrator/).
PACKAGE_DIR = Path(__file__).resolve().parents[1]


def bundled_dir(installed: str, in_repository: str) -> Path:
    """A folder shipped with the package: in an installed wheel the package data
    orchestrator/<installed>/, in the source tree the repository's <in_repository>/
    (pyproject.toml maps one to the other)."""
    inside = PACKAGE_DIR / installed
    return inside if inside.is_dir() else PACKAGE_DIR.parent / in_repository


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in the same folder and a rename."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)
    return path


def write_bytes_atomic(path: str | Path, data: bytes) -> Path:
    """:func:`write_text_atomic` for bytes (figures)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)
    return path


def write_json_atomic(path: str | Path, data: Any) -> Path:
    """``data`` as indented JSON (numpy numbers and paths converted), written atomically."""
    return write_text_atomic(path, json.dumps(data, indent=2, default=json_default) + "\n")


def read_json(path: str | Path, notes: list[str] | None = None) -> Any | None:
    """The JSON document at ``path``, or None when it is missing or unreadable.

    An unreadable file (not a missing one) adds a line to ``notes`` when given.
    """
    path = Path(path)
    if not path.is_file():
        return None
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        if notes is not None:
            notes.append(f"{path.name} could not be read ({exc}); ignored")
        return None


def read_json_object(path: str | Path) -> dict | None:
    """:func:`read_json` when the document is a JSON object, else None."""
    data = read_json(path)
    return data if isinstance(data, dict) else None
