"""The package's shape: stages import only downwards, no cycles, no private names across
modules, no module over 600 lines.

orchestrator/ is layered by the data flow (bottom first)::

    core -> scene -> plan -> case -> contact -> run -> transport -> results -> report -> pipeline -> studies -> cli

A module may import from its own stage and the stages below it; analytical/ (pure physics)
imports nothing of orchestrator/. Imports inside functions count too: a late import is still a
dependency.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LAYERS = ["core", "scene", "plan", "case", "contact", "run", "transport", "results", "report", "pipeline", "studies",
          "cli"]
MAX_LINES = 600


def _modules() -> dict[str, Path]:
    out = {}
    for top in ("orchestrator", "analytical"):
        for path in sorted((ROOT / top).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


MODULES = _modules()


def _stage(module: str) -> str | None:
    """The stage of an orchestrator module (None for analytical and the package root)."""
    parts = module.split(".")
    if parts[0] != "orchestrator" or len(parts) < 2:
        return None
    return parts[1]


def _imports(path: Path) -> list[tuple[str, list[str], int]]:
    """(module imported, names taken from it, line) for every project import in the file."""
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            base = node.module
            if not base.startswith(("orchestrator", "analytical")):
                continue
            names = [a.name for a in node.names]
            submodules = [n for n in names if f"{base}.{n}" in MODULES]
            for n in submodules:
                out.append((f"{base}.{n}", [], node.lineno))
            rest = [n for n in names if n not in submodules]
            if rest:
                out.append((base, rest, node.lineno))
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith(("orchestrator", "analytical")):
                    out.append((a.name, [], node.lineno))
    return out


GRAPH = {m: sorted({target for target, _, _ in _imports(p) if target in MODULES and target != m})
         for m, p in MODULES.items()}


def test_stages_import_only_downwards():
    wrong = []
    for module, path in MODULES.items():
        for target, _, line in _imports(path):
            if module.startswith("analytical") and target.startswith("orchestrator"):
                wrong.append(f"{path.relative_to(ROOT)}:{line} imports {target} (analytical is pure)")
                continue
            src, dst = _stage(module), _stage(target)
            if src in LAYERS and dst in LAYERS and LAYERS.index(dst) > LAYERS.index(src):
                wrong.append(f"{path.relative_to(ROOT)}:{line} ({src}) imports {target} ({dst})")
    assert not wrong, "imports against the stage order:\n" + "\n".join(wrong)


def test_every_stage_is_in_the_order():
    """A subpackage or module of orchestrator/ missing from LAYERS would escape the order check."""
    stages = {_stage(m) for m in MODULES if _stage(m) is not None}
    assert stages <= set(LAYERS), f"stages not in LAYERS: {sorted(stages - set(LAYERS))}"


def test_no_import_cycles():
    """Tarjan's strongly connected components over the module graph: each must be one module."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in GRAPH[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in GRAPH:
        if v not in index:
            visit(v)
    assert not cycles, f"import cycles: {cycles}"


def test_no_private_names_across_modules():
    wrong = [f"{path.relative_to(ROOT)}:{line} takes {name} from {target}"
             for module, path in MODULES.items()
             for target, names, line in _imports(path)
             for name in names if name.startswith("_") and not name.startswith("__")]
    assert not wrong, "private names imported across modules:\n" + "\n".join(wrong)


@pytest.mark.parametrize("module", sorted(MODULES))
def test_module_is_at_most_600_lines(module):
    lines = len(MODULES[module].read_text().splitlines())
    assert lines <= MAX_LINES, f"{module} has {lines} lines (at most {MAX_LINES}): split it by responsibility"


def test_the_layer_check_sees_a_wrong_import(tmp_path):
    """The check itself: an upward import in a file is reported."""
    probe = tmp_path / "probe.py"
    probe.write_text("from orchestrator.studies.sweep import run_sweep\n")
    (target, names, line), = _imports(probe)
    assert (target, names) == ("orchestrator.studies.sweep", ["run_sweep"])
    assert LAYERS.index(_stage(target)) > LAYERS.index(_stage("orchestrator.case.render"))


def test_only_the_cli_parses_a_command_line():
    """Every verb is reached through `debrisfoam` (its exit codes, --debug, error messages): no module
    outside orchestrator/cli/ builds its own argparse parser or has a __main__ of its own."""
    wrong = []
    for module, path in MODULES.items():
        if module.startswith("orchestrator.cli"):
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import) and any(a.name == "argparse" for a in node.names) or \
                    isinstance(node, ast.ImportFrom) and node.module == "argparse":
                wrong.append(f"{module}:{node.lineno}: imports argparse")
            if isinstance(node, ast.Compare) and isinstance(node.left, ast.Name) and node.left.id == "__name__" \
                    and any(isinstance(c, ast.Constant) and c.value == "__main__" for c in node.comparators):
                wrong.append(f"{module}:{node.lineno}: if __name__ == '__main__'")
    assert not wrong, "give it a verb in orchestrator/cli/ instead:\n" + "\n".join(wrong)
