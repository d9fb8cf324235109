"""Ctrl-C stops a render: KeyboardInterrupt is raised within about one
tile's time, and the interpreter (and the module) go on working."""

import os
import signal
import threading
import time

import numpy as np

import pytest

import spar

SCENE = "scenes/calcite-polarized.toml"


def test_sigint_stops_a_render_and_the_interpreter_goes_on(repo):
    scene = spar.load_scene(os.path.join(repo, SCENE))
    small = dict(resolution=(8, 8), samples=1)
    before = scene.render(mode="stokes", wavelength=580, **small).stokes
    # About four minutes on two cores if not stopped (256 tiles of
    # 16x16 pixels, four samples, 21 wavelengths).
    scene.set(resolution=(256, 256), samples=4)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        scene.render(mode="stokes")
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 20, f"the render went on for {elapsed:.1f} s after Ctrl-C"
    # Python, and spar, still work: the same small render gives the same bits.
    assert sum(range(10)) == 45
    after = spar.load_scene(os.path.join(repo, SCENE)).render(
        mode="stokes", wavelength=580, **small
    ).stokes
    assert np.array_equal(before.view(np.uint32), after.view(np.uint32))


def test_the_gil_is_released_while_rendering(repo):
    """Another Python thread runs while a render runs, and may change the
    scene being rendered (the render has its own copy)."""
    # The render must last long enough to tell, on any machine: the image
    # doubles in size until one lasts half a second (CI's machine rendered
    # 32x32 in 0.35 s).
    side = 32
    while True:
        scene = spar.load_scene(os.path.join(repo, SCENE))
        ticks = []
        stop = threading.Event()

        def tick():
            while not stop.is_set():
                ticks.append(time.monotonic())
                if len(ticks) == 20:
                    scene.seed = 99
                time.sleep(0.01)

        t = threading.Thread(target=tick)
        start = time.monotonic()
        t.start()
        r = scene.render(mode="stokes", resolution=(side, side), samples=1)
        end = time.monotonic()
        stop.set()
        t.join()
        if end - start > 0.5 or side >= 512:
            break
        side *= 2
    assert end - start > 0.5, f"a {side}x{side} render was too short to tell"
    during = [x for x in ticks if start + 0.1 < x < end - 0.1]
    # At 100 ticks a second, a render of half a second or more leaves
    # dozens; a held GIL would leave none.
    assert len(during) > 10, (len(during), end - start)
    assert scene.seed == 99
    assert "seed=0 " in r.metadata["spar:settings"]
