"""The documentation checked like code (`make docs-check`): no broken links, no history, a short
README, docs a newcomer can finish, `make help` listing every target, and the figures a test can
recompute cheaply equal to what the code gives today.

No OpenFOAM: the stale-figure checks ask the planner, which counts cells without meshing.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GUIDE = ROOT / "docs" / "guide.md"
README_MAX_WORDS = 800
#: docs/*.md together (generated scene.md and catalogue.md included, docs/results/ not): a reference
#: a newcomer can read through; measurements and how they were found go to CHANGELOG.md.
DOCS_MAX_WORDS = 15_000
MAKEFILE = ROOT / "Makefile"

#: Pages whose links must resolve: the README, every page under docs/ (generated ones too, since
#: their links are written by the report generators), the benchmarks' pages.
LINKED_PAGES = [README, *sorted((ROOT / "docs").rglob("*.md")), *sorted((ROOT / "benchmarks").glob("*.md"))]
#: Pages that say what is true now: the README and the hand-written docs (docs/results/ is generated
#: from runs and CHANGELOG.md is the history).
CURRENT_PAGES = [README, *sorted((ROOT / "docs").glob("*.md"))]

#: History phrasing: a page that tells how things were, or when they changed, instead of how they are.
#: Each pattern is specific enough not to flag present-tense English ("before the impact", "still
#: water", "the memory available now"); "no longer" and "now <verb>s" are always phrases of change.
HISTORY = [
    r"\bbefore the (fix|fixes|mend|change|changes)\b",
    r"\bafter the (fix|fixes|mend|change|changes)\b",
    r"\bthe set-up before\b",
    r"\bbefore those features\b",
    r"\bfirst set-up\b",
    r"\bmend(ed|s)?\b",
    r"\b(was|were|got|been) (fixed|mended|repaired)\b",
    r"\bfindings mean now\b",
    r"\bthen and\b[^.]*\bnow\b",
    r"\b(does|is|are) now\b",
    r"\bnow (acts|moves|sets|puts|uses|takes|gives|runs|reads|goes|holds|has|is|keeps|stays|writes|starts|ends|stops|frees|strikes|finishes|carries)\b",
    r"\bno longer\b",
    r"\bwas changed\b",
    r"\bpredates?\b",
    r"\blater changes?\b",
    r"\bused to\b",
    r"\bpreviously\b",
    r"\bformerly\b",
    r"\brecently\b",
    r"\bhad been\b",
    r"\bthe old\b",
    r"\b(projection|adjustment|setting|constraint) still (on|off)\b",
    r"\(before:? [-+]?\d",
    r"[\d%]\s*before\)",
    r"\bsession \d",
    r"\bthis session\b",
    r"\b(this|last|previous) round\b",
    r"\bcommit [0-9a-f]{7,40}\b",
]

#: The patterns as searched: a space in a pattern matches any run of whitespace (a phrase may wrap).
_HISTORY = [re.compile(p.replace(" ", r"\s+"), re.I) for p in HISTORY]

_FENCE = re.compile(r"^(```|~~~).*?^\1", re.S | re.M)
_CODE_SPAN = re.compile(r"`[^`\n]*`")
_INLINE_LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
_REF_LINK = re.compile(r"^\s*\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$", re.M)
_HTML_LINK = re.compile(r"""<(?:a|img)\b[^>]*?\b(?:href|src)\s*=\s*["']([^"']+)["']""", re.I)


def _prose(text: str) -> str:
    """The page without fenced code blocks (their lines kept empty, so line numbers stay true)."""
    return _FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)


def _links(text: str) -> list[tuple[int, str]]:
    """(line, target) of every Markdown or HTML link outside code, in the page's order."""
    prose = _CODE_SPAN.sub(lambda m: " " * len(m.group(0)), _prose(text))
    found = []
    for pattern in (_INLINE_LINK, _REF_LINK, _HTML_LINK):
        for m in pattern.finditer(prose):
            found.append((m.start(), prose.count("\n", 0, m.start()) + 1, m.group(1)))
    return [(line, target) for _, line, target in sorted(found)]


