"""``Scene.render`` releases the GIL while it renders (issue 3): another Python thread keeps running."""

from __future__ import annotations

import brdfpy

from conftest import python_spins_during


def test_python_threads_run_during_a_render(one_thread: None) -> None:
    scene = brdfpy.Scene()
    scene.add(brdfpy.icosphere(7), brdfpy.model("cook_torrance"))
    scene.add_light(brdfpy.DirectionalLight((-1, -1, -1)))
    cam = brdfpy.Camera.perspective((0, 0, 3))
    scene.render(cam, 64, 48)  # warm up (pool, caches)
    count, _ = python_spins_during(lambda: scene.render(cam, 1280, 960, samples=4))
    # a render of ~1/4 s: with the GIL held, this loop would get at most a few switch intervals (5 ms)
    # before and after the Rust call; released, it spins the whole time (millions of iterations)
    assert count > 200_000, count
