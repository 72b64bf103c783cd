"""YAML as the scene and sweep files are read: their text decoded, each key given once.

:func:`decode_text` accepts UTF-8 with or without a byte-order mark and UTF-16 with one (what
a Windows editor saves as "Unicode"); anything else is bad input naming the file.
:func:`load_yaml` refuses a key given twice in one mapping (PyYAML would keep the last one
silently), naming the dotted key, both lines and the file.
"""

from __future__ import annotations

import codecs
from typing import Any

import yaml

from orchestrator.core.errors import InputError

__all__ = ["decode_text", "duplicate_key", "load_yaml"]

#: Byte-order marks and the codec each one means (UTF-32 before UTF-16: its mark starts with UTF-16's).
_BOMS = (
    (codecs.BOM_UTF32_LE, "utf-32"),
    (codecs.BOM_UTF32_BE, "utf-32"),
    (codecs.BOM_UTF8, "utf-8-sig"),
    (codecs.BOM_UTF16_LE, "utf-16"),
    (codecs.BOM_UTF16_BE, "utf-16"),
)


def decode_text(raw: bytes, field: str, source: str | None = None) -> str:
    """The text of a file's bytes: UTF-8 (with or without a BOM), or UTF-16/32 with a BOM."""
    codec = next((name for bom, name in _BOMS if raw.startswith(bom)), "utf-8")
    try:
        return raw.decode(codec)
    except UnicodeDecodeError as err:
        raise InputError(field, f"not {codec.upper().replace('-SIG', '')} text (byte {raw[err.start]:#04x} at "
                         f"offset {err.start}): save the file as UTF-8", source) from None


def duplicate_key(node: yaml.Node, path: tuple[str, ...] = (), seen: set[int] | None = None) -> tuple[str, int, int] | None:
    """The first key given twice in one mapping of a composed YAML document: (dotted key, first
    line, second line), lines counted from 1; None when every key is unique."""
    seen = set() if seen is None else seen
    if id(node) in seen:  # an alias met again
        return None
    seen.add(id(node))
    if isinstance(node, yaml.MappingNode):
        lines: dict[Any, int] = {}
        for key, value in node.value:
            name = key.value if isinstance(key, yaml.ScalarNode) else None
            if name is not None and name != "<<":
                if name in lines:
                    return ".".join((*path, str(name))), lines[name], key.start_mark.line + 1
                lines[name] = key.start_mark.line + 1
            found = duplicate_key(value, (*path, str(name)), seen)
            if found:
                return found
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            found = duplicate_key(item, (*path, str(i)), seen)
            if found:
                return found
    return None


def load_yaml(text: str, field: str, source: str | None = None) -> Any:
    """The YAML document in ``text`` (safe types only); InputError when it is not YAML, or when a
    mapping gives a key twice (named by its dotted path)."""
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
        found = duplicate_key(node) if node is not None else None
        if found:
            key, first, second = found
            raise InputError(key, f"given twice (lines {first} and {second}); YAML would keep only the last: say it "
                             "once", source)
        return yaml.safe_load(text)
    except yaml.YAMLError as err:
        raise InputError(field, f"not valid YAML: {err}", source) from None
