"""World.step releases the GIL (other threads run meanwhile, calls on one world
take turns) and honours Ctrl-C within a long step, the world then at its start."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import carom


def long_step(collisions):
    """A world whose one step takes minutes: the events scheme at a high speed, or a
    pairwise step of thousands of substeps."""
    if collisions == "events":
        world = carom.World(box=(150, 150), collisions="events", seed=3)
        world.place(2000, speed=1e7)
    else:
        world = carom.World(box=(150, 150), collisions="pairwise", max_travel=0.001, seed=3)
        world.place(2000, speed=5e4)
    return world


@pytest.mark.parametrize("collisions", ["events", "pairwise"])
def test_sigint_from_a_timer_stops_a_long_step_within_a_second(collisions):
    world = long_step(collisions)
    start = world.positions.copy()
    fired = []

    def interrupt():
        fired.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(0.5, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            world.step(1)
        stopped = time.monotonic()
    finally:
        timer.cancel()
    assert fired and stopped - fired[0] < 1.5, "the signal was seen late, or its timer never ran"
    # The step cut short returned to its start.
    assert world.step_count == 0 and world.time == 0.0
    assert np.array_equal(world.positions, start)


def test_other_threads_run_while_a_world_steps():
    world = carom.World(box=(150, 150), collisions="pairwise", max_travel=0.001, seed=3)
    world.place(2000, speed=1e3)  # one step of a second or more
    stepping = threading.Thread(target=lambda: world.step(1))
    began = time.monotonic()
    stepping.start()
    for _ in range(10):  # this thread's own work while the other steps
        time.sleep(0.01)
    ran = time.monotonic() - began
    alive = stepping.is_alive()
    stepping.join()
    assert alive and ran < 0.5, f"this thread waited {ran:.2f} s for the step"
    assert world.step_count == 1


def test_calls_on_one_world_from_two_threads_take_turns():
    world = carom.World(box=(60, 60), boundary="periodic", seed=11)
    world.place(400, radius=(0.5, 1.0), speed=1.5)
    alone = world.copy()
    threads = [threading.Thread(target=lambda: world.step(500)) for _ in range(2)]
    for thread in threads:
        thread.start()
    counts = set()
    while any(thread.is_alive() for thread in threads):
        counts.add(world.step_count)  # between steps only: 0, 500 or 1000
    for thread in threads:
        thread.join()
    assert counts <= {0, 500, 1000}
    alone.step(1000)
    assert world.step_count == 1000
    assert np.array_equal(world.positions, alone.positions)
