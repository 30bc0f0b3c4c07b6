"""``Scene.render`` releases the GIL while it renders (issue 3): another Python thread keeps running."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import brdfpy
import pytest


@pytest.fixture
def one_thread() -> Iterator[None]:
    before = brdfpy.get_num_threads()
    brdfpy.set_num_threads(1)  # leave the second core to the Python thread
    yield
    brdfpy.set_num_threads(before)


def test_python_threads_run_during_a_render(one_thread: None) -> None:
    scene = brdfpy.Scene()
    scene.add(brdfpy.icosphere(7), brdfpy.model("cook_torrance"))
    scene.add_light(brdfpy.DirectionalLight((-1, -1, -1)))
    cam = brdfpy.Camera.perspective((0, 0, 3))
    scene.render(cam, 64, 48)  # warm up (pool, caches)
    in_render = threading.Event()
    done = threading.Event()

    def work() -> None:
        in_render.set()
        scene.render(cam, 1280, 960, samples=4)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    in_render.wait()
    count = 0
    while not done.is_set():
        count += 1
    t.join()
    # a render of ~1/4 s: with the GIL held, this loop would get at most a few switch intervals (5 ms)
    # before and after the Rust call; released, it spins the whole time (millions of iterations)
    assert count > 200_000, count
