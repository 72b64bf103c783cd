"""The scenes and sweeps shipped with the package, and naming them without a path.

The repository's ``cases/`` travels in the wheel as ``orchestrator/scenes/`` (pyproject.toml), so
an installed ``debrisfoam`` carries the study's scenes and sweeps. A verb that takes a scene or a
sweep file also takes a shipped one by name, from any folder: ``debrisfoam render 1debris -o X``,
``debrisfoam render hard/glancing -o X``, ``debrisfoam sweep tiny-mesh-study --dry-run``. A file
the user names that exists always wins over a shipped one of the same name; a name is only looked
up in the package when no such file is there.

Light on purpose (paths and YAML only): the command line resolves names while it parses.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from orchestrator.core.files import bundled_dir

__all__ = ["resolve_scene", "resolve_sweep", "scenes_dir", "shipped_scenes", "shipped_sweeps", "sweeps_dir"]

#: The sweeps' folder inside the scenes' folder.
SWEEPS = "sweeps"


def scenes_dir() -> Path:
    """The shipped example scenes: the repository's cases/, or the installed package's scenes/."""
    return bundled_dir("scenes", "cases")


def sweeps_dir() -> Path:
    """The shipped sweeps (cases/sweeps/)."""
    return scenes_dir() / SWEEPS


def _description(path: Path, fallback_key: str) -> str:
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8")) or {}
    except (OSError, UnicodeDecodeError, yaml.YAMLError):
        data = {}
    if not isinstance(data, dict):
        return ""
    text = data.get("description")
    return " ".join(str(text).split()) if text else f"(extends {data.get(fallback_key, '?')})"


def shipped_scenes() -> list[tuple[Path, str]]:
    """(path, one-line description) of every shipped scene (sweep files excluded)."""
    root = scenes_dir()
    return [(p, _description(p, "extends")) for p in sorted(root.rglob("*.yaml"))
            if SWEEPS not in p.relative_to(root).parts]


def shipped_sweeps() -> list[tuple[Path, str]]:
    """(path, one-line description) of every shipped sweep."""
    return [(p, _description(p, "base")) for p in sorted(sweeps_dir().glob("*.yaml"))]


def shipped_name(path: Path, root: Path | None = None) -> str:
    """The name a shipped file is given by: its path under ``root`` without ``.yaml``."""
    return path.relative_to(root or scenes_dir()).with_suffix("").as_posix()


def _find(text: str, root: Path, exclude_sweeps: bool) -> Path | None:
    name = text.strip()
    if not name or Path(name).is_absolute() or ".." in Path(name).parts:
        return None
    for candidate in (root / name, root / f"{name}.yaml"):
        if candidate.is_file() and candidate.suffix == ".yaml":
            if exclude_sweeps and SWEEPS in candidate.relative_to(root).parts:
                return None
            return candidate
    return None


def resolve_scene(text: str) -> str:
    """``text`` itself when it names an existing file (or no shipped scene); otherwise the path of
    the shipped scene it names (``1debris``, ``1debris.yaml``, ``hard/glancing``)."""
    if Path(text).exists():
        return text
    found = _find(text, scenes_dir(), exclude_sweeps=True)
    return str(found) if found else text


def resolve_sweep(text: str) -> str:
    """:func:`resolve_scene` for sweep files (``tiny-mesh-study``, ``sweeps/debris-layouts``)."""
    if Path(text).exists():
        return text
    found = _find(text, sweeps_dir(), exclude_sweeps=False)
    if found is None and text.startswith(f"{SWEEPS}/"):
        found = _find(text[len(SWEEPS) + 1:], sweeps_dir(), exclude_sweeps=False)
    return str(found) if found else text
