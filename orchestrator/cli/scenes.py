"""The scene verbs: ``scenes`` (the shipped examples), ``catalogue`` (the debris types and column
sections a scene can name), ``validate`` (a scene checked, nothing written) and ``schema`` (the
scene reference, docs/scene.md)."""

from __future__ import annotations

import argparse

from orchestrator.cli.common import EXIT_OK, SCENE_HELP, closing_options, emit, warn
from orchestrator.scene.shipped import resolve_scene

__all__ = ["add_scene_parsers", "cmd_catalogue", "cmd_scenes", "cmd_schema", "cmd_validate"]


def cmd_scenes(args: argparse.Namespace) -> int:
    from orchestrator.scene.shipped import scenes_dir, shipped_name, shipped_scenes, shipped_sweeps, sweeps_dir

    root = scenes_dir()
    scenes = [(shipped_name(p, root), p, d) for p, d in shipped_scenes()]
    sweeps = [(shipped_name(p, sweeps_dir()), p, d) for p, d in shipped_sweeps()]
    if args.json:
        emit({"folder": str(root),
              "scenes": [{"name": n, "path": str(p), "description": d} for n, p, d in scenes],
              "sweeps": [{"name": n, "path": str(p), "description": d} for n, p, d in sweeps]}, True)
        return EXIT_OK
    width = max(len(n) for n, _, _ in scenes + sweeps)
    print(f"shipped scenes (in {root}; give the name, e.g. `debrisfoam render 1debris -o runs/1debris`):")
    for name, _, text in scenes:
        print(f"  {name:<{width}}  {text}")
    print(f"shipped sweeps (in {sweeps_dir()}; e.g. `debrisfoam sweep {sweeps[0][0] if sweeps else 'NAME'} "
          "--dry-run`):")
    for name, _, text in sweeps:
        print(f"  {name:<{width}}  {text}")
    return EXIT_OK


def cmd_validate(args: argparse.Namespace) -> int:
    from orchestrator.plan.planner import plan_case
    from orchestrator.plan.resources import Demand, check_resources
    from orchestrator.scene.scenefile import load_scene

    scene = load_scene(args.scene, list(args.set or []))
    plan = plan_case(scene, args.scene)
    # validate runs nothing: a hard resource limit is bad input, a soft one a warning
    warnings = list(plan.warnings) + check_resources(Demand.of_plan(plan), args.scene, confirmed=True)
    result = {"scene": args.scene, "valid": True, "name": scene.name, "bodies": len(scene.debris),
              "solver": plan.solver, "planned_cells": int(plan.cell_count), "warnings": warnings}
    emit({k: v for k, v in result.items() if args.json or k != "warnings"}, args.json)
    warn(warnings)
    return EXIT_OK


def cmd_schema(args: argparse.Namespace) -> int:
    from orchestrator.scene.reference import markdown, schema_rows, select

    rows = select(schema_rows(), args.key)
    if args.markdown:
        print(markdown(rows), end="")
    elif args.json:
        from dataclasses import asdict

        emit({"keys": [asdict(r) for r in rows]}, True)
    else:
        for r in rows:
            extra = ", ".join(x for x in (r.type, f"default {r.default}", r.range) if x)
            print(f"{r.key}  ({extra})" + (f"\n    {r.description}" if r.description else ""))
    return EXIT_OK


def cmd_catalogue(args: argparse.Namespace) -> int:
    from orchestrator.report.catalogue_page import catalogue_data, markdown

    if args.markdown:
        print(markdown(), end="")
        return EXIT_OK
    data = catalogue_data()
    if args.json:
        emit(data, True)
        return EXIT_OK
    print("debris types (a scene's `type:`; docs/catalogue.md gives every value's source):")
    for d in data["debris"]:
        print(f"  {d['name']:<27} {' x '.join(f'{s:g}' for s in d['size_m'])} m, {d['mass_kg']:g} kg  "
              f"{d['description']}")
    print("column sections (a column's `section: {kind: ...}`): " + ", ".join(data["section_kinds"]))
    print("materials: " + ", ".join(m["name"] for m in data["materials"]))
    return EXIT_OK


def add_scene_parsers(verbs) -> None:
    """The ``scenes``, ``validate`` and ``schema`` verbs, on the top parser's ``verbs``."""
    p = verbs.add_parser("scenes", help="list the shipped example scenes and sweeps (usable by name), one line each")
    closing_options(p, cmd_scenes)

    p = verbs.add_parser("catalogue", help="the debris types and column sections a scene can name, with their "
                                           "values (docs/catalogue.md is generated from it)")
    p.add_argument("--markdown", action="store_true", help="print the catalogue page (docs/catalogue.md)")
    closing_options(p, cmd_catalogue, json="print JSON (every value and its source)")

    p = verbs.add_parser("validate", help="check a scene (schema and planner) without writing anything: exit 0 "
                                          "or 2")
    p.add_argument("scene", type=resolve_scene, help=SCENE_HELP)
    closing_options(p, cmd_validate, overrides="override a dotted scene key (repeatable)")

    p = verbs.add_parser("schema", help="the scene's keys: types, defaults, allowed ranges, meanings "
                                        "(docs/scene.md is generated from it)")
    p.add_argument("key", nargs="?", default=None, help="a section or key, e.g. debris or run.max_courant")
    p.add_argument("--markdown", action="store_true", help="print the reference page (docs/scene.md)")
    closing_options(p, cmd_schema)
