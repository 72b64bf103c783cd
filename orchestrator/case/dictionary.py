"""OpenFOAM dictionaries as the runner reads and edits them (foamlib, the one dictionary library).

foamlib edits a file in place: an entry set or deleted is written anew and every other byte of
the file (the rendered comments, layout and digits) is kept. It writes a number with Python's
`str` (a float's shortest text that reads back to the same double), so nothing is rounded.

foamlib writes the edited file over the old one in place; a running solver re-reads run-time
modified files (controlDict) at any moment and must never see half a file. `edit_dictionary`
therefore edits a copy beside the file and renames it over the file. foamlib also leaves a line
of indentation where it deletes an entry and adds one before an entry it adds: the runner adds
and removes the same constraints at every restart, so the edited text keeps at most one empty
line in a row (whitespace only: nothing OpenFOAM reads).
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

from foamlib import FoamFile, FoamFileDecodeError

__all__ = ["DictionaryError", "edit_dictionary", "plain", "read_dictionary"]

#: what foamlib raises for a file that is not an OpenFOAM dictionary (a ValueError)
DictionaryError = FoamFileDecodeError


def read_dictionary(path: str | Path) -> FoamFile:
    """An OpenFOAM dictionary file, parsed when first read (FileNotFoundError, DictionaryError)."""
    return FoamFile(Path(path))


def plain(value: Any) -> Any:
    """A value read from a dictionary as plain Python: sub-dictionaries as dicts, arrays as lists."""
    if isinstance(value, FoamFile.SubDict):
        return value.as_dict()
    if hasattr(value, "tolist"):
        return value.tolist()
    return value


@contextmanager
def edit_dictionary(path: str | Path) -> Iterator[FoamFile]:
    """Edit an OpenFOAM dictionary and replace the file at once when the block ends without an
    error (a block that sets nothing leaves the file as it is, its modification time too)."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    os.close(fd)
    try:
        shutil.copyfile(target, tmp)
        copy = FoamFile(tmp)
        with copy:
            yield copy
        before, text = target.read_bytes(), Path(tmp).read_bytes()
        if text != before:
            Path(tmp).write_bytes(re.sub(rb"\n{3,}", b"\n\n", re.sub(rb"\n[ \t]+(?=\n)", b"\n", text)))
            os.chmod(tmp, 0o644)
            os.replace(tmp, target)
    finally:
        Path(tmp).unlink(missing_ok=True)
