"""Watertightness: triangles that share edges cover every pixel exactly once (issue 3, "Tests").

The meshes tile the screen: a jittered grid and a triangle fan around a random centre, drawn in NDC over
a square turned by a random angle and lifted along the camera rays to random depths (see
``raster_oracle.geometry.screen_tiling``), seen by random perspective cameras. Their images tile the
screen, so exactly one triangle must own each pixel centre -- including the centres that fall exactly
on shared edges or vertices (the fill rule's job).

Two checks: the full render leaves no pixel uncovered, and rendering every triangle alone (additive
coverage, no depth test involved) covers each pixel exactly once, by the triangle the full render shows
there. Plus pixel-aligned grids, whose every shared edge runs through sample points, and a tilted floor
that crosses the near plane, where the clipped pieces of neighbouring triangles must still meet.
"""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest

from raster_oracle import camera as ocam
from raster_oracle import geometry as og
from raster_oracle import raster as oraster

W, H = 48, 36


def random_camera(rng: np.random.Generator) -> tuple[ocam.Camera, brdfpy.Camera]:
    eye, target = rng.normal(size=3) * 2, rng.normal(size=3) * 0.3
    up = rng.normal(size=3)
    fovy = float(rng.uniform(30, 80))
    return (
        ocam.Camera.perspective(eye, target, up, fovy=fovy, near=0.1, far=100.0),
        brdfpy.Camera.perspective(eye, target, up, fovy=fovy, near=0.1, far=100.0),
    )


def render_ids(v: np.ndarray, f: np.ndarray, cam: brdfpy.Camera, w: int = W, h: int = H) -> np.ndarray:
    scene = brdfpy.Scene()
    scene.add(brdfpy.Mesh(v, f, normals=np.tile([0.0, 0.0, 1.0], (len(v), 1))), "lambert")
    return np.asarray(scene.render(cam, w, h, shading="flat", outputs="all").triangle_id)


def additive_coverage(v: np.ndarray, f: np.ndarray, cam: brdfpy.Camera, w: int = W, h: int = H) -> np.ndarray:
    """(F, H, W) coverage of each triangle rendered alone."""
    return np.stack([render_ids(v, f[i : i + 1], cam, w, h) == 0 for i in range(len(f))])


@pytest.mark.parametrize("kind", ["grid", "fan"])
@pytest.mark.parametrize("seed", range(3))
def test_screen_tiling_meshes_cover_every_pixel_exactly_once(kind: str, seed: int) -> None:
    rng = np.random.default_rng(1000 + seed)
    ocamera, cam = random_camera(rng)
    v, f = og.screen_tiling(kind, rng, ocamera, W / H)
    v = v.astype(np.float32)
    # the reference agrees that this mesh tiles the screen (from brdfpy's own float32 vertices)
    ref = oraster.coverage_count(v.astype(np.float64), f, ocamera, W, H)
    assert ref.min() == 1 and ref.max() == 1
    ids = render_ids(v, f, cam)
    assert (ids >= 0).all(), (
        f"{int((ids < 0).sum())} pixels uncovered, e.g. {np.argwhere(ids < 0)[:3].tolist()}"
    )
    cover = additive_coverage(v, f, cam)
    count = cover.sum(axis=0)
    assert count.min() == 1 and count.max() == 1, (
        f"uncovered {np.argwhere(count == 0)[:3].tolist()}, "
        f"covered twice {np.argwhere(count > 1)[:3].tolist()}"
    )
    # each pixel's owner in the additive test is the triangle the full render shows there
    np.testing.assert_array_equal(np.argmax(cover, axis=0), ids)


@pytest.mark.parametrize("size", [(16, 16), (17, 9)])
def test_edges_through_pixel_centres_are_owned_once(size: tuple[int, int]) -> None:
    # an orthographic view in which the grid's vertices sit exactly on pixel centres: every edge
    # (horizontal, vertical, diagonal) runs through sample points, so only the tie rule decides them
    w, h = size
    nx, ny = w - 1, h - 1
    v, f = og.grid(nx, ny)
    v = v * [nx / w, ny / h, 1.0]  # vertex (i, j) at the centre of pixel (i, j)
    cam = brdfpy.Camera.orthographic((0, 0, 1), (0, 0, 0), height=2.0)
    ocamera = ocam.Camera.orthographic((0, 0, 1), (0, 0, 0), height=2.0)
    count = additive_coverage(v.astype(np.float32), f, cam, w, h).sum(axis=0)
    ref = oraster.coverage_count(v, f, ocamera, w, h)
    # inside the grid every pixel exactly once; on its outer boundary, the fill rule keeps the top and
    # left edges' samples and drops the right and bottom ones, as the reference does
    assert count.max() == 1
    np.testing.assert_array_equal(count, ref)


@pytest.mark.parametrize("seed", range(2))
def test_a_floor_crossing_the_near_plane_stays_watertight(seed: int) -> None:
    # a large jittered floor under a low camera: the triangles near the eye are clipped at the near
    # plane, and the pieces of neighbouring triangles must still meet exactly
    rng = np.random.default_rng(seed)
    v, f = og.grid(10, 10, 0.24, rng)
    v = np.column_stack([v[:, 0] * 20, np.full(len(v), -0.5), v[:, 1] * 20])
    f = f[:, ::-1]  # CCW seen from above
    yaw = rng.uniform(0, 2 * np.pi)
    target = (np.cos(yaw), -0.6, np.sin(yaw))
    cam = brdfpy.Camera.perspective((0, 0, 0), target, fovy=70, near=0.3, far=100)
    ocamera = ocam.Camera.perspective((0, 0, 0), target, fovy=70, near=0.3, far=100)
    ref = oraster.coverage_count(v, f, ocamera, W, H)
    lower = ref > 0  # the floor fills the lower part of the image
    assert lower.sum() > W * H // 3 and ref.max() == 1
    count = additive_coverage(v.astype(np.float32), f, cam).sum(axis=0)
    assert count.max() == 1, f"covered twice at {np.argwhere(count > 1)[:3].tolist()}"
    # the same pixels are covered; a pixel on the floor's outer silhouette may be decided differently
    # only if it lies within 1/128 px of it, which the reference flags
    assert (count[lower] == 1).mean() > 0.99
