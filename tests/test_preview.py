"""The scene preview: a real off-screen pyvista render of the shipped scenes, checked as an image."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from analytical.errors import InputError
from orchestrator.plan.planner import plan_case
from orchestrator.report.preview import WINDOW_SIZE_PX, preview_scene, preview_scene_file
from orchestrator.scene.scenefile import load_scene
from tests.conftest import ROOT, run_cli

CASES = ("1debris", "6debris-2x3", "nodebris")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _scene_path(name: str) -> Path:
    return ROOT / "cases" / f"{name}.yaml"


def _pixels(path: Path) -> np.ndarray:
    with Image.open(path) as img:
        return np.asarray(img.convert("RGB"), dtype=int)


def _debris_pixels(rgb: np.ndarray) -> int:
    """Pixels of the debris red (shaded or not): strong red, little green and blue."""
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return int(((r > 150) & (g < 90) & (b < 90)).sum())


@pytest.fixture(scope="module")
def images(tmp_path_factory) -> dict[str, Path]:
    """Each shipped case drawn once (into a folder that does not exist yet). Its draw time is a
    benchmark (benchmarks/bench_preview.py), not a test."""
    out = tmp_path_factory.mktemp("preview")
    return {name: preview_scene_file(_scene_path(name), out / "new" / "folder" / f"{name}.png", []) for name in CASES}


@pytest.mark.parametrize("name", CASES)
def test_preview_is_a_png_of_the_window_size(images, name):
    path = images[name]
    assert path.is_file()
    assert path.read_bytes()[:8] == PNG_SIGNATURE
    with Image.open(path) as img:
        img.verify()
    with Image.open(path) as img:
        assert img.format == "PNG"
        assert img.size == WINDOW_SIZE_PX
    assert not list(path.parent.glob(".*.tmp")), "the temporary file was left behind"


@pytest.mark.parametrize("name", CASES)
def test_preview_is_not_trivial(images, name):
    rgb = _pixels(images[name])
    distinct = np.unique((rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]).size
    assert distinct > 500, f"only {distinct} colours"
    drawn = float((rgb.min(axis=-1) < 245).mean())  # anything but the white background
    assert 0.3 < drawn < 0.95, f"{drawn:.0%} of the image is drawn"
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    assert ((b > r + 40) & (b > g)).sum() > 50_000, "no blue water to be seen"


def test_debris_colour_appears_with_debris_only(images):
    six = _debris_pixels(_pixels(images["6debris-2x3"]))
    one = _debris_pixels(_pixels(images["1debris"]))
    none = _debris_pixels(_pixels(images["nodebris"]))
    assert six > 1000
    assert six > 1.5 * one > 0, "six bodies should cover more of the image than one"
    assert none < 20, "debris red drawn in a scene without debris"


def test_images_differ_between_scenes(images):
    a, b = _pixels(images["nodebris"]), _pixels(images["6debris-2x3"])
    changed = float((np.abs(a - b).max(axis=-1) > 30).mean())
    assert changed > 0.01, f"only {changed:.2%} of the pixels differ"


def test_preview_scene_from_a_plan_makes_the_folder(tmp_path):
    scene = load_scene(_scene_path("1debris"))
    plan = plan_case(scene)
    out = preview_scene(scene, plan, tmp_path / "case" / "preview.png")
    assert out == tmp_path / "case" / "preview.png"
    assert out.read_bytes()[:8] == PNG_SIGNATURE


def test_debris_rotation_is_drawn(tmp_path):
    """A yawed and pitched body draws differently from the same body straight."""
    straight = preview_scene_file(_scene_path("1debris"), tmp_path / "straight.png")
    turned = preview_scene_file(
        _scene_path("1debris"), tmp_path / "turned.png", ["debris.0.yaw_deg=60", "debris.0.pitch_deg=20"]
    )
    a, b = _pixels(straight), _pixels(turned)
    assert (np.abs(a - b).max(axis=-1) > 30).sum() > 100
    assert _debris_pixels(b) > 300


def test_two_d_scene_without_column(tmp_path):
    out = preview_scene_file(
        _scene_path("nodebris"),
        tmp_path / "2d.png",
        ["column=null", "gauges=[{name: WG1, x_m: -0.1, y_m: 0.0}]"],
    )
    assert _pixels(out).shape == (WINDOW_SIZE_PX[1], WINDOW_SIZE_PX[0], 3)


@pytest.mark.parametrize(
    "override, field",
    [("mesh.cell_size_m=-1", "mesh.cell_size_m"), ("flume.no_such_key=1", "flume.no_such_key")],
)
def test_bad_override_raises_input_error(tmp_path, override, field):
    out = tmp_path / "bad.png"
    with pytest.raises(InputError) as err:
        preview_scene_file(_scene_path("1debris"), out, [override])
    assert err.value.field == field
    assert not out.exists()


def test_missing_scene_raises_input_error(tmp_path):
    with pytest.raises(InputError):
        preview_scene_file(tmp_path / "absent.yaml", tmp_path / "p.png")


def test_cli_preview(tmp_path):
    out = tmp_path / "p.png"
    proc = run_cli("preview", "cases/1debris.yaml", "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert out.read_bytes()[:8] == PNG_SIGNATURE
    assert "bad X server" not in proc.stderr


def test_cli_preview_bad_override_exits_2(tmp_path):
    proc = run_cli("preview", "cases/1debris.yaml", "-o", str(tmp_path / "p.png"), "--set", "mesh.cell_size_m=-1")
    assert proc.returncode == 2
    assert "mesh.cell_size_m" in proc.stderr


def test_labels_are_legible_and_the_plan_view_has_both_scales(monkeypatch, tmp_path):
    """Every name and scale mark at a size that reads at 100 % (VTK sizes in pixels; the marks
    were 9-10 px), x marks in the plan view and the whole-flume strip, y marks in the plan view,
    and each of six bodies side by side named (numbered after the prefix they share)."""
    import pyvista as pv

    points, corner = [], []
    add_point_labels, add_text = pv.Plotter.add_point_labels, pv.Plotter.add_text

    def spy_points(self, pts, labels, *args, **kwargs):
        points.append(([str(s).strip() for s in labels], kwargs.get("font_size")))
        return add_point_labels(self, pts, labels, *args, **kwargs)

    def spy_text(self, text, *args, **kwargs):
        corner.append((text, kwargs.get("font_size")))
        return add_text(self, text, *args, **kwargs)

    monkeypatch.setattr(pv.Plotter, "add_point_labels", spy_points)
    monkeypatch.setattr(pv.Plotter, "add_text", spy_text)
    preview_scene_file(_scene_path("6debris-2x3"), tmp_path / "six.png")
    assert points and corner
    assert min(size for _, size in points) >= 12, points
    assert min(size for _, size in corner) >= 10, corner
    labels = [label for names, _ in points for label in names]
    assert labels.count("x = 0 m") == 2, "x marks in the plan view and in the whole-flume strip"
    y_marks = next(names for names, _ in points if "y = 0 m" in names)
    assert any(label.startswith("y = -") for label in y_marks), "y marks on both sides of the centreline"
    assert all(label.startswith("y = ") and label.endswith(" m") for label in y_marks), "every y mark with its unit"
    headline = corner[0][0]
    assert "6 debris bodies (one-way" in headline and "no debris" not in headline  # the flow runs without them
    assert "see plan.json" not in headline
    assert {"1", "2", "3", "4", "5", "6"} <= set(labels) and "debrisN = body N" in labels