def _slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[`*_]|\[([^\]]*)\]\([^)]*\)", r"\1", heading).strip().lower()
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def _anchors(page: Path) -> set[str]:
    seen: dict[str, int] = {}
    out = set()
    for m in re.finditer(r"^#{1,6}\s+(.*?)\s*#*\s*$", _prose(page.read_text(encoding="utf-8")), re.M):
        slug = _slug(m.group(1))
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def _rel(path: Path) -> str:
    return str(path.relative_to(ROOT))


@pytest.mark.parametrize("page", LINKED_PAGES, ids=_rel)
def test_every_relative_link_resolves(page):
    broken = []
    for line, target in _links(page.read_text(encoding="utf-8")):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
            continue
        path, _, anchor = target.partition("#")
        dest = (page.parent / path).resolve() if path else page
        if not dest.exists():
            broken.append(f"line {line}: {target} (no such file)")
        elif anchor and dest.suffix == ".md" and anchor.lower() not in _anchors(dest):
            broken.append(f"line {line}: {target} (no heading gives #{anchor} in {_rel(dest)})")
    assert not broken, f"{_rel(page)}: broken links:\n  " + "\n  ".join(broken)


def test_the_link_reader_finds_what_it_must():
    text = ("[a](x.md) ![b](img/p.png) [c](y.md#sec) [d]: z.md\n`[not](code.md)`\n"
            "```\n[not](fenced.md)\n```\n<img src=\"q.png\">\n")
    assert [t for _, t in _links(text)] == ["x.md", "img/p.png", "y.md#sec", "q.png"]
    assert _slug("Known limits") == "known-limits"
    assert _slug("What `make case-1debris` gives") == "what-make-case-1debris-gives"


@pytest.mark.parametrize("page", CURRENT_PAGES, ids=_rel)
def test_pages_say_what_is_true_now_not_its_history(page):
    prose = _prose(page.read_text(encoding="utf-8"))
    hits = []
    for pattern in _HISTORY:
        for m in pattern.finditer(prose):
            hits.append(f"line {prose.count(chr(10), 0, m.start()) + 1}: {m.group(0)!r}")
    assert not hits, (f"{_rel(page)} tells history (it belongs in CHANGELOG.md, or restate it as a "
                      "comparison of two options):\n  " + "\n  ".join(hits))


#: The word a page must not number its work periods by, kept apart here so that this file does
#: not itself contain the phrase the history check looks for.
WORK_PERIOD = "sess" + "ion"


def test_the_history_patterns_catch_history_and_spare_the_present():
    def flagged(s):
        return any(p.search(s) for p in _HISTORY)

    for history in ("What thin-wet-bed showed before the mend", "What the findings mean now",
                    "took 336 s then and 431 s now", "the set-up before the fixes below",
                    "The debris rows predate three later changes", "water -0.48 % (-1.28 % before)",
                    "(before:\n    0.002 m/s)", "as it was in " + WORK_PERIOD + " 12",
                    "the friction now acts at the centre", "A missed stop no longer fails a run",
                    "the damper used to turn the body", "the default was changed to 3 cm",
                    "the runner now sets them aside", "Each body\nnow moves its own cellZone",
                    "The planner now puts a plane", "it now stays within 0.07 mm"):
        assert flagged(history), history
    for present in ("0.75 ms before the impact", "now and then", "known limits",
                    "under 50 mm of still water", "the memory available now", "as before the stop",
                    "as in the steps before); across", "it was still on the 7th of the 21 zone pairs"):
        assert not flagged(present), present


def _readme_words(text: str) -> int:
    return len(_prose(text).split())


def test_the_readme_reads_in_two_minutes():
    words = _readme_words(README.read_text(encoding="utf-8"))
    assert words <= README_MAX_WORDS, (f"README.md has {words} words outside code blocks; at most "
                                       f"{README_MAX_WORDS} (depth goes to docs/)")


def test_readme_words_are_counted_outside_code_blocks():
    assert _readme_words("one two\n```\nthree four five\n```\nsix\n") == 3


def _words(text: str) -> int:
    """Words as `wc -w` counts them: runs of non-space, code blocks included."""
    return len(text.split())


def test_the_readme_with_its_code_is_short_too():
    words = _words(README.read_text(encoding="utf-8"))
    assert words <= README_MAX_WORDS, (f"README.md has {words} words, code blocks included; at most "
                                       f"{README_MAX_WORDS}")


def test_the_docs_are_a_reference_a_newcomer_can_finish():
    pages = sorted((ROOT / "docs").glob("*.md"))
    counts = {_rel(p): _words(p.read_text(encoding="utf-8")) for p in pages}
    total = sum(counts.values())
    assert total <= DOCS_MAX_WORDS, (
        f"docs/*.md hold {total:,} words (`wc -w docs/*.md`); at most {DOCS_MAX_WORDS:,}. Keep what is "
        "true now as reference; measurements and their story go to CHANGELOG.md. Per page:\n  "
        + "\n  ".join(f"{n:6,} {page}" for page, n in sorted(counts.items(), key=lambda kv: -kv[1])))


def test_the_word_count_is_wc_w():
    assert _words("a  b\n```\nc d\n```\n- e\n") == 8


# The Makefile: `make help` lists every target.

def _makefile_targets(text: str) -> set[str]:
    """The targets a Makefile defines: rule lines `name [name ...]:` outside recipes, not variable
    assignments (`:=`, `::=`) and not special targets (`.PHONY`) or pattern rules."""
    targets = set()
    for line in text.splitlines():
        if line.startswith(("\t", "#", " ")) or re.match(r"^[^:]*(=|::?=)", line):
            continue
        m = re.match(r"^([^:#=$%]+?)\s*::?(?!=)", line)
        if m:
            targets.update(n for n in m.group(1).split() if not n.startswith("."))
    return targets


def test_the_target_reader_reads_rule_lines_only():
    text = ("X := 1\nY ?= 2\n.PHONY: a b\na: b\n\t@echo x: y\nb c:\n$(STAMP): f\n"
            "# d: e\nsimple::=z\n")
    assert _makefile_targets(text) == {"a", "b", "c"}


def test_make_help_lists_every_target():
    import shutil
    import subprocess

    if shutil.which("make") is None:
        pytest.skip("make is not installed")
    out = subprocess.run(["make", "-s", "--no-print-directory", "-C", str(ROOT), "help"],
                         capture_output=True, text=True, timeout=60, check=True).stdout
    listed = set(re.findall(r"^make ([\w.-]+)", out, re.M))
    targets = _makefile_targets(MAKEFILE.read_text(encoding="utf-8"))
    assert len(targets) >= 20, sorted(targets)
    missing = sorted(targets - listed)
    assert not missing, f"`make help` leaves out: {', '.join(missing)} (add a line to the help recipe)"
    unknown = sorted(listed - targets)
    assert not unknown, f"`make help` lists targets the Makefile does not define: {', '.join(unknown)}"


# Stale figures: the ones a test can recompute in a second.

def _paragraphs(text: str) -> list[str]:
    """Blank-line separated paragraphs, each list item its own, on one line."""
    return [" ".join(p.split()) for p in re.split(r"\n\s*\n|\n(?=\s*[-*] )", _prose(text)) if p.strip()]


def _figure(s: str) -> int:
    return int(s.replace(",", ""))


def _stated_cell_counts(page: Path) -> list[int]:
    """Cell counts stated for the 1-debris scene: 'N cells' or 'N-cell' (N at least 10,000) in a
    paragraph that names it."""
    out = []
    for para in _paragraphs(page.read_text(encoding="utf-8")):
        if re.search(r"1-?debris", para):
            out += [_figure(n) for n in re.findall(r"\b(\d{1,3}(?:,\d{3})+|\d{5,})[ -]cells?\b", para)
                    if _figure(n) >= 10_000]
    return out


@pytest.fixture(scope="module")
def planned_1debris_cells():
    from orchestrator.plan.planner import plan_case
    from orchestrator.scene.shipped import scenes_dir
    from orchestrator.scene.scenefile import load_scene

    scene = scenes_dir() / "1debris.yaml"
    one_way = plan_case(load_scene(scene), str(scene))
    two_way = plan_case(load_scene(scene, ["run.debris_coupling=two-way"]), str(scene))
    assert one_way.solver == "interFoam" and two_way.solver == "overInterDyMFoam"
    return {"one-way (the default)": one_way.cell_count, "two-way": two_way.cell_count}


def test_the_1debris_cell_counts_are_the_planners(planned_1debris_cells):
    stated = {_rel(p): _stated_cell_counts(p) for p in (README, GUIDE) if p.exists()}
    if not any(stated.values()):
        pytest.skip("neither README.md nor docs/guide.md states a cell count for the 1-debris scene")
    planned = set(planned_1debris_cells.values())
    stale = [f"{page}: {n:,} cells" for page, counts in stated.items() for n in counts if n not in planned]
    assert not stale, (f"stale cell counts for the 1-debris scene (the planner: "
                       f"{', '.join(f'{k} {v:,}' for k, v in planned_1debris_cells.items())}):\n  "
                       + "\n  ".join(stale))


def test_the_cell_count_reader_reads_the_readmes_forms(tmp_path):
    page = tmp_path / "p.md"
    page.write_text("The 1-debris scene (interFoam, 135,869 cells) or its 140,749-cell mesh.\n\n"
                    "Another scene: 13,392 cells.\n")
    assert _stated_cell_counts(page) == [135_869, 140_749]


def _cost_statements() -> list[tuple[str, str, float, float]]:
    """(page, what, stated, code) for the planner's cost constants wherever a page states them."""
    from orchestrator.plan.timestep import STEP_FACTOR, US_PER_CELL_STEP

    out = []
    for page in CURRENT_PAGES:
        for para in _paragraphs(page.read_text(encoding="utf-8")):
            if "STEP_FACTOR" in para:
                m = re.search(r"STEP_FACTOR`?,? (\d+(?:\.\d+)?) with debris and (\d+(?:\.\d+)?) without", para)
                if m:
                    out += [(_rel(page), "STEP_FACTOR overInterDyMFoam", float(m[1]), STEP_FACTOR["overInterDyMFoam"]),
                            (_rel(page), "STEP_FACTOR interFoam", float(m[2]), STEP_FACTOR["interFoam"])]
                tail = para[para.index("STEP_FACTOR"):]
                for solver in ("interFoam", "overInterDyMFoam"):
                    m = re.search(rf"\b{solver} (\d+(?:\.\d+)?)\b(?! ?us)", tail)
                    if m:
                        out.append((_rel(page), f"STEP_FACTOR {solver}", float(m[1]), STEP_FACTOR[solver]))
            if "US_PER_CELL_STEP" in para:
                m = re.search(r"\((\d+(?:\.\d+)?) us used\)", para)
                if m:
                    out.append((_rel(page), "US_PER_CELL_STEP interFoam", float(m[1]),
                                US_PER_CELL_STEP["interFoam"] * 1e6))
                m = re.search(r"overInterDyMFoam (\d+(?:\.\d+)?) us\b", para)
                if m:
                    out.append((_rel(page), "US_PER_CELL_STEP overInterDyMFoam", float(m[1]),
                                US_PER_CELL_STEP["overInterDyMFoam"] * 1e6))
    return out


def test_the_stated_cost_constants_are_the_planners():
    statements = _cost_statements()
    if not statements:
        pytest.skip("no page states plan.STEP_FACTOR or plan.US_PER_CELL_STEP")
    stale = [f"{page}: {what} {stated:g} (the code: {code:g})" for page, what, stated, code in statements
             if abs(stated - code) > 1e-9]
    assert not stale, "stale cost figures:\n  " + "\n  ".join(stale)
