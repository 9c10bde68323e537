"""Run by test_mpi.py, under mpirun or alone: a world stepped in two halves,
with a checkpoint between them, or resumed from one. Every process writes
what it measures; process 0 writes the files.

    python mpi_world.py OUT COLLISIONS BOUNDARY GRAVITY_Y DOMAINS [RESUME]

DOMAINS: "none" for one process without a communicator, "auto", or "NXxNY".
"""
import json
import sys

import carom

STEPS = 150  # each half


def main(out, collisions, boundary, gravity, domains, resume=None):
    comm, split = None, None
    if domains != "none":
        from mpi4py import MPI
        comm = MPI.COMM_WORLD
        if domains != "auto":
            split = tuple(int(d) for d in domains.split("x"))
    rank = 0 if comm is None else comm.Get_rank()
    if resume is None:
        world = carom.World((40.0, 30.0), boundary=boundary, dt=0.01, gravity=(0.0, float(gravity)),
                            collisions=collisions, seed=11, comm=comm, domains=split)
        world.place(600, radius=(0.25, 0.5), mass=(1.0, 3.0), speed=2.0)
        world.step(STEPS)
        if rank == 0:
            world.save_checkpoint(out + ".ckpt")
        if comm is not None:
            comm.Barrier()  # the checkpoint is whole before anyone reads it
    else:
        world = carom.World.from_checkpoint(resume, comm=comm, domains=split)
    world.step(STEPS)
    measured = {"kinetic_energy": world.kinetic_energy, "momentum": list(world.momentum),
                "collisions": world.collisions, "max_overlap": world.max_overlap,
                "positions": world.positions.tobytes().hex(), "images": world.images.tobytes().hex()}
    with open(f"{out}.rank{rank}.json", "w") as file:
        json.dump({"measured": measured, "device": world.device_name}, file)
    if rank == 0:
        carom.write_state(out + ".csv", world)


if __name__ == "__main__":
    main(*sys.argv[1:])
