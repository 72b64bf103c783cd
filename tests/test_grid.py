"""BoxGrid: the block-mesh contract between the planner and the blockMesh template."""

import numpy as np
import pytest

from orchestrator.plan.grid import BoxGrid, Segment, graded_segment


def _column_grid(rotation=None, origin=(0.0, 0.0, 0.0)):
    x = (Segment(0, 1, 10), Segment(1, 1.2, 4), Segment(1.2, 3, 12, 3.0))
    y = (Segment(-0.5, -0.1, 6), Segment(-0.1, 0.1, 4), Segment(0.1, 0.5, 6))
    z = (Segment(0, 0.6, 12),)
    kw = {} if rotation is None else {"rotation": rotation}
    return BoxGrid("bg", x, y, z, holes=frozenset({(1, 1, 0)}),
                   patch_names={"hole": "column", "ymin": "sideWalls", "ymax": "sideWalls"}, origin=origin, **kw)


def test_cell_count_excludes_holes():
    g = _column_grid()
    full = (10 + 4 + 12) * (6 + 4 + 6) * 12
    assert g.cell_count() == full - 4 * 4 * 12
    assert len(g.blocks()) == 8


@pytest.mark.parametrize("yaw_deg", [0.0, 30.0, 90.0])
def test_boundary_faces_point_out_of_the_domain(yaw_deg):
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    rot = ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))
    g = _column_grid(rotation=rot, origin=(2.0, 1.0, 0.0))
    pts = g.vertices()
    centre_hole = np.array([1.1, 0.0, 0.3]) @ np.array(rot).T + np.array([2.0, 1.0, 0.0])
    faces = g.boundary_faces()
    assert set(faces) == {"xmin", "xmax", "sideWalls", "zmin", "zmax", "column"}
    # the column is a hole: 4 sides of height 1 block each
    assert len(faces["column"]) == 4
    for name, quads in faces.items():
        for quad in quads:
            p = pts[list(quad)]
            normal = np.cross(p[1] - p[0], p[2] - p[0])
            centre = p.mean(axis=0)
            if name == "column":  # outward from the fluid = into the hole
                assert np.dot(normal, centre_hole - centre) > 0
            else:  # outward = away from the domain centre
                dom_centre = np.array([1.5, 0.0, 0.3]) @ np.array(rot).T + np.array([2.0, 1.0, 0.0])
                assert np.dot(normal, centre - dom_centre) > 0


def test_graded_segment_reaches_target_sizes():
    seg = graded_segment(0.0, 2.0, 0.01, 0.08)
    first, last = seg.cell_sizes_m()
    assert first == pytest.approx(0.01, rel=0.25) and last == pytest.approx(0.08, rel=0.25)
    assert seg.grading > 1
    rev = graded_segment(0.0, 2.0, 0.08, 0.01)
    assert rev.grading < 1 and rev.cells == seg.cells


def test_segments_must_be_contiguous_and_valid():
    with pytest.raises(ValueError, match="contiguous"):
        BoxGrid("g", (Segment(0, 1, 1), Segment(1.5, 2, 1)), (Segment(0, 1, 1),), (Segment(0, 1, 1),))
    with pytest.raises(ValueError):
        Segment(1.0, 0.5, 3)
    with pytest.raises(ValueError, match="hole"):
        BoxGrid("g", (Segment(0, 1, 1),), (Segment(0, 1, 1),), (Segment(0, 1, 1),), holes=frozenset({(1, 0, 0)}))
